"""Warnings about bad input from the ROS graph, with bounded memory and rate.

A node that logs every malformed perception or message in full, and remembers each one forever,
can be flooded by one faulty publisher. :class:`BadInputLog` logs each distinct input once (it
remembers a bounded number of them), at most once per period per group (a perception source, a
sender), and truncates what it shows; the warnings it held back are counted in the next one.
"""

from __future__ import annotations

import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass

#: how much of an offending text a warning shows
MAX_SHOWN = 200
#: the longest warning line logged (a huge malformed input must not flood the log)
MAX_LINE = 600


def shorten(text: str, limit: int = MAX_SHOWN) -> str:
    """``text`` cut to ``limit`` characters (``...`` and the full length when cut)."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters)"


@dataclass
class _Group:
    """When a group last warned, and how many of its warnings were held back since."""

    last: float | None = None
    held_back: int = 0


class BadInputLog:
    """Rate-limited, memory-bounded warnings about bad input.

    Args:
        log: where a warning goes (e.g. ``rospy.logwarn``).
        now: the clock, in seconds (ROS time in nodes).
        period: at most one warning per group in this many seconds.
        remember: how many distinct inputs (and groups) are remembered.
    """

    def __init__(self, log: Callable[[str], None], now: Callable[[], float] = time.monotonic,
                 period: float = 1.0, remember: int = 256) -> None:
        self.log = log
        self.now = now
        self.period = period
        self.remember = remember
        self._seen: OrderedDict[tuple[str, str], None] = OrderedDict()
        self._groups: OrderedDict[str, _Group] = OrderedDict()
        self.logged = 0

    def warn(self, group: str, key: str | None, text: str) -> bool:
        """Warn ``text`` about input ``key`` of ``group``, unless that input was already warned
        about or the group warned less than ``period`` ago. Returns True if it was logged.

        ``key`` None: no input to remember, only the group's rate limit applies (a recurring
        kind of failure is warned about again every period).
        """
        if key is not None:
            seen_key = (group, key)
            if seen_key in self._seen:
                self._seen.move_to_end(seen_key)
                return False
            self._seen[seen_key] = None
            if len(self._seen) > self.remember:
                self._seen.popitem(last=False)
        now = self.now()
        g = self._groups.get(group)
        if g is None:
            g = self._groups[group] = _Group()
            if len(self._groups) > self.remember:
                self._groups.popitem(last=False)
        elif g.last is not None and 0 <= now - g.last < self.period:
            g.held_back += 1
            return False
        self._groups.move_to_end(group)
        g.last = now
        if g.held_back:
            text += f" ({g.held_back} similar warnings held back)"
            g.held_back = 0
        self.logged += 1
        self.log(shorten(text, MAX_LINE))
        return True
