"""The per-agent classes of a ``.mas2j`` (``agentClass``, ``agentArchClass``, ``beliefBaseClass``)
as Python: each names a callable by its dotted path, imported from the project's folder (or
``sys.path``), with the class definition's parameters as strings (docs/agent-hooks.md).

* ``agentClass pkg.mod.fn(p1, p2)`` and ``agentArchClass ...``: ``fn(agent, "p1", "p2")`` is
  called once the agent is made, before it runs; it sets the agent's hooks
  (``agent.selection``, ``agent.belief_update``, ``agent.accept_message``). A class is such a
  callable: its instance may keep state and install its bound methods.
* ``beliefBaseClass pkg.mod.fn(p1)``: ``fn("p1")`` returns the agent's belief base (a
  :class:`.BeliefBase`, e.g. one filled from a file), made before the agent's initial beliefs.

Jason's own belief-base classes (``jason.bb.TextPersistentBB``, ``IndexedBB``, ``ChainBB``,
``DefaultBeliefBase``) map to rason's (:mod:`.jason_bb`); other names of Jason's own Java
classes (``jason.…``) are noted and ignored; any other name that does not import is a
:class:`HookLoadError` naming the project file, line and name.
"""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from .beliefs import BeliefBase
from .classdef import ClassLoadError, import_dotted, split_class_def
from .jason_bb import JasonBeliefBaseError, jason_belief_base

if TYPE_CHECKING:  # pragma: no cover
    from .mas2j import AgentSpec  # (the project reader imports lark: a lone agent does without)


class HookLoadError(ClassLoadError):
    """A class of a ``.mas2j`` agent does not import, or is not what it must be."""


#: the ``.mas2j`` keywords, by the AgentSpec field that holds each
KEYWORDS = {"agent_class": "agentClass", "arch_class": "agentArchClass", "bb_class": "beliefBaseClass"}


@dataclass
class AgentHooks:
    """What a ``.mas2j`` agent's classes give: a belief-base factory and customisers."""

    belief_base: Callable[[], BeliefBase] | None = None
    customisers: list[Callable[[Any], Any]] = field(default_factory=list)
    #: called with the agent when the run ends (TextPersistentBB writes its file)
    stoppers: list[Callable[[Any], Any]] = field(default_factory=list)
    #: the Java classes of Jason that were ignored (one note each)
    notes: list[str] = field(default_factory=list)

    def make_belief_base(self) -> BeliefBase | None:
        """The belief base the factory makes (None: the default one)."""
        return None if self.belief_base is None else self.belief_base()

    def customise(self, agent: Any) -> None:
        """Install the hooks on ``agent``."""
        for fn in self.customisers:
            fn(agent)

    def stop(self, agent: Any) -> None:
        """The run of ``agent`` ends."""
        for fn in self.stoppers:
            fn(agent)


def is_jason_class(name: str) -> bool:
    """A class of Jason's own Java code (``jason.bb.TextPersistentBB``...): nothing to load."""
    return name.startswith("jason.")


def load_hooks(spec: AgentSpec, project_path: str) -> AgentHooks:
    """The hooks of ``spec``'s classes (``project_path``: the ``.mas2j`` file, for the folder
    modules are imported from and for errors)."""
    hooks = AgentHooks()
    folder = os.path.dirname(os.path.abspath(project_path))
    for key, keyword in KEYWORDS.items():
        class_def = getattr(spec, key)
        if not class_def:
            continue
        name, params = split_class_def(class_def)
        where = f"{project_path}:{spec.line}: agent {spec.name}: {keyword} '{name}'"
        if key == "bb_class" and is_jason_class(name):
            try:
                jason_bb = jason_belief_base(name, params)
            except JasonBeliefBaseError as e:
                raise HookLoadError(f"{where}: {e}") from e
            if jason_bb is not None:
                hooks.belief_base = jason_bb.make
                hooks.customisers.append(jason_bb.load)
                hooks.stoppers.append(jason_bb.store)
                continue
        if is_jason_class(name):
            hooks.notes.append(f"agent {spec.name}: {keyword} {name} ignored (a Java class of Jason)")
            continue
        try:
            target = import_dotted(name, folder)
        except Exception as e:   # ImportError, or any fault of the module while imported
            raise HookLoadError(f"{where}: cannot import it from {folder} or sys.path: "
                                f"{type(e).__name__}: {e}") from e
        if not callable(target):
            raise HookLoadError(f"{where}: not callable")
        if key == "bb_class":
            hooks.belief_base = _belief_base_factory(target, params, where)
        else:
            hooks.customisers.append(_customiser(target, params, where))
    return hooks


def _belief_base_factory(target: Callable, params: list[str], where: str) -> Callable[[], BeliefBase]:
    def make() -> BeliefBase:
        try:
            bb = target(*params)
        except Exception as e:
            raise HookLoadError(f"{where}: failed: {type(e).__name__}: {e}") from e
        if not isinstance(bb, BeliefBase):
            raise HookLoadError(f"{where}: returned {type(bb).__name__}, not a "
                                "rason.asl.beliefs.BeliefBase")
        return bb
    return make


def _customiser(target: Callable, params: list[str], where: str) -> Callable[[Any], Any]:
    def customise(agent: Any) -> None:
        try:
            target(agent, *params)
        except Exception as e:
            raise HookLoadError(f"{where}: failed: {type(e).__name__}: {e}") from e
    return customise


__all__ = ["AgentHooks", "HookLoadError", "is_jason_class", "load_hooks"]
