"""tests/polling.py, the one polling helper, stands alone (no ROS): it imports nothing of rason,
returns what the probe found, and fails early, naming the process, when a watched one exits."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from polling import wait_until

TESTS = Path(__file__).resolve().parents[1]


class Exited:
    """A watched process that has exited (what wait_until reads of one)."""

    name = "agent"

    def __init__(self) -> None:
        self.popen = subprocess.Popen([sys.executable, "-c", "raise SystemExit(4)"])
        self.popen.wait()

    def alive(self) -> bool:
        return self.popen.poll() is None

    def output(self) -> str:
        return "last words"


def test_polling_imports_nothing_of_rason():
    check = ("import sys; sys.path.insert(0, sys.argv[1]); import polling; "
             "print(sorted(m for m in sys.modules if m.split('.')[0].startswith('rason')))")
    done = subprocess.run([sys.executable, "-c", check, str(TESTS)], capture_output=True,
                          text=True, timeout=60, check=True)
    assert done.stdout.strip() == "[]"


def test_wait_until_returns_what_the_probe_found():
    looks = iter([None, 0, "found"])
    assert wait_until(lambda: next(looks), "the third look") == "found"


def test_a_watched_process_that_exits_ends_the_wait_with_its_output():
    with pytest.raises(AssertionError, match=r"agent exited \(4\) while waiting for a reply:"
                                             r"\nlast words"):
        wait_until(lambda: None, "a reply", timeout=600, watch=[Exited()])
