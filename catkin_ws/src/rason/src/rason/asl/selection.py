"""The agent's customisation points (Jason's ``Agent.selectEvent``, ``selectOption``,
``selectIntention``, ``buf`` and ``socAcc``), set as functions instead of by subclassing:
``Agent(..., selection=Selection(option=last_option))`` or ``agent.selection.option = fn``.
docs/agent-hooks.md shows each with an example.

A function left ``None`` keeps the default (the first event, the first applicable plan in
source order, round robin over the intentions). Jason's rules for atomic intentions come
first: while an atomic intention runs, neither selection function is asked.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from .plans import Plan


class Option:
    """An applicable plan and the unifier that makes its trigger and context hold (Jason's
    ``Option``)."""

    __slots__ = ("plan", "unifier")

    def __init__(self, plan: Plan, unifier: dict) -> None:
        self.plan = plan
        self.unifier = unifier

    def __repr__(self) -> str:
        return f"Option({self.plan.label_name() or self.plan.trigger}, {self.unifier})"


class Selection:
    """The selection functions of one agent; each takes the agent and a list (in queue or
    source order) and returns one of its members, or None (nothing this cycle):

    * ``event(agent, events) -> Event | None``: which queued event to handle (SelEv);
    * ``option(agent, options) -> Option | None``: which applicable plan to intend (SelAppl);
      with it every relevant plan's context is evaluated, not only up to the first that holds;
    * ``intention(agent, intentions) -> Intention | None``: which running intention executes
      its next step (SelInt).
    """

    __slots__ = ("event", "intention", "option")

    def __init__(self, event: Callable[[Any, list], Any] | None = None,
                 option: Callable[[Any, list], Any] | None = None,
                 intention: Callable[[Any, list], Any] | None = None) -> None:
        self.event = event
        self.option = option
        self.intention = intention
