"""Callbacks that survive any message: one bad message costs one (rate-limited) warning.

rospy logs and forgets an exception raised by a subscriber callback, but a ``rospy.Timer``
thread dies with it, and a ``message_filters`` synchronizer raising from its callback keeps
its lock. Every callback of every rason node is wrapped with :func:`guarded`: whatever it
raises is logged as a warning (at most one per kind every ``period`` seconds of ROS time, with
the count of those held back) and the node carries on.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import Any, TypeVar

import rospy

#: Longest exception text logged (a huge malformed message must not flood the log).
MAX_TEXT = 300
#: Most distinct warning kinds remembered (bounded memory under arbitrary input).
MAX_KINDS = 256

F = TypeVar("F", bound=Callable[..., Any])


def clip(text: str, limit: int = MAX_TEXT) -> str:
    """`text` cut to `limit` characters (with the length of what was cut)."""
    return text if len(text) <= limit else f"{text[:limit]}... ({len(text) - limit} more chars)"


class RateLimitedWarnings:
    """Warnings keyed by kind, each kind logged at most once per `period` s of ROS time."""

    def __init__(self, period: float = 5.0) -> None:
        self.period = period
        self._last: dict[str, float] = {}
        self._held: dict[str, int] = {}
        self._lock = threading.Lock()

    def warn(self, kind: str, text: str) -> bool:
        """Log ``text`` unless `kind` was logged less than `period` ago; True if logged."""
        now = rospy.get_time()
        with self._lock:
            last = self._last.get(kind)
            if last is not None and 0.0 <= now - last < self.period:
                self._held[kind] = self._held.get(kind, 0) + 1
                return False
            if last is None and len(self._last) >= MAX_KINDS:
                self._last.clear()
                self._held.clear()
            held = self._held.pop(kind, 0)
            self._last[kind] = now
        suffix = f" ({held} more like it in the last {self.period:g} s)" if held else ""
        rospy.logwarn(clip(text) + suffix)
        return True


#: The warnings of callbacks wrapped without a warnings object of their own.
WARNINGS = RateLimitedWarnings()


def guarded(what: str, warnings: RateLimitedWarnings | None = None) -> Callable[[F], F]:
    """Decorator: `fn` never raises; an exception becomes a rate-limited warning naming `what`.

    The wrapped callback returns None when it raised.
    """
    sink = warnings or WARNINGS

    def decorate(fn: F) -> F:
        @functools.wraps(fn)
        def wrapper(*args: Any, **kwargs: Any) -> Any:
            try:
                return fn(*args, **kwargs)
            except Exception as err:  # the point: nothing escapes a callback
                sink.warn(f"{what}:{type(err).__name__}",
                          f"{what}: rejected ({type(err).__name__}: {clip(str(err))})")
                return None

        return wrapper  # type: ignore[return-value]

    return decorate
