"""A thread that brings input to a sleeping agent reasons on it itself (``run_here``)."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager

from asl_helpers import RecordingArch, run_until_idle
from polling import wait_until

from rason.asl import Agent, Message, WallClock, parse_literal
from rason.asl.runner import TURN_STEPS


def _hi() -> Message:
    return Message("bob", "m", "achieve", parse_literal("hi"))


@contextmanager
def sleeping_agent(source: str, arch: RecordingArch) -> Iterator[tuple[Agent, threading.Thread]]:
    """An agent on `arch` whose runner thread has gone to sleep (nothing to do)."""
    arch.clock = WallClock()
    agent = Agent("m", source, arch)
    stop = threading.Event()
    runner = threading.Thread(target=agent.run, args=(stop,), daemon=True)
    runner.start()
    try:
        # past its last cycle, into its wait: it has set its wake-up time and let go of the turn
        wait_until(lambda: agent.runner.asleep_until is not None and not agent.runner.turn.locked(),
                   "the runner asleep", period=0.002)
        assert agent.is_idle()
        yield agent, runner
    finally:
        stop.set()
        runner.join(2)
        assert not runner.is_alive()


@contextmanager
def running(source: str) -> Iterator[tuple[Agent, RecordingArch]]:
    """A sleeping agent on a :class:`RecordingArch`."""
    arch = RecordingArch()
    with sleeping_agent(source, arch) as (agent, _runner):
        yield agent, arch


def test_a_message_to_a_sleeping_agent_is_reasoned_on_before_receive_returns() -> None:
    with running("+!hi[source(S)] <- .print(hi, S).") as (agent, arch):
        agent.receive(_hi(), run_here=True)
        assert arch.out == ["hibob"]           # no hand-over to the runner: done already
        agent.receive(_hi(), run_here=True)
        assert arch.out == ["hibob", "hibob"]


def test_without_run_here_the_runner_reasons_later() -> None:
    with running("+!hi[source(S)] <- .print(hi, S).") as (agent, arch):
        agent.receive(_hi())
        wait_until(lambda: arch.out == ["hibob"], "the runner's line", period=0.002)


def test_an_agent_whose_runner_is_not_running_keeps_the_message_for_it() -> None:
    arch = RecordingArch()
    agent = Agent("m", "+!hi[source(S)] <- .print(hi, S).", arch)
    agent.receive(_hi(), run_here=True)
    assert arch.out == [] and agent.runner.has_input()
    run_until_idle(agent)
    assert arch.out == ["hibob"]


def test_a_deadline_made_on_the_bringing_thread_wakes_the_runner_for_it() -> None:
    with running("+!hi <- .print(start); .wait(60); .print(done).") as (agent, arch):
        start = time.monotonic()
        agent.receive(_hi(), run_here=True)
        assert arch.out == ["start"]           # the rest waits for the .wait's deadline
        wait_until(lambda: arch.out == ["start", "done"], "the line after .wait", period=0.002)
        assert time.monotonic() - start >= 0.06


def test_a_long_turn_is_handed_to_the_runner() -> None:
    steps = 10 * TURN_STEPS
    source = f"+!hi <- !count(0).\n+!count(N) : N < {steps} <- !count(N + 1).\n+!count(N) <- .print(N)."
    with running(source) as (agent, arch):
        agent.receive(_hi(), run_here=True)
        assert arch.out == []                  # the bringing thread stopped after TURN_STEPS
        wait_until(lambda: arch.out == [str(steps)], "the runner's count", period=0.002)


class _PokedArch(RecordingArch):
    """Records which thread printed each line; printing "poke" brings the runner other input."""

    def __init__(self) -> None:
        super().__init__()
        self.agent: Agent | None = None
        self.printed_by: list[tuple[str, int]] = []

    def console(self, agent_name: str, text: str) -> None:
        super().console(agent_name, text)
        self.printed_by.append((text, threading.get_ident()))
        if text == "poke" and self.agent is not None:
            self.agent.wake()


def test_input_for_the_runner_ends_a_turn_after_the_current_cycle() -> None:
    arch = _PokedArch()
    with sleeping_agent("+!hi <- .print(poke); .print(b); .print(c).", arch) as (agent, runner):
        arch.agent = agent
        agent.receive(_hi(), run_here=True)
        wait_until(lambda: arch.out == ["poke", "b", "c"], "the three lines", period=0.002)
        by = dict(arch.printed_by)
        assert by["poke"] == threading.get_ident()      # the bringing thread began
        assert by["b"] == by["c"] == runner.ident       # and gave way at the next cycle


class _HeldArch(_PokedArch):
    """Printing "hold" blocks the printing thread until the test lets it go."""

    def __init__(self) -> None:
        super().__init__()
        self.holding = threading.Event()
        self.let_go = threading.Event()

    def console(self, agent_name: str, text: str) -> None:
        super().console(agent_name, text)
        if text == "hold":
            self.holding.set()
            assert self.let_go.wait(3)


def test_input_brought_during_another_threads_turn_is_left_to_that_turn() -> None:
    arch = _HeldArch()
    source = "+!hi <- .print(hold).\n+!second <- .print(second)."
    with sleeping_agent(source, arch) as (agent, _runner):
        first = threading.Thread(target=agent.receive, args=(_hi(), True))
        first.start()
        try:
            assert arch.holding.wait(3)                # the first bringer reasons, held mid-turn
            agent.receive(Message("bob", "m", "achieve", parse_literal("second")), run_here=True)
            assert "second" not in arch.out            # left to the turn under way, not run here
        finally:
            arch.let_go.set()
        first.join(3)
        assert arch.out == ["hold", "second"]          # done by the time the first bringer returns
        assert dict(arch.printed_by)["second"] == first.ident    # not handed to the runner
