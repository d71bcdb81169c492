"""Internal actions (Jason's ``jason.stdlib``), one function each, registered by name.

An internal action is ``fn(ctx: IAContext, args: list) -> result`` where ``args`` are already
resolved with the current substitution and ``result`` is:

* ``True`` / ``False`` (bindings made through ``ctx.unify`` are kept on ``True``);
* an iterator of substitutions (dicts), for actions that backtrack (``.member``);
* :data:`SUSPEND` when the action suspended the intention itself (``.wait``, askOne).

Adding one is a single decorated function::

    @internal_action(".my_ia")
    def my_ia(ctx, args):
        return ctx.unify(args[0], 42.0)

A user's own internal actions take a dotted name without the leading dot, as in Jason
(``my.act``): put them in a Python module (``from rason.asl import internal_action``) and
load it with :func:`load_modules` (``python -m rason.asl run --internal-actions MODULE``,
``rosrun rason agent ... _internal_actions:=[MODULE]``). Numbers arrive as ``float``, atoms
and structures as ``Literal``, strings as ``str``; ``ctx.unify(a, b)`` binds, ``ctx.ag`` is
the agent.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable

from ..terms import is_internal_action

IA_REGISTRY: dict[str, Callable] = {}

SUSPEND = object()


class IAError(Exception):
    """An internal action was misused; the intention fails with ``error(kind)``."""

    def __init__(self, message: str, kind: str = "ia_failed", annots: list | None = None) -> None:
        super().__init__(message)
        self.kind = kind
        self.message = message
        self.annots = annots or []


class FailGoal(Exception):
    """Raised by ``.fail(...)``: fail the intention with the given annotations."""

    def __init__(self, annots: list) -> None:
        super().__init__("fail")
        self.annots = annots


def internal_action(*names: str) -> Callable:
    """Register an internal action under one or more names (``".print"``, ``"my.act"``)."""
    for n in names:
        if not is_internal_action(n):
            raise ValueError(f"internal action name {n!r} has no dot: use '.{n}' or 'lib.{n}'")

    def deco(fn: Callable) -> Callable:
        for n in names:
            IA_REGISTRY[n] = fn
        return fn

    return deco


class ModuleLoadError(Exception):
    """A module of internal actions could not be imported (the message says why)."""


def load_modules(modules: Iterable[str]) -> list[str]:
    """Import the named Python modules (``my_package.my_actions``) so that their
    ``@internal_action`` functions register; the names they added, sorted."""
    before = set(IA_REGISTRY)
    for name in modules:
        name = name.strip()
        if not name:
            continue
        try:
            importlib.import_module(name)
        except Exception as err:
            raise ModuleLoadError(f"cannot load internal actions from module {name!r}: "
                                  f"{type(err).__name__}: {err}") from err
    return sorted(set(IA_REGISTRY) - before)


def arg_count(args: list, *allowed: int) -> None:
    """Jason's ``checkArguments``: fail with ``wrong_arguments`` unless len(args) is allowed."""
    if len(args) not in allowed:
        lo, hi = min(allowed), max(allowed)
        if lo == hi:
            need = " One argument is expected." if lo == 1 else f" {lo} arguments are expected."
        else:
            need = f" From {lo} to {hi} arguments are expected."
        raise IAError("The internal action '{ia}' has not received the required number of "
                      "argument(s)." + need, "wrong_arguments")


def wrong_arg(reason: str) -> IAError:
    """Jason's ``createWrongArgument``: an ``error(wrong_arguments)`` with its message."""
    return IAError("Wrong argument for internal action '{ia}': " + reason, "wrong_arguments")


from . import comm, containers, control, core, extra, goals, lists, strings  # noqa: E402,F401  (registration)
