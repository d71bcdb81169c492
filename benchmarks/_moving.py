"""Shared by the simulator benchmarks (a name starting with ``_`` is not a benchmark)."""

from __future__ import annotations

import contextlib
import threading
import time
from collections.abc import Iterator

#: (m/s, rad/s) per robot: Faulty drives a curve, Helper turns, so every Kinect frame is a
#: fresh picture (a still scene is not re-rendered)
COMMANDS = {"faulty": (0.3, 0.3), "helper": (0.0, 0.4)}


@contextlib.contextmanager
def robots_moving(ns: str, period: float = 0.05) -> Iterator[None]:
    """Keep both robots of the simulator under `ns` moving while the block runs (the simulator
    stops a robot whose last command is over 0.6 s old)."""
    import rospy
    from geometry_msgs.msg import Twist

    pubs = {name: rospy.Publisher(f"{ns}/{name}/mobile_base/commands/velocity", Twist,
                                  queue_size=1) for name in COMMANDS}
    stop = threading.Event()

    def command() -> None:
        while not stop.is_set():
            for name, (v, w) in COMMANDS.items():
                msg = Twist()
                msg.linear.x, msg.angular.z = v, w
                pubs[name].publish(msg)
            time.sleep(period)

    driver = threading.Thread(target=command, daemon=True)
    driver.start()
    try:
        yield
    finally:
        stop.set()
        driver.join()
        for pub in pubs.values():
            pub.unregister()
