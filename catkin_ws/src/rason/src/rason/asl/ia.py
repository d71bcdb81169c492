"""Internal actions: their registry, the context they see, their errors (shared by the
interpreter and the standard library, :mod:`rason.asl.stdlib`, which it does not import).

An internal action is ``fn(ctx: IAContext, args: list) -> result`` where ``args`` are already
resolved with the current substitution and ``result`` is:

* ``True`` / ``False`` (bindings made through ``ctx.unify`` are kept on ``True``);
* an iterator of substitutions (dicts), for actions that backtrack (``.member``);
* :data:`SUSPEND` when the action suspended the intention itself (``.wait``, askOne).

Adding one is a single decorated function; ``arity`` is the number of arguments it takes (or
the least and the most, ``(2, 3)``; ``None`` for the most: no upper bound), checked before it
runs, with Jason's ``wrong_arguments`` error::

    @internal_action(".my_ia", arity=1)
    def my_ia(ctx: IAContext, args: list) -> bool:
        return ctx.unify(args[0], 42.0)

A user's own internal actions take a dotted name without the leading dot, as in Jason
(``my.act``): put them in a Python module (``from rason.asl import internal_action``) and
load it with :func:`load_modules` (``python -m rason.asl run --internal-actions MODULE``,
``rosrun rason agent ... _internal_actions:=[MODULE]``). Numbers arrive as ``float``, atoms
and structures as ``Literal``, strings as ``str``; ``ctx.unify(a, b)`` binds, ``ctx.ag`` is
the agent.

The standard library registers itself on the first look-up of an action or the first
registration of a user's (so a user's action of the same name replaces the library's), never
when the interpreter's modules are imported. A look-up imports its most used module,
``core`` (``.print`` and the like), first and the rest only for a name that
module does not register (an agent that only prints starts without them).
"""

from __future__ import annotations

import importlib
import threading
from collections.abc import Callable, Iterable, Iterator
from typing import TYPE_CHECKING, Any

from .terms import Literal, is_internal_action
from .unify import resolve, unify

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent
    from .intentions import IntendedMeans, Intention

#: what ``arity=`` takes: a number of arguments, or the least and the most (None: no most)
Arity = int | tuple[int, int | None] | None

#: returned by an internal action that suspended its intention itself
SUSPEND = object()

#: the module of the standard library, imported on first need (see :func:`load_library`)
LIBRARY = __name__.rsplit(".", 1)[0] + ".stdlib"


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


class ModuleLoadError(Exception):
    """A module of internal actions could not be imported (the message says why)."""


class InternalAction:
    """One registered action: its function and how many arguments it takes (``most`` -1: no
    upper bound; ``least`` 0 and ``most`` -1: not checked)."""

    __slots__ = ("fn", "least", "most")

    def __init__(self, fn: Callable, least: int = 0, most: int = -1) -> None:
        self.fn = fn
        self.least = least
        self.most = most

    def check_arity(self, name: str, n: int) -> None:
        """Jason's ``checkArguments``: ``error(wrong_arguments)`` unless ``n`` arguments fit."""
        if n >= self.least and (self.most < 0 or n <= self.most):
            return
        lo, hi = self.least, self.most
        if lo == hi or hi < 0:
            need = " One argument is expected." if lo == 1 else f" {lo} arguments are expected."
        else:
            need = f" From {lo} to {hi} arguments are expected."
        raise IAError(f"The internal action '{short_name(name)}' has not received the required "
                      "number of argument(s)." + need, "wrong_arguments")


#: every internal action by name (``.print``, ``my.act``)
IA_REGISTRY: dict[str, InternalAction] = {}
#: the standard library's state: 0 not loaded, 1 its core module loaded, 2 all of it loaded
_library_state: list[int] = [0]
#: held while the library loads: another thread's look-up waits for it (re-entrant: the
#: library's own registrations come back through :func:`load_library` in the loading thread)
_library_lock = threading.RLock()
#: True while the library's modules are being imported (their registrations load nothing)
_library_loading: list[bool] = [False]


def _import_library(state: int) -> None:
    """Bring the library to ``state`` (1: its core module, 2: all of it), once."""
    with _library_lock:
        if _library_state[0] >= state or _library_loading[0]:
            return
        _library_loading[0] = True
        try:
            names = ("core",) if state == 1 else importlib.import_module(LIBRARY).MODULES
            for name in names:
                importlib.import_module(f"{LIBRARY}.{name}")
            _library_state[0] = state
        finally:
            _library_loading[0] = False


def load_library() -> None:
    """Import the whole standard library (once), which registers its actions."""
    if _library_state[0] < 2:
        _import_library(2)


def lookup(name: str) -> InternalAction | None:
    """The internal action registered under ``name`` (None: there is none); the first look-up
    imports the library's core module, a name it lacks the rest of the library."""
    entry = IA_REGISTRY.get(name)
    if entry is None and _library_state[0] < 2:
        if _library_state[0] == 0:
            _import_library(1)
            entry = IA_REGISTRY.get(name)
        if entry is None:
            load_library()
            entry = IA_REGISTRY.get(name)
    return entry


def is_registered(name: str) -> bool:
    """True when ``name`` is a registered internal action."""
    return lookup(name) is not None


def _arity_bounds(arity: Arity) -> tuple[int, int]:
    if arity is None:
        return 0, -1
    if isinstance(arity, int):
        return arity, arity
    lo, hi = arity
    return lo, -1 if hi is None else hi


def internal_action(*names: str, arity: Arity = None) -> Callable:
    """Register an internal action under one or more names (``".print"``, ``"my.act"``);
    ``arity``: its number of arguments, ``(least, most)`` or ``(least, None)``; None: any."""
    for n in names:
        if not is_internal_action(n):
            raise ValueError(f"internal action name {n!r} has no dot: use '.{n}' or 'lib.{n}'")
    least, most = _arity_bounds(arity)
    load_library()   # the library first: a user's action replaces the library's of its name

    def deco(fn: Callable) -> Callable:
        for n in names:
            IA_REGISTRY[n] = InternalAction(fn, least, most)
        return fn

    return deco


def load_modules(modules: Iterable[str]) -> list[str]:
    """Import the named Python modules (``my_package.my_actions``) so that their
    ``@internal_action`` functions register; the names they added, sorted."""
    names = [name.strip() for name in modules if name.strip()]
    if not names:
        return []   # the library loads on its first look-up
    load_library()
    before = set(IA_REGISTRY)
    for name in names:
        try:
            importlib.import_module(name)
        except Exception as err:
            raise ModuleLoadError(f"cannot load internal actions from module {name!r}: "
                                  f"{type(err).__name__}: {err}") from err
    return sorted(set(IA_REGISTRY) - before)


def short_name(name: str) -> str:
    """How Jason names an action in its messages: by its class name (``sort`` for ``.sort``)."""
    return name.rsplit(".", 1)[-1]


def wrong_arg(reason: str) -> IAError:
    """Jason's ``createWrongArgument``: an ``error(wrong_arguments)`` with its message."""
    return IAError("Wrong argument for internal action '{ia}': " + reason, "wrong_arguments")


class IAContext:
    """What an internal action sees: agent, current substitution and (in a body) intention."""

    __slots__ = ("ag", "deed", "im", "intention", "s")

    def __init__(self, ag: Agent, s: dict, intention: Intention | None = None,
                 im: IntendedMeans | None = None, deed: Any = None) -> None:
        self.ag = ag
        self.s = s
        self.intention = intention
        self.im = im
        self.deed = deed

    def unify(self, a: Any, b: Any) -> bool:
        """Unify in the context's substitution (undone on failure)."""
        s2 = dict(self.s)
        if unify(a, b, s2, self.ag):
            self.s = s2
            return True
        return False

    def solve(self, f: Any, s: dict | None = None) -> Iterator[dict]:
        """Every substitution under which the formula ``f`` follows from the agent's state."""
        return self.ag.solve(f, self.s if s is None else s, self.intention)

    def query_beliefs(self, lit: Literal) -> Iterator[dict]:
        """Every substitution under which ``lit`` matches a belief (facts and rules), without
        the rest of :meth:`solve` (no internal actions, no arithmetic)."""
        return self.ag.query_beliefs(lit, self.s)


def call_ia(ctx: IAContext, lit: Literal) -> Any:
    """Run the internal action ``lit`` (arguments resolved with the context's substitution).

    An unknown ``.name`` is, in Jason, only a parser warning: the literal stays a plain one and
    runs as an environment action, which fails with ``error(action_failed)``.
    """
    entry = IA_REGISTRY.get(lit.functor)
    if entry is None:
        entry = lookup(lit.functor)
        if entry is None:
            raise IAError(f"unknown internal action {lit.functor}", "action_failed")
    s = ctx.s
    args = [resolve(a, s, ctx.ag) for a in lit.args]
    entry.check_arity(lit.functor, len(args))
    try:
        return entry.fn(ctx, args)
    except IAError as e:
        if "{ia}" in e.message:   # Jason names the action by its class name (``sort``)
            e.message = e.message.replace("{ia}", short_name(lit.functor))
        raise
