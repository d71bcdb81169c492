"""The demo's and the mission's waits name the processes that died (pure logic, no ROS)."""

from __future__ import annotations

import os
import sys

import pytest

from rason.process.harness import HarnessError, Process
from rason_diagnosis.scenario import raise_if_dead


def test_raise_if_dead_names_only_the_processes_that_exited(tmp_path):
    done = Process("done", [sys.executable, "-c", "pass"], dict(os.environ), tmp_path / "d.log")
    running = Process("running", [sys.executable, "-c", "import time; time.sleep(60)"],
                      dict(os.environ), tmp_path / "r.log")
    try:
        done.wait(30)
        with pytest.raises(HarnessError, match=r"^agent died: \['faulty'\]$"):
            raise_if_dead({"faulty": done, "helper": running}, "agent")
        raise_if_dead({"helper": running}, "agent")      # all alive: nothing raised
    finally:
        running.stop()
