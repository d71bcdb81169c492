"""The internal-action registry (:mod:`rason.asl.ia`): the interpreter does not import its
library, and the registry checks each action's declared arity with Jason's message."""

from __future__ import annotations

import ast
import os
import subprocess
import sys

from asl_helpers import lines, run_source

import rason.asl
from rason.asl import internal_action
from rason.asl.ia import IA_REGISTRY, lookup

ERR = '-!s[error(E), error_msg(M)] <- .print(E, " | ", M).'


def run(body: str) -> list[str]:
    """Run ``+!s <- body.`` with a failure plan that prints the error and its message."""
    return lines(run_source(f"!s.\n+!s <- {body}.\n{ERR}"))


def modules_after(statement: str) -> list[str]:
    """The ``rason.asl`` modules a fresh Python process holds after ``statement``."""
    done = subprocess.run([sys.executable, "-c", statement + "\nimport sys\n"
                           "print(' '.join(m for m in sys.modules if m.startswith('rason.asl')))"],
                          capture_output=True, text=True, timeout=60, check=True)
    return done.stdout.split()


def test_the_unifier_and_the_interpreter_load_without_the_library() -> None:
    for statement in ("import rason.asl.unify", "import rason.asl.logic",
                      "from rason.asl import Agent, internal_action"):
        loaded = modules_after(statement)
        assert "rason.asl.unify" in loaded
        assert not [m for m in loaded if m.startswith("rason.asl.stdlib")], (statement, loaded)
    # the library comes with the first look-up of an action: its core module for ``.print``,
    # the rest for a name the core module does not register
    printing = modules_after("from rason.asl.ia import lookup\nassert lookup('.print')")
    assert "rason.asl.stdlib.core" in printing and "rason.asl.stdlib.lists" not in printing
    listing = modules_after("from rason.asl.ia import lookup\nassert lookup('.length')")
    assert {"rason.asl.stdlib.core", "rason.asl.stdlib.lists", "rason.asl.stdlib.goals"} <= set(listing)
    # a user's action replaces the library's of its name, whichever module of it was loaded
    for first in ("", "lookup('.print')\n"):
        modules_after("from rason.asl.ia import internal_action, lookup\n" + first +
                      "@internal_action('.length')\ndef mine(ctx, args): return True\n"
                      "assert lookup('.length').fn is mine and lookup('.print') is not None")
    # threads looking up at once each wait for the library the first one loads
    modules_after("import threading\nfrom rason.asl.ia import lookup\nfound = []\n"
                  "ts = [threading.Thread(target=lambda n=n: found.append(lookup(n)))\n"
                  "      for n in ('.print', '.length', '.print', '.member') * 4]\n"
                  "[t.start() for t in ts]\n[t.join() for t in ts]\n"
                  "assert len(found) == 16 and None not in found, found")
    # no user's module to load: nothing of the library either
    assert "rason.asl.stdlib.core" not in modules_after("from rason.asl.ia import load_modules\n"
                                                        "assert load_modules(['']) == []")


def _module_level_imports(package: str) -> dict[str, set[str]]:
    """Each module of ``package`` (a folder) -> the modules of it that must have run when it
    is imported: ``from .x import y`` needs x; ``from . import y`` needs module y, or the
    package itself when y is a name it defines. Imports under ``if TYPE_CHECKING:`` and inside
    functions are not run at import time; a package's modules need not their package (it is
    being imported when they are)."""
    wanted: dict[str, set[tuple[str, tuple[str, ...]]]] = {}   # module -> (name, its package)
    for folder, _dirs, files in os.walk(package):
        for name in files:
            if not name.endswith(".py"):
                continue
            parts = os.path.relpath(os.path.join(folder, name), package)[:-3].split(os.sep)
            is_package = parts[-1] == "__init__"
            module = tuple(parts[:-1] if is_package else parts)
            here = module if is_package else module[:-1]
            with open(os.path.join(folder, name), encoding="utf-8") as f:
                tree = ast.parse(f.read())
            needs = set()
            for node in tree.body:
                if isinstance(node, ast.ImportFrom) and node.level:
                    base = here[:len(here) - node.level + 1]
                    if node.module is not None:
                        needs.add((".".join((*base, *node.module.split("."))), ()))
                    else:
                        needs.update((".".join((*base, alias.name)), base) for alias in node.names)
            wanted[".".join(module)] = needs
    graph: dict[str, set[str]] = {}
    for m, needs in wanted.items():
        deps = {n if n in wanted else ".".join(package_of) for n, package_of in needs}
        graph[m] = {d for d in deps if d in wanted and d != m}
    return graph


def test_the_interpreters_modules_form_no_import_circle() -> None:
    graph = _module_level_imports(os.path.dirname(rason.asl.__file__))
    graph[""] = set()   # the package's own __init__ is being imported when any of them is
    assert "ia" in graph["logic"] and "stdlib.strings" in graph["stdlib.lists"]
    for start in graph:
        seen, todo = set(), list(graph[start])
        while todo:
            m = todo.pop()
            assert m != start, f"rason.asl.{start} imports itself through rason.asl.{m}"
            if m not in seen:
                seen.add(m)
                todo.extend(graph[m])


def test_wrong_arity_fails_with_jasons_message() -> None:
    # JasonException.createWrongArgumentNb, as before the arity moved to the registration
    assert run(".length([1], 2, 3)") == [
        "wrong_arguments | The internal action 'length' has not received the required number of "
        "argument(s). 2 arguments are expected."]
    assert run(".my_name") == [
        "wrong_arguments | The internal action 'my_name' has not received the required number of "
        "argument(s). One argument is expected."]
    assert run(".range(X, 1)") == [
        "wrong_arguments | The internal action 'range' has not received the required number of "
        "argument(s). From 3 to 4 arguments are expected."]
    # the action's body does not run: its own checks would give another message
    assert run('.fork(and)') == [
        "wrong_arguments | The internal action 'fork' has not received the required number of "
        "argument(s). 2 arguments are expected."]


def test_a_users_action_declares_its_arity_once() -> None:
    @internal_action("test_ia_registry.pair", arity=(1, 2))
    def pair(ctx, args):
        return ctx.unify(args[-1], float(len(args)))

    try:
        assert run("test_ia_registry.pair(N); .print(N); test_ia_registry.pair(a, M); .print(M)") \
            == ["1", "2"]
        assert run("test_ia_registry.pair(a, b, c)") == [
            "wrong_arguments | The internal action 'pair' has not received the required number "
            "of argument(s). From 1 to 2 arguments are expected."]
        assert lookup("test_ia_registry.pair").fn is pair
    finally:
        del IA_REGISTRY["test_ia_registry.pair"]
