"""One polling helper for the tests: wait until something holds, fail clearly when it does not.

Tests import it as ``from polling import wait_until`` (tests/ is on ``sys.path``: its
conftest.py lives there). A negative check ("X did not happen") does not sleep a fixed time
before asserting: it waits with this helper for a *sentinel*, something that must come after X
would have (a later message on the same topic, the node's answer to the next request), then
asserts that X is absent.
"""

from __future__ import annotations

import subprocess
import time
from collections.abc import Callable, Iterable
from typing import Any, Protocol, TypeVar

T = TypeVar("T")


class Watched(Protocol):
    """A process whose exit ends a wait early (the harness's ``Process`` is one)."""

    name: str
    popen: subprocess.Popen[Any]

    def alive(self) -> bool: ...

    def output(self) -> str: ...


#: seconds between two looks
PERIOD = 0.02


def wait_until(probe: Callable[[], T], what: str, timeout: float = 20.0,
               watch: Iterable[Watched] = (), period: float = PERIOD) -> T:
    """Call ``probe`` every ``period`` seconds until it returns something true, and return
    that; an AssertionError naming ``what`` after ``timeout`` wall-clock seconds, or as soon as
    a process of ``watch`` has exited (with the end of its output)."""
    watched = list(watch)
    deadline = time.monotonic() + timeout
    while True:
        found = probe()
        if found:
            return found
        for proc in watched:
            if not proc.alive():
                raise AssertionError(f"{proc.name} exited ({proc.popen.returncode}) while "
                                     f"waiting for {what}:\n{proc.output()[-3000:]}")
        if time.monotonic() >= deadline:
            raise AssertionError(f"no {what} within {timeout} s")
        time.sleep(period)
