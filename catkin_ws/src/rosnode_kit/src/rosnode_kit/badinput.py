"""Warnings about bad input from the ROS graph, with bounded memory and rate.

A node that logs every malformed perception or message in full, and remembers each one forever,
can be flooded by one faulty publisher. :class:`BadInputLog` logs each distinct input once (it
remembers a bounded number of them), at most once per period per group (a perception source, a
sender), and truncates what it shows; the warnings it held back are counted in the next one.

A flood under ever new group names (senders, sources) would pass every per-group limit, so all
the BadInputLogs of a process also share one :class:`GlobalLimit`: at most ``GLOBAL_BURST``
warnings at once and ``GLOBAL_RATE`` a second after that; the next warning it lets through
counts those it held back. It measures monotonic wall time, not ROS time, on purpose: it bounds
what reaches the disk (a simulated clock running fast or stopped must not change that).
"""

from __future__ import annotations

import hashlib
import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from dataclasses import dataclass

#: how much of an offending text a warning shows
MAX_SHOWN = 200
#: the longest warning line logged (a huge malformed input must not flood the log)
MAX_LINE = 600
#: warnings a process may log at once, and each second after that, whatever their groups
GLOBAL_BURST = 20
GLOBAL_RATE = 2.0


def shorten(text: str, limit: int = MAX_SHOWN) -> str:
    """``text`` cut to ``limit`` characters (``...`` and the full length when cut)."""
    if len(text) <= limit:
        return text
    return f"{text[:limit]}... ({len(text)} characters)"


class GlobalLimit:
    """A token bucket shared by the warnings of a process (thread-safe): `burst` at once,
    `rate` a second after that; counts what it refused."""

    def __init__(self, rate: float = GLOBAL_RATE, burst: int = GLOBAL_BURST,
                 now: Callable[[], float] = time.monotonic) -> None:
        self.rate, self.burst, self.now = rate, burst, now
        self._tokens = float(burst)
        self._last = now()
        self.held_back = 0
        self._lock = threading.Lock()

    def take(self) -> int | None:
        """None if no warning may be logged now (it is counted); else how many were held back
        since the last one that was (that count is then reset)."""
        with self._lock:
            now = self.now()
            self._tokens = min(float(self.burst),
                               self._tokens + max(0.0, now - self._last) * self.rate)
            self._last = now
            if self._tokens < 1.0:
                self.held_back += 1
                return None
            self._tokens -= 1.0
            held, self.held_back = self.held_back, 0
            return held


#: The limit every BadInputLog of this process shares unless given its own.
PROCESS_LIMIT = GlobalLimit()


def _compact(text: str) -> str:
    """`text`, or a digest of it when long (what is remembered of an input or a group name: a
    flood of huge ones must not be kept whole)."""
    if len(text) <= 64:
        return text
    return "#" + hashlib.blake2b(text.encode("utf-8", "replace"), digest_size=16).hexdigest()


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
        limit: the limit shared with the process's other warnings (:data:`PROCESS_LIMIT`).
    """

    def __init__(self, log: Callable[[str], None], now: Callable[[], float] = time.monotonic,
                 period: float = 1.0, remember: int = 256,
                 limit: GlobalLimit | None = None) -> None:
        self.log = log
        self.now = now
        self.period = period
        self.remember = remember
        self.limit = limit or PROCESS_LIMIT
        self._seen: OrderedDict[tuple[str, str], None] = OrderedDict()
        self._groups: OrderedDict[str, _Group] = OrderedDict()
        self.logged = 0

    def warn(self, group: str, key: str | None, text: str) -> bool:
        """Warn ``text`` about input ``key`` of ``group``, unless that input was already warned
        about or the group warned less than ``period`` ago. Returns True if it was logged.

        ``key`` None: no input to remember, only the group's rate limit applies (a recurring
        kind of failure is warned about again every period).
        """
        group = _compact(group)
        if key is not None:
            seen_key = (group, _compact(key))
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
        held_globally = self.limit.take()
        if held_globally is None:       # the process logs too much: counted by the limit only
            return False
        g.last = now
        text = shorten(text, MAX_LINE)
        if g.held_back:
            text += f" ({g.held_back} similar warnings held back)"
            g.held_back = 0
        if held_globally:
            text += f" ({held_globally} other warnings held back: too many at once)"
        self.logged += 1
        self.log(text)
        return True
