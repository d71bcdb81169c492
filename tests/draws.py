"""How many examples the larger property tests draw.

The full suite (CI, ``./run.sh test``) draws each test's full count. ``./run.sh test --fast``,
the inner loop, sets ``RASON_TEST_FAST=1`` and draws a fifth of it (at least ``FAST_MINIMUM``),
so the tests that need no ROS stay under two minutes; the full count still runs in CI.
Tests import it as ``from draws import examples`` (tests/ is on ``sys.path``).
"""

from __future__ import annotations

import os

#: the environment variable ``./run.sh test --fast`` sets to "1"
FAST = "RASON_TEST_FAST"
#: the share of the full count drawn in the inner loop, and the least it draws
FAST_SHARE = 5
FAST_MINIMUM = 40


def examples(full: int) -> int:
    """``full``, or the inner loop's share of it when ``RASON_TEST_FAST=1``."""
    if os.environ.get(FAST) == "1":
        return min(full, max(FAST_MINIMUM, full // FAST_SHARE))
    return full
