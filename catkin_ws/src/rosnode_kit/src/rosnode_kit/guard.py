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

from rosnode_kit.badinput import BadInputLog, shorten

#: Most distinct warning kinds remembered (bounded memory under arbitrary input).
MAX_KINDS = 256

F = TypeVar("F", bound=Callable[..., Any])


class RateLimitedWarnings:
    """Warnings keyed by kind, each kind logged at most once per `period` s of ROS time.

    A :class:`~rosnode_kit.badinput.BadInputLog` on ``rospy.logwarn`` and ROS time, with no
    per-input memory: the same failure is reported again every period while it lasts.
    """

    def __init__(self, period: float = 5.0) -> None:
        self.period = period
        self._log = BadInputLog(rospy.logwarn, rospy.get_time, period=period, remember=MAX_KINDS)
        self._lock = threading.Lock()

    def warn(self, kind: str, text: str) -> bool:
        """Log ``text`` unless `kind` was logged less than `period` ago; True if logged."""
        with self._lock:
            return self._log.warn(kind, None, text)


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
                          f"{what}: rejected ({type(err).__name__}: {shorten(str(err))})")
                return None

        return wrapper  # type: ignore[return-value]

    return decorate
