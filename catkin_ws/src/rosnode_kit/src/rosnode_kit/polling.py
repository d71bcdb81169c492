"""The one deadline poll: ask again and again until something holds or the time is up.

Standard library only (no rospy at import): the process harness, its reaper, the network
namespaces, ``rosrun rason act``, the workstation and the tests' ``wait_until`` all wait with
:func:`poll`, or share one :class:`Deadline` between several waits. ``clock`` and ``sleep``
default to wall-clock time; a node that must follow the simulation passes ROS time (e.g.
``clock=rospy.get_time``), and ``stop=rospy.is_shutdown`` ends a node's wait at its shutdown.
"""

from __future__ import annotations

import subprocess
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import Any, Protocol, TypeVar

T = TypeVar("T")


@dataclass
class Deadline:
    """The moment ``seconds`` after its creation on ``clock`` (wall-clock by default)."""

    seconds: float
    #: seconds, only differences count (``time.monotonic``, ``rospy.get_time``)
    clock: Callable[[], float] = time.monotonic
    at: float = field(init=False)

    def __post_init__(self) -> None:
        self.at = self.clock() + self.seconds

    def remaining(self) -> float:
        """Seconds left until the deadline, never below 0."""
        return max(0.0, self.at - self.clock())

    def passed(self) -> bool:
        """True once the deadline is reached."""
        return self.clock() >= self.at


def poll(probe: Callable[[], T], timeout: float, period: float, *,
         check: Callable[[], None] | None = None, stop: Callable[[], bool] | None = None,
         clock: Callable[[], float] = time.monotonic, sleep: Callable[[float], Any] = time.sleep) -> T:
    """Call ``probe`` every ``period`` s until it returns something true, and return that; its
    last (false) value once ``timeout`` s of ``clock`` have passed, or as soon as ``stop()`` is
    true. ``probe`` is called at least once. ``check`` runs after each false answer: it raises
    to end the wait early (see :func:`watching`)."""
    deadline = Deadline(timeout, clock)
    while True:
        value = probe()
        if value:
            return value
        if check is not None:
            check()
        if deadline.passed() or (stop is not None and stop()):
            return value
        sleep(period)


class Watched(Protocol):
    """A process whose exit ends a wait early (the harness's ``Process`` is one)."""

    name: str
    popen: subprocess.Popen[Any]

    def alive(self) -> bool: ...

    def output(self) -> str: ...


def watching(processes: Iterable[Watched], what: str,
             error: Callable[[str], Exception] = AssertionError) -> Callable[[], None]:
    """A ``check`` for :func:`poll`: raises ``error`` as soon as one of ``processes`` has
    exited, naming it, its exit status, ``what`` was awaited and the end of its output."""
    watched = list(processes)

    def check() -> None:
        for proc in watched:
            if not proc.alive():
                raise error(f"{proc.name} exited ({proc.popen.returncode}) while waiting for "
                            f"{what}:\n{proc.output()[-3000:]}")
    return check
