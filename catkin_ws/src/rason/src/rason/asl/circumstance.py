"""The agent's circumstance (Jason's ``Circumstance``): the events, the intentions (running,
suspended, pending), the pending actions, the waits and timers, and their small operations."""

from __future__ import annotations

import heapq
import itertools
from collections import deque
from typing import TYPE_CHECKING, Any

from . import reasoning
from .intentions import (
    ActionResult,
    AskWait,
    Event,
    EventWait,
    Intention,
    PendingAction,
    PendingEvent,
    Suspension,
    Timer,
    TimerKind,
)
from .plans import ACHIEVE, ADD, GOAL_STATE, Trigger
from .terms import Literal, java_map_order, term_str
from .unify import unify

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent

#: an intention back from these waits posts its goal as executing again
_EXECUTING_AGAIN = frozenset({Suspension.WAIT, Suspension.EVENT_WAIT, Suspension.ASK,
                              Suspension.SUSPENDED})
#: what an intention waits for when its own event is queued (it is not blocking then)
_OWN_EVENT_WAITS = frozenset({None, Suspension.SUBGOAL, Suspension.EVENT, Suspension.FAILURE})


class Circumstance:
    """The state the reasoning cycle works on (Jason's ``C``) of the agent ``ag``."""

    def __init__(self, ag: Agent) -> None:
        self.ag = ag
        self.events: deque[Event] = deque()
        #: goal-state meta events waiting for the start of the next deliberation (Jason's
        #: GoalListenerForMetaEvents posts them with runAtBeginOfNextCycle)
        self.goal_state_events: list[Event] = []
        #: Jason's queue of running intentions (a FIFO: SelInt polls the first one, an
        #: intention that executed a step goes back to the end)
        self.running: deque[Intention] = deque()
        self.action_results: deque[ActionResult] = deque()
        self.current: Intention | None = None
        self.suspended: dict[int, Intention] = {}
        self.pending_actions: dict[int, PendingAction] = {}
        self.timers: list[Timer] = []                 # a heap
        self.event_waits: list[EventWait] = []
        self.pending_events: list[PendingEvent] = []  # Jason's PE: events held by .suspend
        self.selected_event: Event | None = None      # Jason's C.SE (the event of this cycle)
        self.ask_waits: dict[str, AskWait] = {}       # by the question's msg_id
        self.seq = itertools.count()                  # the timers' tie-breaker
        self.action_ids = itertools.count(1)
        self.intention_ids = itertools.count(1)
        #: set once an [atomic] plan is intended: until then no intention can be atomic
        self.atomic_used = False

    # ================================================================ events
    def add_event(self, ev: Event) -> None:
        """Queue an event; like Jason, an external event nobody listens to is only kept when
        some plan is relevant for it."""
        t = ev.trigger
        pl = self.ag.pl
        if pl.goal_state_plans and t.op == ADD and t.type == ACHIEVE and ev.intention is None:
            self.goal_state(t, "pending")
        if self.event_waits:
            self.check_event_waits(ev)
        elif (ev.intention is None and not (ev.trigger.is_goal and ev.trigger.op == ADD)
              and not pl.relevant(ev.trigger) and not pl.may_branch(ev.trigger.key)):
            return
        self.events.append(ev)

    def check_event_waits(self, ev: Event) -> None:
        """Resume the intentions whose ``.wait(E)`` the event ``ev`` matches."""
        t = ev.trigger
        keep = []
        woken = []
        for w in self.event_waits:
            trig = w.trigger
            if (trig is not None and trig.op == t.op and trig.type == t.type
                    and unify(trig.literal, t.literal, {}, self.ag)):
                woken.append(w.intention)
                if w.intention.wait_elapsed is not None:
                    self.bind_elapsed(w.intention)
            else:
                keep.append(w)
        if woken:
            self.event_waits = keep
            for i in woken:
                self.resume(i)

    def check_cond_waits(self) -> None:
        """Resume the intentions whose ``.wait(Condition)`` holds now."""
        if not any(w.condition is not None for w in self.event_waits):
            return
        keep = []
        for w in self.event_waits:
            cond, i, im = w.condition, w.intention, w.means
            if cond is not None and im is not None:
                sol = next(iter(self.ag.solve(cond, im.u, i)), None)
                if sol is not None:
                    im.u = sol
                    if i.wait_elapsed is not None:
                        self.bind_elapsed(i)
                    self.resume(i)
                    continue
            keep.append(w)
        self.event_waits = keep

    def goal_state(self, trigger: Trigger, state: str, reason: Any = "") -> None:
        """Post the goal-state meta event ``^!g[state(S)[reason(R)]]`` when a plan handles it
        (Jason's GoalListenerForMetaEvents)."""
        lit = trigger.literal
        if not isinstance(lit, Literal):
            return
        st = Literal("state", (Literal(state),), (Literal("reason", (reason,)),))
        meta = Trigger(GOAL_STATE, trigger.type, lit.add_annots([st]))
        if self.ag.pl.relevant(meta):
            self.goal_state_events.append(Event(meta))

    def post_goal_states(self) -> None:
        """At the start of a deliberation: the goal-state events of the last cycle go before
        every other event, after the meta events already queued (Jason's insertMetaEvent)."""
        if not self.goal_state_events:
            return
        posted, self.goal_state_events = self.goal_state_events, []
        pos = 0
        for ev in self.events:
            if ev.trigger.op != GOAL_STATE:
                break
            pos += 1
        for ev in posted:
            self.events.insert(pos, ev)
            pos += 1

    # ================================================================ intentions
    def atomic_running(self) -> bool:
        """Jason's ``C.hasAtomicIntention``: an atomic intention runs, or waits (``.wait``,
        an action, an answer) without giving up its atomicity; one waiting for its own
        event (a subgoal, a belief change, a failure) is not counted."""
        if not self.atomic_used:
            return False
        for i in self.running:
            if i.atomic_count:
                return True
        for i in self.suspended.values():
            if i.atomic_count and not i.sus_ia and not i.dropped and i.suspended not in _OWN_EVENT_WAITS:
                return True
        return False

    def all_intentions(self) -> list[Intention]:
        """Every intention: the current one, the running, the suspended, those of events."""
        out = []
        if self.current is not None:
            out.append(self.current)
        out.extend(self.running)
        out.extend(i for i in self.suspended.values() if i is not self.current)
        seen = set()
        for ev in itertools.chain(self.events, (e for _, e in self.pending_events)):
            if ev.intention is not None and ev.intention.id not in seen and ev.intention not in out:
                seen.add(ev.intention.id)
                out.append(ev.intention)
        return out

    def places(self) -> list[tuple[str, Intention]]:
        """The intentions as Jason's ``Circumstance.getAllIntentions`` visits them, with their
        place: the selected event's (SE), the current one (SI) unless it is the same, then those
        of queued events (E), of held events (PE), waiting for an action (PA), pending (PI:
        ``.wait``, ask, ``.suspend``, a goal condition) and running (I), each time without the SE
        and SI intentions. An intention held by ``.suspend`` while waiting for an action is in PA
        and in PI."""
        out: list[tuple[str, Intention]] = []
        se = self.selected_event
        by_se = se.intention if se is not None else None
        if by_se is not None:
            out.append(("SE", by_se))
        cur = self.current
        by_si = cur if cur is not by_se else None
        if by_si is not None:
            out.append(("SI", by_si))

        def others(place: str, intentions: Any) -> None:
            out.extend((place, i) for i in intentions
                       if i is not None and i is not by_se and i is not by_si)
        others("E", (ev.intention for ev in self.events))
        others("PE", (held.event.intention
                      for held in java_map_order(self.pending_events, lambda p: p.key)))
        pend = [i for i in self.suspended.values() if i is not cur]
        others("PA", sorted((i for i in pend if i.suspended is Suspension.ACTION), key=lambda i: i.id & 15))
        others("PI", java_map_order([i for i in pend if i.pi_key is not None], lambda i: i.pi_key))
        others("I", self.running)
        return out

    def suspend(self, i: Intention, why: Suspension) -> None:
        """``i`` waits (for ``why``) among the suspended intentions."""
        i.suspended = why
        self.suspended[i.id] = i

    def resume(self, i: Intention, executing: bool = True) -> bool:
        """What ``i`` waited for happened: back to the running queue, unless ``.suspend`` holds
        it (then it stays in PI as ``suspended-<id>`` until ``.resume``, as in jason.stdlib.wait).
        Returns True when ``i`` runs again (its goal then is ``executing`` again, unless
        ``executing`` is False: it is about to fail)."""
        if i.sus_ia and not i.dropped:
            i.suspended = Suspension.SUSPENDED
            i.pi_key = f"suspended-{i.id}"
            self.suspended[i.id] = i
            return False
        self.suspended.pop(i.id, None)
        why, i.suspended = i.suspended, None
        i.pi_key = None
        if not i.dropped and i.ims:
            self.running.append(i)
            top = i.ims[-1]
            if executing and why in _EXECUTING_AGAIN and self.ag.pl.goal_state_plans and top.is_goal_add:
                self.goal_state(top.trigger, "executing")   # Jason's resumeIntention
            return True
        return False

    def detach(self, i: Intention) -> None:
        """Remove ``i`` from every queue/registration (it is about to be re-attached elsewhere)."""
        if i in self.running:
            self.running.remove(i)
        self.suspended.pop(i.id, None)
        if self.event_waits:
            self.event_waits = [w for w in self.event_waits if w.intention is not i]
        for k in [k for k, w in self.ask_waits.items() if w.intention is i]:
            del self.ask_waits[k]
        for aid in [aid for aid, p in self.pending_actions.items() if p.intention is i]:
            del self.pending_actions[aid]
            self.ag.arch.action_abandoned(self.ag, aid)    # nobody waits for it: stop it
        if any(ev.intention is i for ev in self.events):
            self.events = deque(ev for ev in self.events if ev.intention is not i)
        if self.pending_events:
            self.pending_events = [p for p in self.pending_events if p.event.intention is not i]
        i.suspended = None
        i.sus_ia = False
        i.pi_key = None

    def remove_intention(self, i: Intention) -> None:
        """Drop ``i``: out of every queue, its stack emptied."""
        self.detach(i)
        i.dropped = True
        i.ims.clear()

    def is_idle(self) -> bool:
        """No events, no runnable intention, no action result to take (inbox aside)."""
        return (not self.events and not self.running and not self.action_results
                and not self.goal_state_events)

    def has_pending(self) -> bool:
        """Something may still happen later: actions, timers, awaited events or answers."""
        return bool(self.pending_actions or self.timers or self.event_waits or self.ask_waits)

    # ================================================================ waits and timers
    def push_timer(self, deadline: float, kind: TimerKind, i: Intention | None, msg_id: str | None = None,
                   data: Any = None) -> None:
        """Start a timer (see :class:`.Timer`)."""
        heapq.heappush(self.timers, Timer(deadline, next(self.seq), kind, i, msg_id, data=data))

    def next_deadline(self) -> float | None:
        """Earliest ``.wait`` deadline (clock seconds), or None."""
        while (self.timers and self.timers[0].kind is not TimerKind.AT
               and self.timers[0].kind is not TimerKind.DEADLINE
               and (self.timers[0].intention is None
                    or self.timers[0].intention.id not in self.suspended)):
            heapq.heappop(self.timers)
        return self.timers[0].deadline if self.timers else None

    def schedule_event(self, trigger: Trigger, delay: float) -> None:
        """``.at``: post the event ``delay`` clock seconds from now."""
        self.push_timer(self.ag.arch.clock.now() + delay, TimerKind.AT, None, data=trigger)

    def suspend_timer(self, i: Intention, deadline: float | None, ms: float = 0.0) -> None:
        """``.wait(ms)``: ``i`` waits until ``deadline`` (None: for ever)."""
        self.suspend(i, Suspension.WAIT)
        # whole milliseconds in the reason, as Jason (its wait time is a long)
        i.wait_reason = Literal("wait", (float(i.id),), (Literal("time", (float(int(ms)),)),))
        # Jason's key in PI is the reason's text (``wait(3)[time(1000)]``): it orders PI
        i.pi_key = term_str(i.wait_reason)
        if deadline is not None:
            self.push_timer(deadline, TimerKind.WAIT, i, data=i.wait_reason)
        self._goal_waiting(i, i.wait_reason)

    def suspend_event_wait(self, i: Intention, trig: Trigger | None, cond: Any,
                           deadline: float | None) -> None:
        """``.wait(E)`` / ``.wait(Condition)``: ``i`` waits for an event or a condition."""
        self.suspend(i, Suspension.EVENT_WAIT)
        what = trig.literal if trig is not None else cond
        i.wait_reason = Literal("wait", (float(i.id),), (what,))
        i.pi_key = term_str(i.wait_reason)
        self._goal_waiting(i, i.wait_reason)
        self.event_waits.append(EventWait(trig, cond, i, i.top()))
        if deadline is not None:
            # the reason identifies this very wait: a timer of an earlier wait is stale
            self.push_timer(deadline, TimerKind.EVENT_TIMEOUT, i, data=i.wait_reason)

    def _goal_waiting(self, i: Intention, reason: Any) -> None:
        """Jason's intentionWaiting: the goal of the top means is ``waiting``."""
        top = i.top()
        if self.ag.pl.goal_state_plans and top is not None and top.trigger.op == ADD and top.trigger.is_goal:
            self.goal_state(top.trigger, "waiting", reason)

    def bind_elapsed(self, i: Intention) -> None:
        """``.wait(E, T, Elapsed)``: Elapsed gets the milliseconds the intention waited."""
        term, start = i.wait_elapsed
        i.wait_elapsed = None
        im = i.top()
        if im is not None:
            s2 = dict(im.u)
            if unify(term, float(int((self.ag.arch.clock.now() - start) * 1000)), s2):
                im.u = s2

    def check_timers(self) -> bool:
        """Fire the timers due: ``.at`` events, hard deadlines, ``.wait`` and ask timeouts."""
        ag = self.ag
        now = ag.arch.clock.now()
        did = False
        while self.timers and self.timers[0].deadline <= now:
            timer = heapq.heappop(self.timers)
            kind, i = timer.kind, timer.intention
            if kind is TimerKind.AT:
                self.add_event(Event(timer.data))
                did = True
                continue
            if kind is TimerKind.DEADLINE:
                ag.goals.deadline_reached(*timer.data)
                did = True
                continue
            if i is None or i.id not in self.suspended or i.dropped:   # only .at has no intention
                continue
            if kind is TimerKind.WAIT and i.suspended is Suspension.WAIT and timer.data is i.wait_reason:
                self.resume(i)
                did = True
            elif (kind is TimerKind.EVENT_TIMEOUT and i.suspended is Suspension.EVENT_WAIT
                  and timer.data is i.wait_reason):
                self.event_waits = [w for w in self.event_waits if w.intention is not i]
                if i.wait_elapsed is not None:
                    self.bind_elapsed(i)
                    self.resume(i)
                    did = True
                    continue
                if not self.resume(i, executing=False):
                    continue
                top = i.top()
                assert top is not None      # a waiting intention has its .wait on top
                reasoning.fail_intention(ag, i, annots=reasoning.error_annots(
                    ag, top, None, "wait_timeout", "timeout in .wait"))
                did = True
            elif kind is TimerKind.ASK_TIMEOUT and i.suspended is Suspension.ASK:
                did = ag.comm.ask_timed_out(i, timer.msg_id) or did
        return did
