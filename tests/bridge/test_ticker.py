"""rason.ros.ticker.Ticker: a ROS-time timer that ticks only while it has something to watch."""

from __future__ import annotations

import threading
import time

from rason.ros.ticker import Ticker


def test_ticks_only_while_active_and_starts_when_kicked(ros) -> None:
    ros.init_rospy()
    active = threading.Event()
    ticks: list[float] = []
    ticker = Ticker(50.0, lambda: ticks.append(time.monotonic()), active.is_set, name="test-ticker")
    time.sleep(0.3)
    assert ticks == []                     # nothing to watch: not one tick

    active.set()
    ticker.kick()
    deadline = time.monotonic() + 5.0
    while len(ticks) < 5 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert len(ticks) >= 5                 # active: it ticks

    active.clear()
    time.sleep(0.1)                        # the tick under way, if any, ends
    settled = len(ticks)
    time.sleep(0.3)
    assert len(ticks) == settled           # inactive again: it sleeps

    active.set()                           # active without a kick: it does not poll to find out
    time.sleep(0.3)
    assert len(ticks) == settled
    ticker.kick()
    deadline = time.monotonic() + 5.0
    while len(ticks) == settled and time.monotonic() < deadline:
        time.sleep(0.01)
    assert len(ticks) > settled
    active.clear()
