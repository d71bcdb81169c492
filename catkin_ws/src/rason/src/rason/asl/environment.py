"""Environments written in Python for ``.mas2j`` projects (Jason's ``Environment`` class).

A project's ``environment: pkg.mod.Cls(3, "x")`` names a subclass of :class:`Environment`: the
module ``pkg.mod`` is imported with the project's folder first on ``sys.path``, ``Cls`` is built
without arguments, then ``init(["3", "x"])`` gets the project's arguments as strings (quotes
removed), as Jason's ``init(String[] args)`` does. Each external action of an agent calls
``execute_action(agent_name, action)``; its result is the action's success. Percepts are global
(every agent sees them) or an agent's own; an agent perceives the global ones then its own when
they changed since it last looked. ``stop()`` runs when the MAS ends.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import TYPE_CHECKING

from .arch import Clock
from .classdef import ClassLoadError, import_dotted, split_class_def
from .parser import parse_literal
from .runtime import LocalArch
from .terms import Literal

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent
    from .runtime import LocalMas

PerceptLike = Literal | str


class EnvironmentLoadError(ClassLoadError):
    """The project's environment class cannot be found, built or initialised."""


def _as_literal(p: PerceptLike) -> Literal:
    return parse_literal(p) if isinstance(p, str) else p


class Environment:
    """Base of a project's environment (Jason's ``jason.environment.Environment``).

    Override :meth:`init`, :meth:`execute_action` and :meth:`stop`; change what agents perceive
    with :meth:`add_percept`, :meth:`remove_percept` and :meth:`clear_percepts` (``agent=None``:
    the global percepts, else that agent's own). Percepts are literals or their source text.
    """

    def __init__(self) -> None:
        self._lock = threading.RLock()
        self._global: list[Literal] = []
        self._own: dict[str, list[Literal]] = {}
        #: agents whose percepts did not change since they last perceived
        self._up_to_date: set[str] = set()
        #: called with agent names (none: all) whose percepts changed: wakes them
        self._inform: Callable[[tuple[str, ...]], None] = lambda names: None
        self._console: Callable[[str, str], None] = lambda who, text: print(f"[{who}] {text}",
                                                                            flush=True)
        self._names: Callable[[], list[str]] = list

    # ------------------------------------------------------------ the contract
    def init(self, args: list[str]) -> None:
        """Called once before the agents run, with the project's arguments as strings."""

    def execute_action(self, agent: str, action: Literal) -> bool:
        """Do ``action`` for ``agent``; True if it succeeded (Jason's ``executeAction``)."""
        return False

    def stop(self) -> None:
        """Called once when the MAS ends."""

    # ------------------------------------------------------------ percepts
    def add_percept(self, *percepts: PerceptLike, agent: str | None = None) -> None:
        """Add percepts, global or ``agent``'s own (one copy of each)."""
        with self._lock:
            target = self._target(agent)
            for p in map(_as_literal, percepts):
                if p not in target:
                    target.append(p)
            self._changed(agent)

    def remove_percept(self, *percepts: PerceptLike, agent: str | None = None) -> bool:
        """Remove percepts, global or ``agent``'s own; True if one was there."""
        with self._lock:
            target = self._target(agent)
            found = False
            for p in map(_as_literal, percepts):
                if p in target:
                    target.remove(p)
                    found = True
            if found:
                self._changed(agent)
            return found

    def clear_percepts(self, agent: str | None = None) -> None:
        """Remove every global percept (``agent=None``), or every percept of ``agent``'s own."""
        with self._lock:
            target = self._target(agent)
            if target:
                target.clear()
                self._changed(agent)

    def contains_percept(self, percept: PerceptLike, agent: str | None = None) -> bool:
        with self._lock:
            return _as_literal(percept) in self._target(agent)

    def percepts(self, agent: str) -> list[Literal] | None:
        """What ``agent`` perceives (global percepts, then its own), or None when that did not
        change since its last call (Jason's ``getPercepts``)."""
        with self._lock:
            if agent in self._up_to_date:
                return None
            self._up_to_date.add(agent)
            return [*self._global, *self._own.get(agent, ())]

    # ------------------------------------------------------------ the MAS
    def inform_agents_changed(self, *agents: str) -> None:
        """Wake ``agents`` (none: all) to perceive (Jason's ``informAgsEnvironmentChanged``)."""
        self._inform(agents)

    def agent_names(self) -> list[str]:
        return self._names()

    def log(self, text: str, who: str | None = None) -> None:
        """Print ``[who] text`` with the agents' output (``who``: this class's name), as
        Jason's console shows an environment's logger."""
        self._console(who or type(self).__name__, text)

    def _target(self, agent: str | None) -> list[Literal]:
        return self._global if agent is None else self._own.setdefault(agent, [])

    def _changed(self, agent: str | None) -> None:
        if agent is None:
            self._up_to_date.clear()
        else:
            self._up_to_date.discard(agent)


class EnvArch(LocalArch):
    """Architecture of an agent of a local MAS with an environment: it perceives and acts
    on the project's :class:`Environment`."""

    def __init__(self, mas: LocalMas, clock: Clock, env: Environment, name: str) -> None:
        super().__init__(mas, clock)
        self.env = env
        self.name = name

    def perceive(self) -> list[Literal] | None:
        return self.env.percepts(self.name)

    def act(self, agent: Agent, action: Literal, action_id: int) -> None:
        try:
            ok = bool(self.env.execute_action(agent.name, action))
        except Exception as e:  # a faulty environment fails the action, not the MAS
            agent.warn(f"environment failed on {action}: {type(e).__name__}: {e}")
            ok = False
        if ok:
            agent.action_feedback(action_id, True)
        else:
            agent.action_feedback(action_id, False, "action_failed", "")


def load_environment(class_def: str, project_dir: str) -> Environment:
    """Import, build and initialise the environment ``class_def`` names (see the module doc)."""
    name, args = split_class_def(class_def)
    try:
        cls = import_dotted(name, project_dir)
    except ImportError as e:
        raise EnvironmentLoadError(f"environment '{name}': cannot import it from {project_dir}: "
                                   f"{e}") from e
    if not (isinstance(cls, type) and issubclass(cls, Environment)):
        raise EnvironmentLoadError(f"environment '{name}': not a subclass of "
                                   "rason.asl.environment.Environment")
    try:
        env = cls()
        env.init(args)
    except Exception as e:  # any fault of the user's class: a clear error
        raise EnvironmentLoadError(f"environment '{name}{tuple(args) if args else ''}': "
                                   f"initialisation failed: {type(e).__name__}: {e}") from e
    return env


__all__ = ["EnvArch", "Environment", "EnvironmentLoadError", "load_environment"]
