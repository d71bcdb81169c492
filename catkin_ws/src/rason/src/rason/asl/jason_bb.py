"""Jason's own belief-base classes, which a ``.mas2j`` names with ``beliefBaseClass``, as
rason's (a local run: ``python -m rason.asl run``; see :mod:`.hooks`):

* ``jason.bb.DefaultBeliefBase``: rason's :class:`.BeliefBase`;
* ``jason.bb.IndexedBB("p(key,_)", ...)``: its patterns are checked, and then it changes
  nothing, as in Jason 3.3, where the agent adds beliefs through a method IndexedBB does not
  override (``+p(1,b)`` keeps ``p(1,a)``, though the class means to replace it);
* ``jason.bb.TextPersistentBB``: the beliefs are kept in ``AGENT.bb`` (in the folder the run
  starts in) between runs: read, as initial beliefs, before the agent runs, and written, in
  Jason's format, when the run ends (not the rules, the percepts or the ``kqml`` namespace);
* ``jason.bb.ChainBB(C1, C2, ...)``: each class of the chain applies.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

from .beliefs import BeliefBase
from .classdef import split_class_def
from .parser import parse_literal, parse_source
from .terms import Literal, Var, term_str

#: the file of an agent's beliefs kept by ``TextPersistentBB``: the agent's name and this
PERSISTENT_SUFFIX = ".bb"
#: the first line Jason's ``TextPersistentBB`` writes (then a blank line and the beliefs)
PERSISTENT_HEADER = "// BB stored by TextPersistentBB for agent '{agent}'"


class JasonBeliefBaseError(ValueError):
    """A parameter of one of Jason's belief-base classes is not what the class takes."""


@dataclass
class JasonBeliefBase:
    """What a chain of Jason's belief-base classes asks of one agent's belief base."""

    #: IndexedBB's keys: (functor, arity, negation) -> positions of the key arguments (kept,
    #: unused: see the module's text)
    unique_keys: dict[tuple, tuple[int, ...]] = field(default_factory=dict)
    #: TextPersistentBB: the beliefs live in ``AGENT.bb`` between runs
    persistent: bool = False

    def make(self) -> BeliefBase:
        """A new belief base."""
        return BeliefBase()

    def load(self, agent: Any) -> None:
        """TextPersistentBB's start: the beliefs of ``AGENT.bb``, if any, as initial ones."""
        if not self.persistent:
            return
        path = persistent_file(agent.name)
        if not os.path.isfile(path):
            return
        with open(path, encoding="utf-8") as f:
            source = parse_source(f.read(), path)
        for b in source.beliefs:
            if isinstance(b, Literal):
                agent.add_belief(b if b.has_source() else b.with_self_source(), front=False)

    def store(self, agent: Any) -> None:
        """TextPersistentBB's stop: write the agent's beliefs to ``AGENT.bb``."""
        if not self.persistent:
            return
        with open(persistent_file(agent.name), "w", encoding="utf-8") as f:
            f.write(stored_beliefs(agent.name, agent.bb))


def persistent_file(agent_name: str) -> str:
    """Where TextPersistentBB keeps an agent's beliefs (relative to the current folder)."""
    return agent_name + PERSISTENT_SUFFIX


def stored_beliefs(agent_name: str, bb: BeliefBase) -> str:
    """The text of ``AGENT.bb``, as Jason's TextPersistentBB writes it."""
    lines = [PERSISTENT_HEADER.format(agent=agent_name), ""]
    for b in bb.beliefs():
        if b.functor.startswith("kqml::") or _is_percept(b):
            continue
        lines.append(term_str(b) + ".")
    return "\n".join(lines) + "\n"


def _is_percept(b: Literal) -> bool:
    return any(isinstance(a, Literal) and a.functor == "source" and a.args
               and isinstance(a.args[0], Literal) and a.args[0].functor == "percept"
               for a in b.annots)


def jason_belief_base(name: str, params: list[str]) -> JasonBeliefBase | None:
    """rason's equivalent of Jason's belief-base class ``name`` with ``params`` (a chain's
    parameters are class definitions); None when it has none (JDBC, ...)."""
    made = JasonBeliefBase()
    return made if _apply(made, name, params) else None


def _apply(made: JasonBeliefBase, name: str, params: list[str]) -> bool:
    if name == "jason.bb.DefaultBeliefBase":
        return True
    if name == "jason.bb.TextPersistentBB":
        made.persistent = True
        return True
    if name == "jason.bb.IndexedBB":
        for pattern in params:
            made.unique_keys.update([index_pattern(pattern)])
        return True
    if name == "jason.bb.ChainBB":
        return all(_apply(made, *split_class_def(p)) for p in params)
    return False


def index_pattern(text: str) -> tuple[tuple, tuple[int, ...]]:
    """``"student(key,_)"`` -> ((functor, arity, negation), positions of the arguments that
    are not variables, the key)."""
    try:
        lit = parse_literal(text.strip().strip('"'))
    except Exception as e:
        raise JasonBeliefBaseError(f"IndexedBB: {text!r} is not a literal: {e}") from e
    key = (lit.functor, len(lit.args), lit.neg)
    return key, tuple(k for k, a in enumerate(lit.args) if not isinstance(a, Var))


__all__ = ["JasonBeliefBase", "JasonBeliefBaseError", "index_pattern", "jason_belief_base",
           "persistent_file", "stored_beliefs"]
