"""One polling helper for the tests: wait until something holds, fail clearly when it does not.

Tests import it as ``from polling import wait_until`` (tests/ is on ``sys.path``: its
conftest.py lives there). It is :func:`rosnode_kit.polling.poll`, the product's one deadline
poll, failing as a test fails (an AssertionError). A negative check ("X did not happen") does
not sleep a fixed time before asserting: it waits with this helper for a *sentinel*,
something that must come after X would have (a later message on the same topic, the node's
answer to the next request), then asserts that X is absent.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import TypeVar

from rosnode_kit.polling import Watched, poll, watching

T = TypeVar("T")

#: seconds between two looks
PERIOD = 0.02


def wait_until(probe: Callable[[], T], what: str, timeout: float = 20.0,
               watch: Iterable[Watched] = (), period: float = PERIOD) -> T:
    """Call ``probe`` every ``period`` seconds until it returns something true, and return
    that; an AssertionError naming ``what`` after ``timeout`` wall-clock seconds, or as soon as
    a process of ``watch`` has exited (with the end of its output)."""
    found = poll(probe, timeout, period, check=watching(watch, what))
    if not found:
        raise AssertionError(f"no {what} within {timeout} s")
    return found
