"""A structured, read-only picture of an agent's mind (what a mind inspector shows).

:func:`mind_state` reads the belief base, the events and the intentions of an agent and returns
plain records (dataclasses of strings, numbers and lists) that serialise to JSON as they are;
:func:`mind_text` gives the same mind as Jason text (the ``Mind`` service). Both take the agent's
state lock and never change the agent. An inspector that reads one agent again and again (the
node's ``mind_state`` topic) keeps a :class:`MindReader`: it remembers what the last snapshot
formatted, and it can decline to wait for a busy agent. The agent itself keeps nothing of its
inspectors. The records hold only strings, numbers, lists, dicts and records, so
``json.dumps(state, default=vars)`` serialises them (see :func:`to_json`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from enum import StrEnum
from typing import TYPE_CHECKING

from .intentions import Event, IntendedMeans, Intention, Suspension
from .plans import ADD, K_LOOP, Deed, body_deeds, deed_str
from .terms import Literal, Rule, term_str

if TYPE_CHECKING:
    from .agent import Agent


class Step(StrEnum):
    """Where a formula of a plan body stands in an intended means."""

    DONE = "done"
    CURRENT = "current"
    TODO = "todo"


@dataclass
class BeliefView:
    """One belief: its functor/arity group, its text without annotations, the rest apart."""

    group: str                 # "robot/4", "~ok/0"
    text: str                  # robot(faulty,10,1.2,90)
    annots: list[str]          # annotations other than source(...)
    sources: list[str]         # percept, self, helper...


@dataclass
class BodyStep:
    """One formula of a plan body and whether it ran, runs now, or is still to run."""

    text: str
    step: Step


@dataclass
class MeansView:
    """A plan instance on an intention stack (an intended means)."""

    trigger: str
    plan: str                  # "@label +!g : context" (the head as written)
    where: str                 # "faulty.asl:12"
    body: list[BodyStep]
    doing: str | None          # the formula being (or last) executed, inside blocks too
    unifier: dict[str, str]


@dataclass
class IntentionView:
    """An intention: its stack of plan instances, the top first."""

    id: int
    suspended: str | None      # None when runnable, else what it waits for ("action 3", ...)
    means: list[MeansView]


@dataclass
class EventView:
    trigger: str
    intention: int | None      # the intention it belongs to; None for an external event


@dataclass
class MindState:
    """Everything an inspector shows of one agent's mind, at one moment."""

    beliefs: list[BeliefView] = field(default_factory=list)
    rules: list[str] = field(default_factory=list)
    events: list[EventView] = field(default_factory=list)
    desires: list[str] = field(default_factory=list)
    intentions: list[IntentionView] = field(default_factory=list)


class MindReader:
    """Snapshots of one agent's mind for an inspector that reads it again and again.

    It keeps the views of the last snapshot's beliefs (a belief is an immutable literal: equal
    beliefs, equal views), so a snapshot formats only the beliefs new since the last one; only
    the last snapshot's views are kept.
    """

    def __init__(self, agent: Agent) -> None:
        self.agent = agent
        self.beliefs: dict[Literal, BeliefView] = {}

    def snapshot(self, blocking: bool = True) -> MindState | None:
        """The mind now; None when not `blocking` and a reasoning cycle of another thread holds
        the agent right now."""
        lock = self.agent.runner.state_lock
        if not lock.acquire(blocking=blocking):
            return None
        try:
            return self._read()
        finally:
            lock.release()

    def _read(self) -> MindState:
        """Read the mind (the agent's state lock held)."""
        agent = self.agent
        state = MindState()
        previous = self.beliefs
        views: dict[Literal, BeliefView] = {}
        for b in agent.bb:
            if isinstance(b, Rule):
                state.rules.append(str(b))
            elif isinstance(b, Literal):
                view = views.get(b) or previous.get(b) or _new_belief_view(b)
                views[b] = view
                state.beliefs.append(view)
        self.beliefs = views
        held = [ev for _, ev in agent.circ.pending_events]
        for ev in [*agent.circ.events, *held]:
            state.events.append(_event(ev))
            if ev.trigger.is_goal:
                state.desires.append(str(ev.trigger))
        for i in agent.circ.all_intentions():
            state.intentions.append(IntentionView(
                id=i.id, suspended=suspension_text(agent, i) or None,
                means=[_means(im) for im in reversed(i.ims)]))
            state.desires.extend(str(im.trigger) for im in i.ims
                                 if im.trigger.is_goal and im.trigger.op == ADD)
        return state


def suspension_text(agent: Agent, i: Intention) -> str:
    """What ``i`` waits for, as the mind shows it (``action 3``, ``wait``...)."""
    if i.suspended is Suspension.ACTION:
        for aid, p in agent.circ.pending_actions.items():
            if p.intention is i:
                return f"action {aid}"
    return i.suspended.value if i.suspended is not None else ""


def mind_text(agent: Agent) -> dict[str, list[str]]:
    """The mental state as Jason text: beliefs, desires, intentions, pending actions (it waits
    for the agent's state lock)."""
    with agent.runner.state_lock:
        return _mind_text(agent)


def _mind_text(agent: Agent) -> dict[str, list[str]]:
    beliefs = [term_str(b) if isinstance(b, Literal) else str(b) for b in agent.bb]
    desires = [str(ev.trigger) for ev in agent.circ.events if ev.trigger.is_goal]
    intentions = []
    for i in agent.circ.all_intentions():
        tops = " / ".join(str(im.trigger) for im in reversed(i.ims))
        state = f" (suspended: {suspension_text(agent, i)})" if i.suspended else ""
        intentions.append(f"intention {i.id}: {tops}{state}")
        desires.extend(str(im.trigger) for im in i.ims if im.trigger.is_goal and im.trigger.op == ADD)
    pending = [f"{aid}: {term_str(p.action)}" for aid, p in agent.circ.pending_actions.items()]
    return {"beliefs": beliefs, "desires": desires, "intentions": intentions,
            "pending_actions": pending}


def mind_state(agent: Agent) -> MindState:
    """A structured snapshot of `agent`'s mind (it waits for the agent's state lock)."""
    state = MindReader(agent).snapshot()
    assert state is not None        # a blocking snapshot always reads
    return state


def to_json(value: object) -> str:
    """Compact JSON of records of this module (and of dicts and lists holding them)."""
    import json  # here: an agent that is never inspected does not pay its import at start

    return json.dumps(value, default=vars, separators=(",", ":"))


def _new_belief_view(b: Literal) -> BeliefView:
    sources, annots = [], []
    for a in b.annots:
        if isinstance(a, Literal) and a.functor == "source" and len(a.args) == 1:
            sources.append(term_str(a.args[0]))
        else:
            annots.append(term_str(a))
    return BeliefView(group=f"{'~' if b.neg else ''}{b.functor}/{len(b.args)}",
                      text=term_str(b.no_annots()), annots=annots, sources=sources)


def _event(ev: Event) -> EventView:
    return EventView(trigger=str(ev.trigger),
                     intention=ev.intention.id if ev.intention is not None else None)


def _means(im: IntendedMeans) -> MeansView:
    plan = im.plan
    head = plan.as_text().split(" <- ", 1)[0]
    src = plan.src.removeprefix("file:")
    where = f"{os.path.basename(src) or src}:{plan.line}" if src else f"line {plan.line}"
    return MeansView(trigger=str(im.trigger), plan=head, where=where, body=_body_steps(im),
                     doing=deed_str(im.current) if im.current is not None else None,
                     unifier={k: term_str(v) for k, v in im.u.items()})


def _body_steps(im: IntendedMeans) -> list[BodyStep]:
    """The plan's body, each top-level formula marked done, current or still to run.

    The current formula is the one being executed or last executed (``im.current``), or the
    if/while/for block that holds it; before the first one it is none of them.
    """
    body = im.plan.body
    deed = im.current
    if deed is not None and deed.kind == K_LOOP:
        deed = deed.extra.loop        # the next round of a while/for: the loop itself
    current = _top_level_index(body, deed) if deed is not None else None
    if current is None:               # nothing run yet: what left the stack is done
        remaining = {id(d) for d in im.stack}
        current_left = next((k for k, d in enumerate(body) if id(d) in remaining), len(body))
        return [BodyStep(deed_str(d), Step.DONE if k < current_left else Step.TODO)
                for k, d in enumerate(body)]
    return [BodyStep(deed_str(d), Step.DONE if k < current else
                     Step.CURRENT if k == current else Step.TODO)
            for k, d in enumerate(body)]


def _top_level_index(body: tuple, deed: Deed) -> int | None:
    """Index of the top-level formula of `body` that is `deed` or holds it in a block."""
    for k, d in enumerate(body):
        if d is deed or any(inner is deed for inner in body_deeds((d,))):
            return k
    return None
