"""rason.ros.ticker.Ticker: a ROS-time timer that ticks only while it has something to watch."""

from __future__ import annotations

import threading

from polling import wait_until

from rason.ros.ticker import Ticker

RATE = 50.0
#: periods of the reference ticker that stand for "a while" in the negative checks
PERIODS = 15


class Watched:
    """The ticker's ``active()``: an event, counting how often the ticker asked."""

    def __init__(self) -> None:
        self.event = threading.Event()
        self.asked: list[bool] = []

    def __call__(self) -> bool:
        answer = self.event.is_set()
        self.asked.append(answer)
        return answer


def test_ticks_only_while_active_and_starts_when_kicked(ros) -> None:
    ros.init_rospy()
    # a reference ticker at the same rate, always active: its ticks show that ROS time passed
    # long enough for the ticker under test to have ticked (or polled) had it been going to
    reference: list[None] = []
    Ticker(RATE, lambda: reference.append(None), lambda: True, name="reference-ticker")

    def periods_pass() -> None:
        start = len(reference)
        wait_until(lambda: len(reference) >= start + PERIODS, f"{PERIODS} reference ticks")

    active = Watched()
    ticks: list[int] = []
    ticker = Ticker(RATE, lambda: ticks.append(len(ticks)), active, name="test-ticker")
    wait_until(lambda: active.asked, "the ticker's first look")
    periods_pass()
    assert ticks == [] and active.asked == [False]    # nothing to watch: not one tick, no poll

    active.event.set()
    ticker.kick()
    wait_until(lambda: len(ticks) >= 5, "5 ticks")      # active: it ticks

    active.event.clear()
    # the tick loop's look, then the idle loop's: it blocks until kicked
    wait_until(lambda: active.asked[-2:] == [False, False], "the ticker to see it is inactive")
    settled, looks = len(ticks), len(active.asked)
    ticker.kick()                                       # a kick while inactive: one look, no tick
    wait_until(lambda: len(active.asked) > looks, "the ticker's look after the kick")
    periods_pass()
    assert len(ticks) == settled and active.asked[looks:] == [False]

    active.event.set()                     # active without a kick: it does not poll to find out
    periods_pass()
    assert len(ticks) == settled and len(active.asked) == looks + 1
    ticker.kick()
    wait_until(lambda: len(ticks) > settled, "a tick after the kick")
    active.event.clear()
