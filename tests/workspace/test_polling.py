"""The one deadline poll, rosnode_kit.polling, and tests/polling.py's wait_until built on it,
without ROS: wait_until imports nothing of rason, returns what the probe found, and fails early,
naming the process, when a watched one exits; the poll's looks are counted on a fake clock that
only its fake sleep moves (instant)."""

from __future__ import annotations

import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from polling import wait_until

from rosnode_kit.polling import Deadline, poll, watching

TESTS = Path(__file__).resolve().parents[1]


class Exited:
    """A watched process that has exited (what wait_until reads of one)."""

    name = "agent"

    def __init__(self) -> None:
        self.popen = subprocess.Popen([sys.executable, "-c", "raise SystemExit(4)"])
        self.popen.wait()

    def alive(self) -> bool:
        return self.popen.poll() is None

    def output(self) -> str:
        return "last words"


def test_polling_imports_nothing_of_rason():
    check = ("import sys; sys.path.insert(0, sys.argv[1]); import polling; "
             "print(sorted(m for m in sys.modules if m.split('.')[0].startswith('rason')))")
    done = subprocess.run([sys.executable, "-c", check, str(TESTS)], capture_output=True,
                          text=True, timeout=60, check=True)
    assert done.stdout.strip() == "[]"


def test_wait_until_returns_what_the_probe_found():
    looks = iter([None, 0, "found"])
    assert wait_until(lambda: next(looks), "the third look") == "found"


def test_a_watched_process_that_exits_ends_the_wait_with_its_output():
    with pytest.raises(AssertionError, match=r"agent exited \(4\) while waiting for a reply:"
                                             r"\nlast words"):
        wait_until(lambda: None, "a reply", timeout=600, watch=[Exited()])


def test_wait_until_fails_naming_what_it_waited_for():
    with pytest.raises(AssertionError, match=r"^no topic /x within 0\.0 s$"):
        wait_until(lambda: None, "topic /x", timeout=0.0)


@dataclass
class FakeTime:
    """A clock that moves only when someone sleeps on it."""

    now: float = 100.0
    sleeps: list[float] = field(default_factory=list)

    def clock(self) -> float:
        return self.now

    def sleep(self, seconds: float) -> None:
        self.sleeps.append(seconds)
        self.now += seconds


@dataclass
class FakePopen:
    returncode: int | None = None


@dataclass
class FakeProcess:
    """What a wait watches: the harness's Process has these."""

    name: str
    running: bool = True
    popen: FakePopen = field(default_factory=FakePopen)

    def alive(self) -> bool:
        return self.running

    def output(self) -> str:
        return "x" * 5000 + "the last words"


def counting(answers: list[object]):
    """A probe giving ``answers`` in turn (the last one again once they run out), and its calls."""
    calls: list[int] = []

    def probe() -> object:
        calls.append(1)
        return answers[min(len(calls), len(answers)) - 1]
    return probe, calls


def test_poll_returns_the_first_true_answer_at_once():
    fake = FakeTime()
    probe, calls = counting(["found"])
    assert poll(probe, 5.0, 0.5, clock=fake.clock, sleep=fake.sleep) == "found"
    assert len(calls) == 1 and fake.sleeps == []


def test_poll_asks_every_period_until_an_answer():
    fake = FakeTime()
    probe, calls = counting([None, 0, [], "third time"])
    assert poll(probe, 5.0, 0.25, clock=fake.clock, sleep=fake.sleep) == "third time"
    assert len(calls) == 4 and fake.sleeps == [0.25] * 3


def test_poll_gives_the_last_false_answer_once_the_timeout_passed():
    fake = FakeTime()
    probe, calls = counting([[]])
    assert poll(probe, 1.0, 0.25, clock=fake.clock, sleep=fake.sleep) == []
    # looks at 0, 0.25, 0.5, 0.75 and 1.0 s: the last one is at the deadline
    assert len(calls) == 5 and fake.now == pytest.approx(101.0)


def test_poll_with_no_time_looks_once():
    fake = FakeTime()
    probe, calls = counting([False])
    assert poll(probe, 0.0, 0.25, clock=fake.clock, sleep=fake.sleep) is False
    assert len(calls) == 1 and fake.sleeps == []


def test_stop_ends_the_wait_early_with_the_last_answer():
    fake = FakeTime()
    probe, calls = counting([0])
    stopped = iter([False, False, True])
    assert poll(probe, 60.0, 0.1, stop=lambda: next(stopped), clock=fake.clock,
                sleep=fake.sleep) == 0
    assert len(calls) == 3 and len(fake.sleeps) == 2


def test_check_runs_after_each_false_answer_and_may_end_the_wait():
    fake = FakeTime()
    proc = FakeProcess("robot")
    probe, calls = counting([None])

    def probe_then_exit() -> object:
        if len(calls) == 2:
            proc.running, proc.popen.returncode = False, 2
        return probe()

    with pytest.raises(RuntimeError) as err:
        poll(probe_then_exit, 60.0, 0.1, check=watching([proc], "the answer", RuntimeError),
             clock=fake.clock, sleep=fake.sleep)
    text = str(err.value)
    assert text.startswith("robot exited (2) while waiting for the answer:\n")
    assert text.endswith("the last words") and len(text) < 3100      # the end of the output
    assert len(calls) == 3


def test_watching_a_running_process_lets_the_wait_go_on():
    fake = FakeTime()
    probe, calls = counting([None, None, "up"])
    check = watching([FakeProcess("a"), FakeProcess("b")], "up")
    assert poll(probe, 9.0, 1.0, check=check, clock=fake.clock, sleep=fake.sleep) == "up"
    assert len(calls) == 3


def test_a_deadline_counts_down_and_never_below_zero():
    fake = FakeTime()
    deadline = Deadline(2.0, fake.clock)
    assert deadline.remaining() == 2.0 and not deadline.passed()
    fake.sleep(1.5)
    assert deadline.remaining() == pytest.approx(0.5) and not deadline.passed()
    fake.sleep(1.0)
    assert deadline.remaining() == 0.0 and deadline.passed()


def test_the_poll_needs_no_rospy():
    code = "import sys, rosnode_kit.polling; print('rospy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout
    assert out.strip() == "False"
