"""A rospy.Timer that sleeps while there is nothing to watch.

A ``rospy.Timer`` wakes its thread at its rate for the life of the node. A decomposer's
watchdog has work only while an action runs; in a fleet of twenty idle decomposers the ticks
alone cost a tenth of a core. :class:`Ticker` calls its callback at the rate, in ROS time (so a
simulator's ``/clock`` paces it), only while ``active()`` is true, and otherwise blocks without
waking until :meth:`Ticker.kick` says it may have become active.
"""

from __future__ import annotations

import threading
from collections.abc import Callable

import rospy


class Ticker:
    """Calls ``callback()`` every ``1/rate`` s of ROS time while ``active()`` is true.

    Whoever makes ``active()`` true calls :meth:`kick`; the first tick then comes one period
    later. The thread is a daemon and ends with the node.
    """

    def __init__(self, rate: float, callback: Callable[[], None], active: Callable[[], bool],
                 name: str = "ticker") -> None:
        self.rate = rate
        self._callback = callback
        self._active = active
        self._wake = threading.Event()
        rospy.on_shutdown(self._wake.set)
        self._thread = threading.Thread(target=self._run, name=name, daemon=True)
        self._thread.start()

    def kick(self) -> None:
        """``active()`` may have become true: start ticking if it is."""
        self._wake.set()

    def _run(self) -> None:
        while not rospy.is_shutdown():
            self._wake.clear()          # before the test: a kick after it is not lost
            if not self._active():
                self._wake.wait()
                continue
            period = rospy.Rate(self.rate)
            while self._active():
                try:
                    period.sleep()
                except rospy.ROSTimeMovedBackwardsException:   # a simulator restarted
                    period = rospy.Rate(self.rate)
                    continue
                except rospy.ROSInterruptException:
                    return
                if rospy.is_shutdown():
                    return
                self._callback()
