"""Goal operations of an agent: drop, succeed, fail, suspend and resume goals (the internal
actions of Jason's ``jason.stdlib`` that change intentions), goal conditions and hard deadlines."""

from __future__ import annotations

from collections import deque
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from . import reasoning
from .intentions import (
    Event,
    Intention,
    PendingEvent,
    Suspension,
    TimerKind,
    event_has_goal,
    has_goal,
)
from .plans import ACHIEVE, ADD, DEL, Trigger
from .terms import Literal, java_map_order
from .unify import resolve, unify

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent

#: goal-state reasons of .suspend / .resume (as Jason's)
_SUSPEND_IA = Literal("suspend_ia")
_RESUME_IA = Literal("resume_ia")
#: the annotations of a goal failed by its hard_deadline (Jason's basic error annotations)
_DEADLINE_REACHED = (Literal("error", (Literal("deadline_reached"),)), Literal("error_msg", ("",)))


class GoalOps:
    """The goal operations of the agent ``ag`` on its circumstance."""

    def __init__(self, ag: Agent) -> None:
        self.ag = ag

    def _goal_positions(self, pattern: Any, s: dict) -> Iterator[tuple[Intention, int]]:
        """Each intention with an intended ``+!G`` the pattern unifies with, and the index of
        the topmost such means."""
        for i in self.ag.circ.all_intentions():
            for idx in range(len(i.ims) - 1, -1, -1):
                t = i.ims[idx].trigger
                if t.op == ADD and t.type == ACHIEVE and unify(pattern, t.literal, dict(s), self.ag):
                    yield i, idx
                    break

    def _goal_events(self, pattern: Any, s: dict) -> list[Event]:
        """The queued ``+!G`` events (goals not intended yet) the pattern unifies with."""
        return [ev for ev in self.ag.circ.events if ev.trigger.op == ADD and ev.trigger.type == ACHIEVE
                and unify(pattern, ev.trigger.literal, dict(s))]

    def drop_goal(self, pattern: Any, s: dict, drop_events: bool) -> None:
        """``.drop_desire`` / ``.drop_intention``: the intentions pursuing G go (with
        ``drop_events``, the queued ``+!G`` events too)."""
        c = self.ag.circ
        for i, _ in list(self._goal_positions(pattern, s)):
            c.remove_intention(i)
        if drop_events:
            def hit(ev: Event) -> bool:
                return (ev.trigger.op == ADD and ev.trigger.type == ACHIEVE
                        and unify(pattern, ev.trigger.literal, dict(s), self.ag))
            c.events = deque(ev for ev in c.events if not hit(ev))
            if c.pending_events:
                c.pending_events = [p for p in c.pending_events if not hit(p.event)]

    def drop_all(self, events: bool, keep: Intention | None = None) -> None:
        """``.drop_all_intentions`` (events=False: only events of intentions go) or
        ``.drop_all_desires`` (every event goes). As in Jason, ``keep`` (the intention running
        the action: it is not in the queue of intentions at that moment) carries on."""
        c = self.ag.circ
        for i in list(c.all_intentions()):
            if i is not keep:
                c.remove_intention(i)
        if events:
            c.events.clear()
            c.pending_events.clear()
        else:
            kept = [ev for ev in c.events if ev.intention is None or ev.intention is keep]
            c.events.clear()
            c.events.extend(kept)

    def succeed_goal(self, pattern: Any, s: dict) -> None:
        """``.succeed_goal(G)``: each goal G is achieved, done or not."""
        ag = self.ag
        c = ag.circ
        for ev in self._goal_events(pattern, s):
            # jason.stdlib.succeed_goal on an event: it goes, as an achieved goal
            c.events.remove(ev)
            if ag.pl.goal_state_plans:
                c.goal_state(ev.trigger, "achieved")
                c.goal_state(ev.trigger, "finished")
            i = ev.intention
            if i is not None:
                top = i.top()
                if top is not None and top.stack:
                    top.stack.pop()
                i.suspended = None
                reasoning.clr_int(ag, i)
                if i.ims and not i.waits():
                    c.running.append(i)
        for i, idx in list(self._goal_positions(pattern, s)):
            self.succeed_at(i, idx)

    def succeed_at(self, i: Intention, idx: int) -> None:
        """The goal of ``i``'s ``idx``-th means is achieved: that means and those above go,
        the caller goes on after the deed that posted the goal."""
        ag = self.ag
        c = ag.circ
        if i.branch_of is not None:
            c.remove_intention(i)   # a branch of the intention (Jason: dropped, no events)
            return
        was_current = i is c.current
        if ag.pl.goal_state_plans and i.ims[idx].trigger.is_goal:
            c.goal_state(i.ims[idx].trigger, "achieved")
            c.goal_state(i.ims[idx].trigger, "finished")
        c.detach(i)
        i.truncate(idx)
        if not i.ims:
            i.dropped = True
            return
        caller = i.ims[-1]
        if caller.stack:
            caller.stack.pop()
        if not was_current:
            reasoning.clr_int(ag, i)
            if i.ims and i.suspended is None:
                c.running.append(i)

    def drop_branches(self, i: Intention) -> None:
        """The branches of ``i`` (``reasoning.branch_for_update``) go, without events."""
        for _place, other in self.ag.circ.places():
            if other.branch_of is i:
                self.ag.circ.remove_intention(other)

    def clear_satisfied_goals(self) -> None:
        """Jason 3's ClrSatInt: each goal whose plan has a goal condition (``<:``) that holds
        now (with the bindings the plan started with) is achieved, done or not."""
        ag = self.ag
        for i in list(ag.circ.all_intentions()):
            if i.dropped:
                continue
            for idx in range(len(i.ims) - 1, -1, -1):
                im = i.ims[idx]
                if im.trigger_u is None:
                    continue
                for _ in ag.solve(im.plan.goal_condition, im.trigger_u, i):
                    self.succeed_at(i, idx)
                    break
                else:
                    continue
                break

    # ---------------------------------------------------------------- .suspend / .resume
    def suspend_goal(self, pattern: Any, s: dict, current: Intention | None) -> tuple[bool, dict]:
        """``.suspend(G)`` (jason.stdlib.suspend), in Jason's order: intentions waiting for an
        action (PA) or pending (PI) are marked, running ones go to PI, then the current one,
        then events for G (or of such intentions) go to PE. As in Jason, one unifier serves
        all the matches, so the bindings of a match restrict the next ones (and are kept).
        Returns (the current intention suspended itself, the unifier)."""
        c = self.ag.circ
        pend = [i for i in c.suspended.values() if i is not current]
        pa = sorted((i for i in pend if i.suspended is Suspension.ACTION),
                    key=lambda i: i.id & 15)
        pi = java_map_order([i for i in pend if i.pi_key is not None], lambda i: i.pi_key)
        for i in pa + pi:
            s2 = has_goal(i, pattern, s)
            if s2 is not None:
                s = s2
                i.sus_ia = True
                if i.pi_key is None:
                    i.pi_key = f"suspended-{i.id}"
        for i in list(c.running):
            s2 = has_goal(i, pattern, s)
            if s2 is not None:
                s = s2
                c.running.remove(i)
                c.suspend(i, Suspension.SUSPENDED)
                i.sus_ia = True
                i.pi_key = f"suspended-{i.id}"
        own = False
        if current is not None:
            s2 = has_goal(current, pattern, s)
            if s2 is not None:
                s = s2
                own = True
                c.suspend(current, Suspension.SUSPENDED)
                current.sus_ia = True
                current.pi_key = f"suspended-self-{current.id}"
        if c.events:
            keep: deque = deque()
            n = 0
            for ev in c.events:
                s2 = event_has_goal(ev, pattern, s)
                if s2 is None:
                    keep.append(ev)
                    continue
                s = s2
                c.pending_events.append(PendingEvent(f"suspended-{ev.trigger}{n}", ev))
                n += 1
                if ev.intention is not None:
                    ev.intention.sus_ia = True
            c.events = keep
        self._goal_state_of(pattern, s, "suspended")
        return own, s

    def _goal_state_of(self, pattern: Any, s: dict, state: str) -> None:
        """The goal-state event of a goal ``.suspend``/``.resume`` handled (when bound)."""
        if self.ag.pl.goal_state_plans:
            g = resolve(pattern, s)
            if isinstance(g, Literal):
                self.ag.circ.goal_state(Trigger(ADD, ACHIEVE, g.with_self_source()), state,
                                        _SUSPEND_IA if state == "suspended" else "")

    def resume_goal(self, pattern: Any, s: dict) -> dict:
        """``.resume(G)`` (jason.stdlib.resume): intentions held in PI by ``.suspend`` go back
        to the running queue (in the order of Jason's PI map), the others only lose the mark;
        then the held events go back to the end of the event queue. One unifier serves all
        the matches (as in Jason); it is returned."""
        ag = self.ag
        c = ag.circ
        pi = [i for i in c.suspended.values() if i.pi_key is not None]
        for i in java_map_order(pi, lambda i: i.pi_key):
            if not i.sus_ia:
                continue
            s2 = has_goal(i, pattern, s)
            if s2 is None:
                continue
            s = s2
            i.sus_ia = False
            top = i.top()
            states = ag.pl.goal_state_plans and top is not None and top.is_goal_add
            if states:
                c.goal_state(top.trigger, "resumed", _RESUME_IA)
            if (i.pi_key or "").startswith("suspended-"):
                i.pi_key = None
                if i.suspended is Suspension.SUSPENDED:
                    c.resume(i)
            elif states:
                c.goal_state(top.trigger, "waiting", i.wait_reason or "")   # still waiting
        for held in java_map_order(list(c.pending_events), lambda p: p.key):
            ev = held.event
            s2 = event_has_goal(ev, pattern, s)
            if s2 is None:
                continue
            s = s2
            if ag.pl.goal_state_plans and ev.trigger.op == ADD and ev.trigger.is_goal:
                c.goal_state(ev.trigger, "resumed", _RESUME_IA)
            c.pending_events.remove(held)
            if ev.intention is not None:
                ev.intention.sus_ia = False
            if c.event_waits:
                c.check_event_waits(ev)
            c.events.append(ev)
        return s

    def fail_goal(self, pattern: Any, s: dict, annots: tuple = ()) -> None:
        """``.fail_goal(G)``: each goal G is failed (its ``-!G`` event gets ``annots``)."""
        ag = self.ag
        c = ag.circ
        for ev in self._goal_events(pattern, s):
            if ev.intention is not None:
                continue
            # jason.stdlib.fail_goal on an external event: it becomes the -!G event
            if ag.pl.goal_state_plans:
                c.goal_state(ev.trigger, "failed", Literal("drop_by_fail_goal"))
            k = c.events.index(ev)
            lit = ev.trigger.literal
            c.events[k] = Event(Trigger(DEL, ACHIEVE, lit.add_annots(annots) if annots else lit))
        for i, idx in list(self._goal_positions(pattern, s)):
            if idx == 0:
                reasoning.fail_goal_at(ag, i, idx, annots)   # Jason 3.3 fails with an NPE
                continue
            s2 = dict(s)
            unify(pattern, i.ims[idx].trigger.literal, s2, ag)
            idx, s2 = self._lowest_occurrence(i, idx, pattern, s2)
            reasoning.fail_goal_above(ag, i, idx, resolve(pattern, s2), annots)

    def _lowest_occurrence(self, i: Intention, idx: int, pattern: Any, s: dict) -> tuple[int, dict]:
        """Jason's ``Intention.dropGoal`` drops the goal again while a means further down
        unifies with it under the bindings so far (a recursive goal): the lowest such means
        with a caller, and the bindings."""
        for j in range(idx - 1, 0, -1):
            t = i.ims[j].trigger
            s2 = dict(s)
            if t.op == ADD and t.type == ACHIEVE and unify(pattern, t.literal, s2, self.ag):
                idx, s = j, s2
        return idx, s

    # ---------------------------------------------------------------- hard deadlines
    def schedule_deadline(self, trig: Trigger, i: Intention | None, delay: float) -> None:
        """A goal's ``hard_deadline``: ``delay`` clock seconds from now, the goal ``trig`` of
        intention ``i`` (None: a ``!!g``) fails if it is still pursued."""
        size = len(i.ims) if i is not None else 0
        self.ag.circ.push_timer(self.ag.arch.clock.now() + delay, TimerKind.DEADLINE, None,
                                data=(trig, i, size))

    def deadline_reached(self, trig: Trigger, i: Intention | None, size: int) -> None:
        """Jason's hard deadline check: the goal is still desired (``!!g``), or its intention
        is as deep as it was and still has the goal; then it fails with ``deadline_reached``."""
        goal = trig.literal
        if i is None:
            drop = bool(self._goal_events(goal, {})) or any(True for _ in self._goal_positions(goal, {}))
        else:
            drop = (not i.dropped and len(i.ims) >= size
                    and any(im.trigger.op == ADD and im.trigger.type == ACHIEVE
                            and unify(goal, im.trigger.literal, {}, self.ag) for im in i.ims))
        if drop:
            self.fail_goal(goal, {}, _DEADLINE_REACHED)
