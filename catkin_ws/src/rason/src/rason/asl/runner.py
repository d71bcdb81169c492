"""Threads and turns of an agent: its inbox (messages, action feedback, wake-ups, from any
thread), the reasoning cycle (``step``), its runner thread (``run``) and the turns of the
threads that bring input while the runner sleeps; the agent's sleep (Jason's ``jag_sleeping``)."""

from __future__ import annotations

import math
import threading
from collections import deque
from typing import TYPE_CHECKING, Any

from . import reasoning
from .arch import Message
from .intentions import ActionResult, Event
from .plans import ADD, BELIEF, Trigger
from .terms import Literal

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent

#: cycles a thread that brought input runs for a sleeping agent before handing over to the
#: agent's runner (see Runner.take_turns)
TURN_STEPS = 64

_JAG_SLEEPING = Trigger(ADD, BELIEF, Literal("jag_sleeping"))
_JAG_AWAKING = Trigger(ADD, BELIEF, Literal("jag_awaking"))


class Runner:
    """Runs the reasoning cycles of the agent ``ag``, one at a time, on its runner thread or
    on a thread that brought input while the runner slept.

    ``receive``, ``action_feedback`` and ``wake`` may be called from any thread.
    """

    def __init__(self, ag: Agent) -> None:
        self.ag = ag
        self.inbox: deque[ActionResult | None] = deque()   # action feedback; None: a wake-up
        self.mail: deque[Message] = deque()                # messages, one taken per cycle
        self.inbox_lock = threading.Lock()
        self.wake_event = threading.Event()
        # held by the thread running reasoning cycles: the agent's runner, or a thread that
        # brought input while the runner slept (see take_turns)
        self.turn = threading.Lock()
        # the runner's wake-up time while it sleeps (math.inf: none), None while it is awake;
        # written with turn held
        self.asleep_until: float | None = None
        self.runner_stop: threading.Event | None = None   # the running runner's stop event
        self.caller_turn = False     # a thread that brought input holds turn (see take_turns)
        #: held during a reasoning cycle (a mind snapshot takes it too)
        self.state_lock = threading.RLock()
        #: idle (Jason's sleeping agent): +jag_sleeping / +jag_awaking events for plans that want them
        self.sleeping = False
        #: called (from any thread) whenever input arrives; a runner may use it to wake up
        self.on_wake: Any = None

    # ================================================================ input, any thread
    def receive(self, message: Message, run_here: bool = False) -> None:
        """Queue an incoming message and wake the agent; with ``run_here`` a caller that finds
        the agent's runner asleep reasons on it itself (:meth:`take_turns`)."""
        with self.inbox_lock:
            self.mail.append(message)
        self._input_arrived(run_here)

    def action_feedback(self, result: ActionResult, run_here: bool = False) -> None:
        """Queue the result of an action (``run_here``: as for :meth:`receive`)."""
        with self.inbox_lock:
            self.inbox.append(result)
        self._input_arrived(run_here)

    def wake(self) -> None:
        """Something changed (e.g. new percepts); run a cycle soon."""
        with self.inbox_lock:
            self.inbox.append(None)
        self._input_arrived(False)

    def _input_arrived(self, run_here: bool) -> None:
        if run_here and self.take_turns():
            return
        self.wake_event.set()
        if self.on_wake is not None:
            self.on_wake()

    def has_input(self) -> bool:
        """Messages, feedback or wake-ups wait in the inbox."""
        with self.inbox_lock:
            return bool(self.inbox or self.mail)

    def take_input(self) -> bool:
        """In a cycle: all action feedback and wake-ups, but (like Jason) one message. True
        when there was any."""
        with self.inbox_lock:
            items = list(self.inbox)
            self.inbox.clear()
            message = self.mail.popleft() if self.mail else None
        did = False
        results = self.ag.circ.action_results
        for it in items:
            did = True
            if type(it) is ActionResult:
                results.append(it)
        if message is not None:
            did = True
            self.ag.comm.process_message(message)
        return did

    # ================================================================ turns
    def take_turns(self) -> bool:
        """Reason on the calling thread, now, if the agent's runner (:meth:`run`) sleeps.

        A thread that brings input to a sleeping agent (a ROS node's receiving thread) runs the
        cycles it causes itself, instead of waking the runner and leaving the CPU to it: on a
        loaded machine that second thread waited for a core behind every other process woken
        by the same broadcast. Cycles still run one at a time (``turn``): input brought while
        another such thread reasons is left to it (it looks for more input once it has let go
        of the turn). True when the input is dealt with and the runner sleeps on; False when
        the runner must take over (see :meth:`_turn_cycles`).
        """
        while True:
            if self.asleep_until is None:
                return False                      # the runner is awake, or not running
            if not self.turn.acquire(blocking=False):
                # a thread that brought input before this one reasons: it finds this input
                # when it lets go (below); the runner, about to sleep or wake, is woken
                return self.caller_turn
            try:
                self.caller_turn = True
                handled = self._turn_cycles()
            finally:
                self.caller_turn = False
                self.turn.release()
            if not handled:
                return False
            if not self.has_input():
                return True
            # input was brought while this thread reasoned and found the turn taken

    def _turn_cycles(self) -> bool:
        """The cycles of a bringing thread's turn (``turn`` held): True when the agent is idle
        and the runner may sleep on; False when the runner must take over: it woke, or was woken
        meanwhile (other input, a stop: the turn ends after the cycle under way), the agent is
        still busy after :data:`TURN_STEPS` cycles, or a timer now falls due before the
        runner's wake-up time."""
        asleep_until = self.asleep_until
        stop = self.runner_stop
        if asleep_until is None or stop is None:
            return False                          # the runner woke, or has not started
        for _ in range(TURN_STEPS):
            if self.wake_event.is_set() or stop.is_set() or self.ag.stop_requested:
                return False
            if not self.step():
                break
        else:
            return False                          # still busy: its runner goes on
        deadline = self.ag.circ.next_deadline()
        return deadline is None or deadline >= asleep_until

    def run(self, stop: threading.Event) -> None:
        """Reason until ``stop`` is set; block (no polling) while idle."""
        def watcher() -> None:
            stop.wait()
            self.wake_event.set()
        ag = self.ag
        threading.Thread(target=watcher, name=f"{ag.name}-stop", daemon=True).start()
        clock = ag.arch.clock
        self.runner_stop = stop
        while not stop.is_set() and not ag.stop_requested:
            sleep, deadline = self._runner_turn(stop)
            if sleep:
                clock.wait(self.wake_event, deadline)
        with self.turn:
            self.asleep_until = None

    def _runner_turn(self, stop: threading.Event) -> tuple[bool, float | None]:
        """One cycle of the runner, holding the turn: (whether it may sleep now, until when)."""
        with self.turn:
            self.asleep_until = None
            self.wake_event.clear()
            if self.step() or stop.is_set() or self.has_input():
                return False, None
            deadline = self.ag.circ.next_deadline()
            self.asleep_until = math.inf if deadline is None else deadline
            return True, deadline

    # ================================================================ the cycle
    def step(self) -> bool:
        """One reasoning cycle; True if it did anything."""
        ag = self.ag
        c = ag.circ
        with self.state_lock:
            try:
                # each stage is skipped (one test) when it has nothing to do: a busy agent
                # without an environment or mail pays no call for sensing
                did = False
                if ag.perceives or self.inbox or self.mail or c.timers:
                    if self.sleeping and (self.inbox or self.mail):
                        self.wake_up()   # as Jason: +jag_awaking before what woke the agent
                    did = ag.sense()
                    if did and self.sleeping:
                        self.wake_up()
                if c.events or c.goal_state_events:
                    did = reasoning.deliberate(ag) or did
                else:
                    c.selected_event = None
                if c.running or c.action_results or ag.pl.goal_condition_plans:
                    did = reasoning.act(ag) or did
                if not did and not self.sleeping and not c.events and not c.running:
                    did = self._fall_asleep()
            except Exception as e:  # a bug or an odd program must not kill the agent
                ag.log(f"internal error in the reasoning cycle ({type(e).__name__}: {e}); "
                       "the event/intention at hand was dropped")
                if c.current is not None:
                    c.remove_intention(c.current)
                    c.current = None
                return True
            return did

    def is_idle(self) -> bool:
        """No events, no runnable intention, nothing in the inbox."""
        return not self.has_input() and self.ag.circ.is_idle()

    def _fall_asleep(self) -> bool:
        """Nothing to do: the agent sleeps; with a ``+jag_sleeping`` plan (Jason's sleep
        event), that event is posted. Returns True when it was."""
        self.sleeping = True
        if self.ag.pl.has_key(_JAG_SLEEPING.key):
            self.ag.circ.events.append(Event(_JAG_SLEEPING))
            return True
        return False

    def wake_up(self) -> None:
        """Input arrived while asleep: ``+jag_awaking`` (when a plan wants it)."""
        self.sleeping = False
        if self.ag.pl.has_key(_JAG_AWAKING.key):
            self.ag.circ.events.append(Event(_JAG_AWAKING))
