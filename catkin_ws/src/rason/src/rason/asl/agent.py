"""The agent (Jason's ``Agent`` + ``Circumstance``): state, public thread-safe API, helpers."""

from __future__ import annotations

import heapq
import itertools
import math
import os
import sys
import threading
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

from . import reasoning
from .arch import AgentArch, JavaRandom, Message
from .beliefs import BeliefBase
from .ia import IAError, is_registered
from .inspection import MindState, mind_state, mind_text
from .intentions import (
    ActionResult,
    AskWait,
    Event,
    EventWait,
    IntendedMeans,
    Intention,
    PendingAction,
    PendingEvent,
    Suspension,
    Timer,
    TimerKind,
    event_has_goal,
    has_goal,
    java_map_order,
)
from .kqml import KQML_SRC, kqml_plans, plans_answered_by
from .logic import query_bb, solve
from .parser import AgentSource, AslSyntaxError, parse_source, parse_term, path_include_resolver
from .plans import ACHIEVE, ADD, BELIEF, DEL, GOAL_STATE, K_INTERNAL, PlanLibrary, Trigger, body_deeds
from .selection import Selection
from .terms import (
    FALSE,
    SOURCE_PERCEPT,
    SOURCE_SELF,
    ListTerm,
    Literal,
    Rule,
    is_ground,
    make_list,
    merge_annots,
    source,
    term_str,
    with_nested_source,
)
from .unify import rename_vars, resolve, unify

#: cycles a thread that brought input runs for a sleeping agent before handing over to the
#: agent's runner (see Agent._take_turns)
TURN_STEPS = 64
#: goal-state reasons of .suspend / .resume (as Jason's)
_SUSPEND_IA = Literal("suspend_ia")
_RESUME_IA = Literal("resume_ia")
#: an intention back from these waits posts its goal as executing again
_EXECUTING_AGAIN = frozenset({Suspension.WAIT, Suspension.EVENT_WAIT, Suspension.ASK,
                              Suspension.SUSPENDED})


@dataclass(frozen=True)
class AgentOptions:
    """Per-agent settings (Jason's agent options in ``.mas2j``).

    ``tro``: tail-recursion optimisation (Jason's ``tro``, on by default): a goal whose plan
    ends by posting the same goal again replaces its intended means instead of growing the
    intention, so ``+!loop <- ...; !loop.`` runs in constant memory.
    ``max_intention_depth``: an intention deeper than this (intended means on its stack)
    fails with ``error(intention_too_deep)`` instead of eating memory.
    """

    tro: bool = True
    max_intention_depth: int = 10_000

    @classmethod
    def from_options(cls, options: dict, default: AgentOptions | None = None) -> AgentOptions:
        """From ``.mas2j``-style options (``tro=false``, ``max_intention_depth=500``); the
        ones not given are those of ``default``."""
        base = default if default is not None else cls()
        tro = options.get("tro", base.tro)
        depth = options.get("max_intention_depth", base.max_intention_depth)
        return cls(tro=str(tro).strip().strip('"').lower() not in ("false", "off", "no", "0"),
                   max_intention_depth=int(float(str(depth).strip().strip('"'))))


def _strip_sources(t: Any) -> Any:
    if isinstance(t, Literal) and t.annots:
        return t.with_annots(tuple(a for a in t.annots
                                   if not (isinstance(a, Literal) and a.functor == "source")), t.tail)
    return t


class Agent:
    """A Jason agent: belief base, plan library, circumstance and reasoning cycle.

    ``receive``, ``action_feedback`` and ``wake`` may be called from any thread; everything else
    runs in the thread that calls ``step``/``run``.
    """

    def __init__(self, name: str, source: str, arch: AgentArch, filename: str = "<string>",
                 seed: int | None = None, src_name: str | None = None,
                 options: AgentOptions | None = None, source_path: list[str] | None = None,
                 selection: Selection | None = None,
                 belief_update: Callable[[Agent, list], bool] | None = None,
                 accept_message: Callable[[Agent, Message], bool] | None = None) -> None:
        self.name = name
        #: the event, option and intention selection functions (see :mod:`.selection`)
        self.selection = selection if selection is not None else Selection()
        #: Jason's ``buf``: ``fn(agent, percepts) -> changed`` instead of :meth:`update_percepts`
        #: (which it may call with the percepts it keeps)
        self.belief_update = belief_update
        #: Jason's ``socAcc``: ``fn(agent, message) -> bool``; a message it refuses is dropped
        #: (answers to this agent's asks are always taken, as in Jason)
        self.accept_message = accept_message
        self.options = options if options is not None else AgentOptions()
        #: folders where included files (and agents created by this one) are looked for
        self.source_path = list(source_path or [])
        self.arch = arch
        #: the architecture has percepts to give (it overrides ``perceive``, in its class or on
        #: the instance): each cycle asks
        self._perceives = (type(arch).perceive is not AgentArch.perceive
                           or "perceive" in getattr(arch, "__dict__", {}))
        self.filename = filename
        if src_name is None:
            src_name = os.path.basename(filename) if filename != "<string>" else filename
        parsed = parse_source(source, filename, src="file:" + src_name,
                              include=path_include_resolver(self.source_path))
        self.bb = BeliefBase()
        #: what a mind inspector keeps between snapshots (an inspection.MindViews, made by
        #: the first snapshot; None for an agent never inspected)
        self.inspector_views: Any = None
        #: ``.namespace_set_prop``'s properties: namespace -> key -> (key term, value term)
        self.namespace_props: dict[str, dict[str, tuple]] = {}
        self.pl = PlanLibrary()
        self.events: deque[Event] = deque()
        # goal-state meta events waiting for the start of the next deliberation (Jason's
        # GoalListenerForMetaEvents posts them with runAtBeginOfNextCycle)
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
        self.random = JavaRandom(seed)
        self._seq = itertools.count()
        self._action_ids = itertools.count(1)
        self.intention_ids = itertools.count(1)
        self._inbox: deque[ActionResult | None] = deque()   # action feedback; None: a wake-up
        self._mail: deque[Message] = deque()                # messages, one taken per cycle
        self._inbox_lock = threading.Lock()
        self._wake_event = threading.Event()
        # held by the thread running reasoning cycles: the agent's runner, or a thread that
        # brought input while the runner slept (see _take_turns)
        self._turn = threading.Lock()
        # the runner's wake-up time while it sleeps (math.inf: none), None while it is awake;
        # written with _turn held
        self._asleep_until: float | None = None
        self._runner_stop: threading.Event | None = None   # the running runner's stop event
        self._caller_turn = False     # a thread that brought input holds _turn (see _take_turns)
        self._state_lock = threading.RLock()
        self._percepts: set = set()
        # set once an [atomic] plan is intended: until then no intention can be atomic
        self.atomic_used = False
        #: set by :meth:`request_stop` (``.stopMAS``, a killed agent): its runner stops
        self.stop_requested = False
        # idle (Jason's sleeping agent): +jag_sleeping / +jag_awaking events for plans that want them
        self.sleeping = False
        # called (from any thread) whenever input arrives; a runner may use it to wake up
        self.on_wake: Any = None
        self.load(parsed)
        arch.attach(self)

    # ================================================================ loading
    def load(self, parsed: AgentSource) -> None:
        """Take the program: plans (then Jason's KQML plans), initial beliefs and goals."""
        self._warn_unknown_actions(parsed)
        for p in parsed.plans + kqml_plans():
            self.pl.add(p)
        self._add_initial_state(parsed)

    def include(self, parsed: AgentSource) -> None:
        """Add an included program (``.include``): its plans after this agent's, its beliefs
        and goals as initial ones (Jason's ``importComponents`` and what follows it)."""
        self._warn_unknown_actions(parsed)
        for p in parsed.plans:
            self.pl.add(p)
        self._add_initial_state(parsed)

    def _warn_unknown_actions(self, parsed: AgentSource) -> None:
        for p in parsed.plans:
            for d in body_deeds(p.body):
                if d.kind == K_INTERNAL and not is_registered(d.term.functor):
                    # as Jason's parser: a warning at load; running it fails with action_failed
                    self.log(f"{self.filename}:{d.line}: warning: unknown internal action "
                             f"{d.term.functor}/{len(d.term.args)}")

    def _add_initial_state(self, parsed: AgentSource) -> None:
        for b in reversed(parsed.beliefs):
            if isinstance(b, Rule):
                self.bb.add_rule(b, front=True)
            else:
                lit = b.with_self_source()
                if not is_ground(lit):
                    self.bb.add(lit, front=True)
                    continue
                self.add_belief(lit, front=True)
        for g in parsed.goals:
            lit = g.with_self_source()
            self.events.append(Event(Trigger(ADD, ACHIEVE, lit)))
            if self.pl.goal_state_plans:
                self.goal_state(self.events[-1].trigger, "pending")

    def add_initial(self, beliefs: str | None = None, goals: str | None = None) -> None:
        """The ``beliefs="..."`` and ``goals="..."`` options of a ``.mas2j`` agent: comma
        separated literals added as initial beliefs / goals."""
        for text, is_goal in ((beliefs, False), (goals, True)):
            if not text:
                continue
            items = parse_term("[" + text + "]")
            for lit in getattr(items, "items", ()):
                if not isinstance(lit, Literal):
                    continue
                lit = lit.with_self_source()
                if is_goal:
                    self.events.append(Event(Trigger(ADD, ACHIEVE, lit)))
                else:
                    self.add_belief(lit, front=False)

    # ================================================================ public API
    def receive(self, message: Message, run_here: bool = False) -> None:
        """Thread-safe: queue an incoming message and wake the agent; with ``run_here`` a
        caller that finds the agent's runner asleep reasons on it itself (:meth:`_take_turns`)."""
        with self._inbox_lock:
            self._mail.append(message)
        self._input_arrived(run_here)

    def action_feedback(self, action_id: int, ok: bool, reason: str | None = None, message: str = "",
                        annots: list | None = None, run_here: bool = False) -> None:
        """Thread-safe: the environment finished action ``action_id`` (ok or failed with reason;
        ``annots``: more annotations for the failure event, like Jason's failure reason term;
        ``run_here``: as for :meth:`receive`)."""
        with self._inbox_lock:
            self._inbox.append(ActionResult(action_id, ok, reason, message, annots))
        self._input_arrived(run_here)

    def wake(self) -> None:
        """Thread-safe: something changed (e.g. new percepts); run a cycle soon."""
        with self._inbox_lock:
            self._inbox.append(None)
        self._input_arrived(False)

    def _input_arrived(self, run_here: bool) -> None:
        if run_here and self._take_turns():
            return
        self._wake_event.set()
        if self.on_wake is not None:
            self.on_wake()

    def _take_turns(self) -> bool:
        """Reason on the calling thread, now, if the agent's runner (:meth:`run`) sleeps.

        A thread that brings input to a sleeping agent (a ROS node's receiving thread) runs the
        cycles it causes itself, instead of waking the runner and leaving the CPU to it: on a
        loaded machine that second thread waited for a core behind every other process woken
        by the same broadcast. Cycles still run one at a time (``_turn``): input brought while
        another such thread reasons is left to it (it looks for more input once it has let go
        of the turn). True when the input is dealt with and the runner sleeps on; False when
        the runner must take over (see :meth:`_turn_cycles`).
        """
        while True:
            if self._asleep_until is None:
                return False                      # the runner is awake, or not running
            if not self._turn.acquire(blocking=False):
                # a thread that brought input before this one reasons: it finds this input
                # when it lets go (below); the runner, about to sleep or wake, is woken
                return self._caller_turn
            try:
                self._caller_turn = True
                handled = self._turn_cycles()
            finally:
                self._caller_turn = False
                self._turn.release()
            if not handled:
                return False
            if not self.has_input():
                return True
            # input was brought while this thread reasoned and found the turn taken

    def _turn_cycles(self) -> bool:
        """The cycles of a bringing thread's turn (``_turn`` held): True when the agent is idle
        and the runner may sleep on; False when the runner must take over: it woke, or was woken
        meanwhile (other input, a stop: the turn ends after the cycle under way), the agent is
        still busy after :data:`TURN_STEPS` cycles, or a timer now falls due before the
        runner's wake-up time."""
        asleep_until = self._asleep_until
        stop = self._runner_stop
        if asleep_until is None or stop is None:
            return False                          # the runner woke, or has not started
        for _ in range(TURN_STEPS):
            if self._wake_event.is_set() or stop.is_set() or self.stop_requested:
                return False
            if not self.step():
                break
        else:
            return False                          # still busy: its runner goes on
        deadline = self.next_deadline()
        return deadline is None or deadline >= asleep_until

    def step(self) -> bool:
        """One reasoning cycle; True if it did anything."""
        with self._state_lock:
            try:
                # each stage is skipped (one test) when it has nothing to do: a busy agent
                # without an environment or mail pays no call for sensing
                did = False
                if self._perceives or self._inbox or self._mail or self.timers:
                    if self.sleeping and (self._inbox or self._mail):
                        self._wake_up()   # as Jason: +jag_awaking before what woke the agent
                    did = self.sense()
                    if did and self.sleeping:
                        self._wake_up()
                if self.events or self.goal_state_events:
                    did = reasoning.deliberate(self) or did
                else:
                    self.selected_event = None
                if self.running or self.action_results or self.pl.goal_condition_plans:
                    did = reasoning.act(self) or did
                if not did and not self.sleeping and not self.events and not self.running:
                    did = self._fall_asleep()
            except Exception as e:  # a bug or an odd program must not kill the agent
                self.log(f"internal error in the reasoning cycle ({type(e).__name__}: {e}); "
                         "the event/intention at hand was dropped")
                if self.current is not None:
                    self.remove_intention(self.current)
                    self.current = None
                return True
            return did

    def _fall_asleep(self) -> bool:
        """Nothing to do: the agent sleeps; with a ``+jag_sleeping`` plan (Jason's sleep
        event), that event is posted. Returns True when it was."""
        self.sleeping = True
        if self.pl.has_key(_JAG_SLEEPING.key):
            self.events.append(Event(_JAG_SLEEPING))
            return True
        return False

    def _wake_up(self) -> None:
        """Input arrived while asleep: ``+jag_awaking`` (when a plan wants it)."""
        self.sleeping = False
        if self.pl.has_key(_JAG_AWAKING.key):
            self.events.append(Event(_JAG_AWAKING))

    def post_external(self, ev: Event) -> None:
        """An external event from the host (Jason's ``addExternalEv``); a sleeping agent wakes
        after it (``+jag_awaking`` comes after the event)."""
        self.add_event(ev)
        if self.sleeping:
            self._wake_up()

    def run(self, stop: threading.Event) -> None:
        """Reason until ``stop`` is set; block (no polling) while idle."""
        def watcher() -> None:
            stop.wait()
            self._wake_event.set()
        threading.Thread(target=watcher, name=f"{self.name}-stop", daemon=True).start()
        clock = self.arch.clock
        self._runner_stop = stop
        while not stop.is_set() and not self.stop_requested:
            sleep, deadline = self._runner_turn(stop)
            if sleep:
                clock.wait(self._wake_event, deadline)
        with self._turn:
            self._asleep_until = None

    def _runner_turn(self, stop: threading.Event) -> tuple[bool, float | None]:
        """One cycle of the runner, holding the turn: (whether it may sleep now, until when)."""
        with self._turn:
            self._asleep_until = None
            self._wake_event.clear()
            if self.step() or stop.is_set() or self.has_input():
                return False, None
            deadline = self.next_deadline()
            self._asleep_until = math.inf if deadline is None else deadline
            return True, deadline

    def is_idle(self) -> bool:
        """No events, no runnable intention, nothing in the inbox."""
        with self._inbox_lock:
            inbox = bool(self._inbox or self._mail)
        return (not self.events and not self.running and not inbox and not self.action_results
                and not self.goal_state_events)

    def has_pending(self) -> bool:
        """Something may still happen later: actions, timers, awaited events or answers."""
        return bool(self.pending_actions or self.timers or self.event_waits or self.ask_waits)

    def has_input(self) -> bool:
        with self._inbox_lock:
            return bool(self._inbox or self._mail)

    def next_deadline(self) -> float | None:
        """Earliest ``.wait`` deadline (clock seconds), or None."""
        while (self.timers and self.timers[0].kind is not TimerKind.AT
               and self.timers[0].kind is not TimerKind.DEADLINE
               and (self.timers[0].intention is None
                    or self.timers[0].intention.id not in self.suspended)):
            heapq.heappop(self.timers)
        return self.timers[0].deadline if self.timers else None

    def mind(self) -> dict[str, list[str]]:
        """Snapshot of the mental state as Jason text (see :func:`inspection.mind_text`)."""
        with self._state_lock:
            return mind_text(self)

    def solve(self, f: Any, s: dict, intention: Intention | None = None) -> Iterator[dict]:
        """Every substitution extending ``s`` under which ``f`` follows from this agent's state
        (Jason's logical consequence)."""
        return solve(self, f, s, intention)

    def query_beliefs(self, lit: Literal, s: dict) -> Iterator[dict]:
        """Every substitution extending ``s`` under which ``lit`` matches a belief or a rule."""
        return query_bb(self, lit, s)

    def count_solutions(self, query: Any) -> int:
        """``.count(Q)``: how many solutions Q has in the current mental state."""
        return sum(1 for _ in solve(self, query, {}))

    def clock_millis(self) -> float:
        """``system.time`` and ``.time(T)``: whole milliseconds of the agent's clock."""
        return float(int(self.arch.clock.now() * 1000))

    def mind_state(self, blocking: bool = True) -> MindState | None:
        """Structured snapshot of the mental state, for a mind inspector (read-only); None when
        not `blocking` and a reasoning cycle of another thread holds the agent right now."""
        if not self._state_lock.acquire(blocking=blocking):
            return None
        try:
            return mind_state(self)
        finally:
            self._state_lock.release()

    def request_stop(self) -> None:
        self.stop_requested = True

    # ================================================================ console
    def console(self, text: str) -> None:
        self.arch.console(self.name, text)

    def warn(self, text: str) -> None:
        self.arch.console(self.name, text)

    def log(self, text: str) -> None:
        print(f"[{self.name}] {text}", file=sys.stderr, flush=True)

    def warn_drop(self, i: Intention, text: str, trig: Any, relevant_msg: str | None = None) -> None:
        """Jason's warning for an intention dropped because its failure was not handled."""
        if relevant_msg:
            self.warn(text)
            self.warn("\n" + i.dump())
            self.warn(relevant_msg)
        else:
            self.warn(text + "\n" + i.dump())

    # ================================================================ sense
    def sense(self) -> bool:
        """Perceive (belief update from the percepts), take mail and feedback, fire timers."""
        percepts = self.arch.perceive()
        if percepts is None:
            did = False
        elif self.belief_update is None:
            did = self.update_percepts(percepts)
        else:
            did = bool(self.belief_update(self, percepts))
        if self._inbox or self._mail:
            # all action feedback and wake-ups, but (like Jason) one message per cycle
            with self._inbox_lock:
                items = list(self._inbox)
                self._inbox.clear()
                message = self._mail.popleft() if self._mail else None
            for it in items:
                did = True
                if type(it) is ActionResult:
                    self.action_results.append(it)
            if message is not None:
                did = True
                self.process_message(message)
        if self.timers:
            did = self.check_timers() or did
        return did

    def update_percepts(self, ps: list) -> bool:
        """Belief update from percepts: add new ones, remove vanished ones (source(percept))."""
        new = set()
        order = []
        for p in ps:
            if isinstance(p, Literal):
                key = _strip_sources(p)
                if key not in new:
                    new.add(key)
                    order.append(key)
        old = self._percepts
        if new == old:
            return False
        for p in old - new:
            self.remove_belief(p.add_annots([SOURCE_PERCEPT]))
        for p in order:
            if p not in old:
                self.add_belief(p.add_annots([SOURCE_PERCEPT]), front=True)
        self._percepts = new
        return True

    def check_timers(self) -> bool:
        now = self.arch.clock.now()
        did = False
        while self.timers and self.timers[0].deadline <= now:
            timer = heapq.heappop(self.timers)
            kind, i = timer.kind, timer.intention
            if kind is TimerKind.AT:
                self.add_event(Event(timer.data))
                did = True
                continue
            if kind is TimerKind.DEADLINE:
                self._deadline_reached(*timer.data)
                did = True
                continue
            if i is None or i.id not in self.suspended or i.dropped:   # only .at has no intention
                continue
            if kind is TimerKind.WAIT and i.suspended is Suspension.WAIT:
                self.resume(i)
                did = True
            elif (kind is TimerKind.EVENT_TIMEOUT and i.suspended is Suspension.EVENT_WAIT
                  and timer.data is i.wait_reason):
                self.event_waits = [w for w in self.event_waits if w.intention is not i]
                if i.wait_elapsed is not None:
                    self._bind_elapsed(i)
                    self.resume(i)
                    did = True
                    continue
                if not self.resume(i, executing=False):
                    continue
                top = i.top()
                assert top is not None      # a waiting intention has its .wait on top
                reasoning.fail_intention(self, i, annots=reasoning.error_annots(
                    self, top, None, "wait_timeout", "timeout in .wait"))
                did = True
            elif kind is TimerKind.ASK_TIMEOUT and i.suspended is Suspension.ASK:
                w = self.ask_waits.pop(timer.msg_id, None) if timer.msg_id is not None else None
                if w is not None:
                    # jason.stdlib.send: ``timeout``, or the answers so far for a list of receivers
                    self.resume(i)
                    im = i.top()
                    assert im is not None   # the .send that asked is on top
                    s2 = dict(im.u)
                    got = Literal("timeout") if w.receivers is None else make_list(w.answers)
                    if unify(w.answer, got, s2, self):
                        im.u = s2
                    did = True
        return did

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

    def suspend(self, i: Intention, why: Suspension) -> None:
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
            if executing and why in _EXECUTING_AGAIN and self.pl.goal_state_plans and top.is_goal_add:
                self.goal_state(top.trigger, "executing")   # Jason's resumeIntention
            return True
        return False

    def goal_state(self, trigger: Trigger, state: str, reason: Any = "") -> None:
        """Post the goal-state meta event ``^!g[state(S)[reason(R)]]`` when a plan handles it
        (Jason's GoalListenerForMetaEvents)."""
        lit = trigger.literal
        if not isinstance(lit, Literal):
            return
        st = Literal("state", (Literal(state),), (Literal("reason", (reason,)),))
        meta = Trigger(GOAL_STATE, trigger.type, lit.add_annots([st]))
        if self.pl.relevant(meta):
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

    def schedule_event(self, trigger: Trigger, delay: float) -> None:
        """``.at``: post the event ``delay`` clock seconds from now."""
        heapq.heappush(self.timers, Timer(self.arch.clock.now() + delay, next(self._seq), TimerKind.AT, None,
                                          data=trigger))

    def suspend_timer(self, i: Intention, deadline: float, ms: float = 0.0) -> None:
        self.suspend(i, Suspension.WAIT)
        i.pi_key = f"{i.id}/time{int(ms)}"
        # whole milliseconds in the reason, as Jason (its wait time is a long)
        i.wait_reason = Literal("wait", (float(i.id),), (Literal("time", (float(int(ms)),)),))
        heapq.heappush(self.timers, Timer(deadline, next(self._seq), TimerKind.WAIT, i))
        self._goal_waiting(i, i.wait_reason)

    def _goal_waiting(self, i: Intention, reason: Any) -> None:
        """Jason's intentionWaiting: the goal of the top means is ``waiting``."""
        top = i.top()
        if self.pl.goal_state_plans and top is not None and top.trigger.op == ADD and top.trigger.is_goal:
            self.goal_state(top.trigger, "waiting", reason)

    def _bind_elapsed(self, i: Intention) -> None:
        """``.wait(E, T, Elapsed)``: Elapsed gets the milliseconds the intention waited."""
        term, start = i.wait_elapsed
        i.wait_elapsed = None
        im = i.top()
        if im is not None:
            s2 = dict(im.u)
            if unify(term, float(int((self.arch.clock.now() - start) * 1000)), s2):
                im.u = s2

    def suspend_event_wait(self, i: Intention, trig: Trigger | None, cond: Any,
                           deadline: float | None) -> None:
        self.suspend(i, Suspension.EVENT_WAIT)
        i.pi_key = f"{i.id}/{trig if trig is not None else term_str(cond)}"
        what = trig.literal if trig is not None else cond
        i.wait_reason = Literal("wait", (float(i.id),), (what,))
        self._goal_waiting(i, i.wait_reason)
        self.event_waits.append(EventWait(trig, cond, i, i.top()))
        if deadline is not None:
            # the reason identifies this very wait: a timer of an earlier wait is stale
            heapq.heappush(self.timers, Timer(deadline, next(self._seq), TimerKind.EVENT_TIMEOUT, i,
                                              data=i.wait_reason))

    def register_ask(self, msg_id: str, i: Intention | None, answer: Any, deadline: float | None,
                     perf: str = "askOne", n: int | None = None) -> None:
        """An intention waits for the answer to ask ``msg_id`` (``n``: number of receivers when
        they were given as a list, then the answer is the list of their answers)."""
        if i is None:
            return
        self.suspend(i, Suspension.ASK)
        i.pi_key = msg_id
        self.ask_waits[msg_id] = AskWait(i, answer, perf, n)
        if deadline is not None:
            heapq.heappush(self.timers, Timer(deadline, next(self._seq), TimerKind.ASK_TIMEOUT, i,
                                              msg_id))

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
            self.arch.action_abandoned(self, aid)    # nobody waits for it: stop it
        if any(ev.intention is i for ev in self.events):
            self.events = deque(ev for ev in self.events if ev.intention is not i)
        if self.pending_events:
            self.pending_events = [p for p in self.pending_events if p.event.intention is not i]
        i.suspended = None
        i.sus_ia = False
        i.pi_key = None

    def remove_intention(self, i: Intention) -> None:
        self.detach(i)
        i.dropped = True
        i.ims.clear()

    def intention_finished(self, i: Intention, last: IntendedMeans) -> None:
        if i.reply is not None:
            q: Message = i.reply
            ans = _strip_sources(reasoning.means_answer(self, last))
            self.send_message(Message(self.name, q.sender, "tell", ans, in_reply_to=q.msg_id))

    def _goal_positions(self, pattern: Any, s: dict):
        for i in self.all_intentions():
            for idx in range(len(i.ims) - 1, -1, -1):
                t = i.ims[idx].trigger
                if t.op == ADD and t.type == ACHIEVE and unify(pattern, t.literal, dict(s), self):
                    yield i, idx
                    break

    def drop_goal(self, pattern: Any, s: dict, drop_events: bool) -> None:
        for i, _ in list(self._goal_positions(pattern, s)):
            self.remove_intention(i)
        if drop_events:
            def hit(ev: Event) -> bool:
                return (ev.trigger.op == ADD and ev.trigger.type == ACHIEVE
                        and unify(pattern, ev.trigger.literal, dict(s), self))
            self.events = deque(ev for ev in self.events if not hit(ev))
            if self.pending_events:
                self.pending_events = [p for p in self.pending_events if not hit(p.event)]

    def drop_all(self, events: bool, keep: Intention | None = None) -> None:
        """``.drop_all_intentions`` (events=False: only events of intentions go) or
        ``.drop_all_desires`` (every event goes). As in Jason, ``keep`` (the intention running
        the action: it is not in the queue of intentions at that moment) carries on."""
        for i in list(self.all_intentions()):
            if i is not keep:
                self.remove_intention(i)
        if events:
            self.events.clear()
            self.pending_events.clear()
        else:
            kept = [ev for ev in self.events if ev.intention is None or ev.intention is keep]
            self.events.clear()
            self.events.extend(kept)

    def _goal_events(self, pattern: Any, s: dict) -> list[Event]:
        """The queued ``+!G`` events (goals not intended yet) the pattern unifies with."""
        return [ev for ev in self.events if ev.trigger.op == ADD and ev.trigger.type == ACHIEVE
                and unify(pattern, ev.trigger.literal, dict(s))]

    def succeed_goal(self, pattern: Any, s: dict) -> None:
        for ev in self._goal_events(pattern, s):
            # jason.stdlib.succeed_goal on an event: it goes, as an achieved goal
            self.events.remove(ev)
            if self.pl.goal_state_plans:
                self.goal_state(ev.trigger, "achieved")
                self.goal_state(ev.trigger, "finished")
            i = ev.intention
            if i is not None:
                top = i.top()
                if top is not None and top.stack:
                    top.stack.pop()
                i.suspended = None
                reasoning.clr_int(self, i)
                if i.ims and not i.dropped and i.suspended is None:
                    self.running.append(i)
        for i, idx in list(self._goal_positions(pattern, s)):
            self._succeed_at(i, idx)

    def _succeed_at(self, i: Intention, idx: int) -> None:
        """The goal of ``i``'s ``idx``-th means is achieved: that means and those above go,
        the caller goes on after the deed that posted the goal."""
        was_current = i is self.current
        if self.pl.goal_state_plans:
            self.goal_state(i.ims[idx].trigger, "achieved")
            self.goal_state(i.ims[idx].trigger, "finished")
        self.detach(i)
        i.truncate(idx)
        if not i.ims:
            i.dropped = True
            return
        caller = i.ims[-1]
        if caller.stack:
            caller.stack.pop()
        if not was_current:
            reasoning.clr_int(self, i)
            if i.ims and i.suspended is None:
                self.running.append(i)

    def clear_satisfied_goals(self) -> None:
        """Jason 3's ClrSatInt: each goal whose plan has a goal condition (``<:``) that holds
        now (with the bindings the plan started with) is achieved, done or not."""
        for i in list(self.all_intentions()):
            if i.dropped:
                continue
            for idx in range(len(i.ims) - 1, -1, -1):
                im = i.ims[idx]
                if im.trigger_u is None:
                    continue
                for _ in solve(self, im.plan.goal_condition, im.trigger_u, i):
                    self._succeed_at(i, idx)
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
        pend = [i for i in self.suspended.values() if i is not current]
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
        for i in list(self.running):
            s2 = has_goal(i, pattern, s)
            if s2 is not None:
                s = s2
                self.running.remove(i)
                self.suspend(i, Suspension.SUSPENDED)
                i.sus_ia = True
                i.pi_key = f"suspended-{i.id}"
        own = False
        if current is not None:
            s2 = has_goal(current, pattern, s)
            if s2 is not None:
                s = s2
                own = True
                self.suspend(current, Suspension.SUSPENDED)
                current.sus_ia = True
                current.pi_key = f"suspended-self-{current.id}"
        if self.events:
            keep: deque = deque()
            c = 0
            for ev in self.events:
                s2 = event_has_goal(ev, pattern, s)
                if s2 is None:
                    keep.append(ev)
                    continue
                s = s2
                self.pending_events.append(PendingEvent(f"suspended-{ev.trigger}{c}", ev))
                c += 1
                if ev.intention is not None:
                    ev.intention.sus_ia = True
            self.events = keep
        self._goal_state_of(pattern, s, "suspended")
        return own, s

    def _goal_state_of(self, pattern: Any, s: dict, state: str) -> None:
        """The goal-state event of a goal ``.suspend``/``.resume`` handled (when bound)."""
        if self.pl.goal_state_plans:
            g = resolve(pattern, s)
            if isinstance(g, Literal):
                self.goal_state(Trigger(ADD, ACHIEVE, g.with_self_source()), state,
                                _SUSPEND_IA if state == "suspended" else "")

    def resume_goal(self, pattern: Any, s: dict) -> dict:
        """``.resume(G)`` (jason.stdlib.resume): intentions held in PI by ``.suspend`` go back
        to the running queue (in the order of Jason's PI map), the others only lose the mark;
        then the held events go back to the end of the event queue. One unifier serves all
        the matches (as in Jason); it is returned."""
        pi = [i for i in self.suspended.values() if i.pi_key is not None]
        for i in java_map_order(pi, lambda i: i.pi_key):
            if not i.sus_ia:
                continue
            s2 = has_goal(i, pattern, s)
            if s2 is None:
                continue
            s = s2
            i.sus_ia = False
            top = i.top()
            states = self.pl.goal_state_plans and top is not None and top.is_goal_add
            if states:
                self.goal_state(top.trigger, "resumed", _RESUME_IA)
            if (i.pi_key or "").startswith("suspended-"):
                i.pi_key = None
                if i.suspended is Suspension.SUSPENDED:
                    self.resume(i)
            elif states:
                self.goal_state(top.trigger, "waiting", i.wait_reason or "")   # still waiting
        for held in java_map_order(list(self.pending_events), lambda p: p.key):
            ev = held.event
            s2 = event_has_goal(ev, pattern, s)
            if s2 is None:
                continue
            s = s2
            if self.pl.goal_state_plans and ev.trigger.op == ADD and ev.trigger.is_goal:
                self.goal_state(ev.trigger, "resumed", _RESUME_IA)
            self.pending_events.remove(held)
            if ev.intention is not None:
                ev.intention.sus_ia = False
            if self.event_waits:
                self._check_event_waits(ev)
            self.events.append(ev)
        return s

    def fail_goal(self, pattern: Any, s: dict, annots: tuple = ()) -> None:
        """``.fail_goal(G)``: each goal G is failed (its ``-!G`` event gets ``annots``)."""
        for ev in self._goal_events(pattern, s):
            if ev.intention is not None:
                continue
            # jason.stdlib.fail_goal on an external event: it becomes the -!G event
            if self.pl.goal_state_plans:
                self.goal_state(ev.trigger, "failed", Literal("drop_by_fail_goal"))
            k = self.events.index(ev)
            lit = ev.trigger.literal
            self.events[k] = Event(Trigger(DEL, ACHIEVE, lit.add_annots(annots) if annots else lit))
        for i, idx in list(self._goal_positions(pattern, s)):
            reasoning.fail_goal_at(self, i, idx, annots)

    def schedule_deadline(self, trig: Trigger, i: Intention | None, delay: float) -> None:
        """A goal's ``hard_deadline``: ``delay`` clock seconds from now, the goal ``trig`` of
        intention ``i`` (None: a ``!!g``) fails if it is still pursued."""
        size = len(i.ims) if i is not None else 0
        heapq.heappush(self.timers, Timer(self.arch.clock.now() + delay, next(self._seq),
                                          TimerKind.DEADLINE, None, data=(trig, i, size)))

    def _deadline_reached(self, trig: Trigger, i: Intention | None, size: int) -> None:
        """Jason's hard deadline check: the goal is still desired (``!!g``), or its intention
        is as deep as it was and still has the goal; then it fails with ``deadline_reached``."""
        goal = trig.literal
        if i is None:
            drop = bool(self._goal_events(goal, {})) or any(True for _ in self._goal_positions(goal, {}))
        else:
            drop = (not i.dropped and len(i.ims) >= size
                    and any(im.trigger.op == ADD and im.trigger.type == ACHIEVE
                            and unify(goal, im.trigger.literal, {}, self) for im in i.ims))
        if drop:
            self.fail_goal(goal, {}, _DEADLINE_REACHED)

    # ================================================================ beliefs
    def add_event(self, ev: Event) -> None:
        """Queue an event; like Jason, an external event nobody listens to is only kept when
        some plan is relevant for it."""
        t = ev.trigger
        if self.pl.goal_state_plans and t.op == ADD and t.type == ACHIEVE and ev.intention is None:
            self.goal_state(t, "pending")
        if self.event_waits:
            self._check_event_waits(ev)
        elif (ev.intention is None and not (ev.trigger.is_goal and ev.trigger.op == ADD)
              and not self.pl.relevant(ev.trigger)):
            return
        self.events.append(ev)

    def _check_event_waits(self, ev: Event) -> None:
        t = ev.trigger
        keep = []
        woken = []
        for w in self.event_waits:
            trig = w.trigger
            if (trig is not None and trig.op == t.op and trig.type == t.type
                    and unify(trig.literal, t.literal, {}, self)):
                woken.append(w.intention)
                if w.intention.wait_elapsed is not None:
                    self._bind_elapsed(w.intention)
            else:
                keep.append(w)
        if woken:
            self.event_waits = keep
            for i in woken:
                self.resume(i)

    def check_cond_waits(self) -> None:
        if not any(w.condition is not None for w in self.event_waits):
            return
        keep = []
        for w in self.event_waits:
            cond, i, im = w.condition, w.intention, w.means
            if cond is not None and im is not None:
                sol = next(iter(solve(self, cond, im.u, i)), None)
                if sol is not None:
                    im.u = sol
                    if i.wait_elapsed is not None:
                        self._bind_elapsed(i)
                    self.resume(i)
                    continue
            keep.append(w)
        self.event_waits = keep

    def add_belief(self, lit: Literal, front: bool = True, focus: Intention | None = None) -> bool:
        """Add a belief (with its source annotations) and post the ``+b`` event if it is new.

        With ``focus`` (a plan body's ``+b``), the event is internal to that intention and is
        always queued; returns True when such an event was posted (the intention must wait).
        """
        added = self.bb.add(lit, front=front)
        return added is not None and self._belief_changed(ADD, added, focus)

    def remove_belief(self, lit: Literal, focus: Intention | None = None) -> bool:
        """Remove a belief; with ``focus`` the ``-b`` event is internal (see :meth:`add_belief`)."""
        removed = self.bb.remove(lit)
        return removed is not None and self._belief_changed(DEL, removed, focus)

    def replace_belief(self, lit: Literal, focus: Intention) -> bool:
        """``-+b`` in ``focus``'s plan body: remove the first belief ``b(...)`` holding all of
        ``lit``'s annotations (its ``-b`` event is external), then add ``lit`` (its ``+b``
        event belongs to ``focus``, as for :meth:`add_belief`). Returns True when that ``+b``
        event was posted (the intention must wait for it)."""
        bb = self.bb
        if self.event_waits:   # a .wait condition is checked after the removal and after the addition
            removed = bb.remove_first_holding(lit)
            if removed is not None:
                self._belief_changed(DEL, removed, None)
            added = bb.add(lit, front=True)
            return added is not None and self._belief_changed(ADD, added, focus)
        removed, added = bb.replace_first_holding(lit)
        if removed is not None and ((DEL, BELIEF, removed.functor, len(removed.args), removed.neg)
                                    in self.pl.by_key or self.pl.var_plans):
            self._belief_changed(DEL, removed, None)   # (not called when no plan would see it)
        if added is None or self._own_event_unseen(ADD, added, focus):
            return False
        self.events.append(Event(Trigger(ADD, BELIEF, added), focus))   # (_belief_changed inlined)
        return True

    def _own_event_unseen(self, op: str, lit: Literal, focus: Intention) -> bool:
        """True when the ``+b``/``-b`` event of a belief change in ``focus``'s plan body need
        not be posted, because posting it changes nothing the program can see: no plan is
        relevant for it, and the next cycle's deliberation would select it first (no other
        event is queued, nothing will be sensed before: no percepts, mail, feedback or timers)
        only to put ``focus`` back at the end of the running queue (Jason's Rel2 rule for an
        internal belief event), and the deed that cycle runs is plain (:attr:`Deed.plain`): it
        cannot see that selected event (``.intend`` and the like list its intention). The
        intention goes to the end of the queue at once instead: the same order, less work."""
        pl = self.pl
        if (self.events or self.event_waits or self._perceives or self._inbox or self._mail
                or self.timers or self.action_results or self.atomic_used or pl.var_plans
                or pl.goal_condition_plans or pl.goal_state_plans
                or (op, BELIEF, lit.functor, len(lit.args), lit.neg) in pl.by_key):
            return False
        ims = (self.running[0] if self.running else focus).ims
        if not ims:
            return False
        stack = ims[-1].stack
        return bool(stack) and stack[-1].plain

    def _belief_changed(self, op: str, lit: Literal, focus: Intention | None) -> bool:
        """Post the ``+b``/``-b`` event of a belief change (see :meth:`add_belief`)."""
        if focus is not None:
            if self._own_event_unseen(op, lit, focus):
                return False
            ev = Event(Trigger(op, BELIEF, lit), focus)
            if not self.event_waits:   # the common case: nobody waits for events
                self.events.append(ev)
                return True
            self._check_event_waits(ev)
            self.events.append(ev)
            if self.event_waits:
                self.check_cond_waits()
            return True
        if not self.event_waits and not self.pl.has_key((op, BELIEF, lit.functor, len(lit.args), lit.neg)):
            return True  # fast path: nobody would see the event
        self.add_event(Event(Trigger(op, BELIEF, lit)))
        if self.event_waits:
            self.check_cond_waits()
        return True

    def abolish(self, pattern: Any, s: dict | None = None) -> None:
        """``.abolish(P)`` (Jason's ``Agent.abolish``): every belief P unifies with (P's
        annotations a subset of the belief's, e.g. ``b(_)[source(ag1)]``) goes, all of it;
        a variable P (``_[source(a)]``) looks at every belief."""
        cands = list(self.bb.candidates(pattern.key)) if type(pattern) is Literal else list(self.bb)
        for b in cands:
            if isinstance(b, Literal) and unify(pattern, b, dict(s or {})):
                removed = self.bb.remove(b)
                if removed is not None:
                    self.add_event(Event(Trigger(DEL, BELIEF, removed)))

    # ================================================================ actions
    def start_action(self, i: Intention, im: IntendedMeans, deed: Any, action: Literal) -> int:
        aid = next(self._action_ids)
        self.pending_actions[aid] = PendingAction(i, im, action, deed)
        self.suspend(i, Suspension.ACTION)
        try:
            self.arch.act(self, action, aid)
        except Exception as e:
            self.action_feedback(aid, False, "action_failed", f"{type(e).__name__}: {e}")
        return aid

    def process_feedback(self, result: ActionResult) -> None:
        entry = self.pending_actions.pop(result.action_id, None)
        if entry is None:
            return
        i, im = entry.intention, entry.means
        if i.dropped or i.id not in self.suspended:
            return
        if not self.resume(i) or result.ok:
            return
        self.running.remove(i)
        kind = result.reason or "action_failed"
        annots = reasoning.error_annots(self, im, entry.deed, kind, result.message or "",
                                        code=entry.action, extra=result.annots)
        reasoning.fail_intention(self, i, annots=annots)

    # ================================================================ communication
    def send_message(self, msg: Message) -> None:
        if msg.receiver == self.name:
            self.receive(msg)
            return
        try:
            self.arch.send(self, msg)
        except Exception as e:
            raise IAError(f"cannot send to {msg.receiver}: {e}") from None

    def process_message(self, m: Message) -> None:
        """One message (Jason's ``TransitionSystem.applyProcMsg``): an answer resumes the
        intention that asked; a literal told/achieved/signalled is handled directly unless the
        program has its own ``kqml_received`` plans; anything else is a ``+!kqml_received``."""
        src = SOURCE_SELF if m.sender == self.name else source(m.sender)
        content = m.content
        if m.in_reply_to is not None and m.in_reply_to in self.ask_waits:
            self._ask_answer(m)
            return
        if m.in_reply_to is not None and m.in_reply_to.startswith("samid"):
            return  # an answer after the ask's timeout is ignored
        if self.accept_message is not None and not self.accept_message(self, m):
            return  # Jason's socAcc refused it
        perf = m.performative
        if (perf in ("tell", "achieve", "signal") and type(content) is Literal
                and not self._user_kqml_plans()):
            # TransitionSystem.applyProcMsg: the content's sources are nested in the sender's
            lit = with_nested_source(content, src.args[0])
            if perf == "tell":
                self.add_belief(lit, front=True)
            elif perf == "achieve":
                self.add_event(Event(Trigger(ADD, ACHIEVE, lit)))
            else:
                self.add_event(Event(Trigger(ADD, BELIEF, lit)))
            return
        if perf == "tell" and type(content) is ListTerm and not self._user_kqml_plans():
            self._tell_all(content, src)
            return
        sender = Literal("self") if m.sender == self.name else Literal(m.sender)
        received = Literal("kqml_received", (sender, Literal(perf), content, Literal(m.msg_id)))
        self.add_event(Event(Trigger(ADD, ACHIEVE, received)))

    def _tell_all(self, content: ListTerm, src: Literal) -> None:
        """A ``tell`` of a list, as the default plans do it (each ground literal is added with
        the sender's source, the rest is skipped) but in one pass: linear in the list's length."""
        items: Any = content
        while type(items) is ListTerm:
            for item in items.items:
                if type(item) is Literal and (item.known_ground or is_ground(item)):
                    self.add_belief(item.add_annots([src]), front=True)
            items = items.tail

    def _user_kqml_plans(self) -> bool:
        """Jason's ``PlanLibrary.hasUserKqmlReceivedPlans``."""
        return any(p.src != KQML_SRC for p in self.pl.relevant(_KQML_RECEIVED))

    def _ask_answer(self, m: Message) -> None:
        """The answer to a ``.send(R, askOne|askAll, C, A)`` that suspended an intention: an
        untell of an askOne is ``false``, a literal (each literal of an askAll list) gets the
        sender's source; with a list of receivers ``A`` is the list of all the answers."""
        mid = m.in_reply_to
        assert mid is not None      # only answers (in_reply_to set) come here
        wait = self.ask_waits[mid]
        i, ans, perf, n, got = wait.intention, wait.answer, wait.performative, wait.receivers, wait.answers
        sender = Literal(m.sender)
        # the answer's variables are not the asker's (Jason's messages are copied as text)
        content = rename_vars(m.content, {})
        if m.performative == "untell" and perf == "askOne":
            content = FALSE
        elif isinstance(content, Literal) or (perf == "askAll" and isinstance(content, ListTerm)):
            # TransitionSystem: the answer's sources are nested in source(Sender)
            content = with_nested_source(content, sender)
        elif perf == "askHow" and isinstance(content, ListTerm):
            content = plans_answered_by(content, m.sender)   # labelled source(Sender)
        if n is not None:
            got.append(content)
            if len(got) < n:
                return
            content = make_list(got)
        del self.ask_waits[mid]
        self._resume_ask(i, ans, content)

    def _resume_ask(self, i: Intention, ans: Any, content: Any) -> None:
        """Unify the answer with the ``.send``'s fourth argument and resume the intention;
        when they do not unify the intention fails with ``ask_failed`` (resumeSyncAskIntention)."""
        im = i.top()
        if i.dropped or i.id not in self.suspended or im is None:
            return
        s2 = dict(im.u)
        if unify(ans, content, s2, self):
            im.u = s2
            self.resume(i)
        elif self.resume(i):
            self.running.remove(i)
            msg = (f"reply of an ask message ('{term_str(content)}') does not unify with fourth "
                   f"argument of .send ('{term_str(resolve(ans, im.u, self))}')")
            reasoning.fail_intention(self, i, annots=reasoning.error_annots(
                self, im, im.current, "ask_failed", msg))


#: what an intention waits for when its own event is queued (it is not blocking then)
_OWN_EVENT_WAITS = frozenset({None, Suspension.SUBGOAL, Suspension.EVENT, Suspension.FAILURE})

#: the annotations of a goal failed by its hard_deadline (Jason's basic error annotations)
_DEADLINE_REACHED = (Literal("error", (Literal("deadline_reached"),)), Literal("error_msg", ("",)))

_JAG_SLEEPING = Trigger(ADD, BELIEF, Literal("jag_sleeping"))
_JAG_AWAKING = Trigger(ADD, BELIEF, Literal("jag_awaking"))

#: the event of a message handled by (default or user) plans
_KQML_RECEIVED = Trigger(ADD, ACHIEVE, Literal("kqml_received", (Literal("s"), Literal("p"),
                                                                  Literal("c"), Literal("m"))))


def load_agent_source(path: str | os.PathLike) -> str:
    """Read an ``.asl`` file (UTF-8); text that is not UTF-8 raises :class:`AslSyntaxError`
    at the first bad byte (``file:line:col: ...``)."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise AslSyntaxError(str(path), line, col,
                             f"not UTF-8 text (byte 0x{data[e.start]:02x}); save the file as UTF-8") from None


__all__ = ["Agent", "AgentOptions", "load_agent_source", "merge_annots"]
