"""``./run.sh mission`` end to end (issue 38): the real runner process, with its roscore, the
simulator, fault injectors, motion decomposers, pose and vision synthesizers and both mission
agents, all started with rosrun; the fault injected with the real service during the task.

Here one wheel weakens, and Faulty learns how it moves now and limps on to every waypoint
itself; and its odometry freezes, and Faulty drives open loop, located by Helper's Kinect after
every leg. The delegated mission (Faulty alone until both actuators break, then Helper) runs
once in the suite, in tests/inspector/test_inspector_mission_browser.py, which checks the
mission's result with the same bar as well as the inspector's page: every waypoint within 0.3 m
by ground truth, and the robots never touch.

Both run in a short mission world (tests/demo/mission_short.yaml, from tests/missions.py): the
same room and robots, a 3 m task, each fault injected on its third leg, so that Faulty recovers
on the way to waypoints 3 and 4.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from missions import SHORT_WORLD, assert_completed

pytestmark = [pytest.mark.ros, pytest.mark.demo]


def _mission(tmp_path, *args: str) -> tuple[dict, str]:
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "rason_diagnosis.mission", "--quiet", "--json",
                           "--no-inspector", "--world", str(SHORT_WORLD), "--out", str(out), *args],
                          capture_output=True, text=True, timeout=900)
    result = json.loads((out / "result.json").read_text())
    # --json ends the output with the same object
    assert json.loads(done.stdout[done.stdout.rindex("\n{"):]) == result, done.stdout[-3000:]
    # signed: every agent and decomposer of the mission got its key (none runs open)
    logs = {p.name: p.read_text() for p in (out / "logs").glob("*.log")}
    assert "faulty_motion_decomposer.log" in logs, sorted(logs)
    assert [name for name, text in logs.items() if "no ~auth_key_file" in text] == []
    return result, done.stdout[-3000:] + done.stderr[-2000:]


def test_one_weak_wheel_faulty_limps_on_to_every_waypoint(tmp_path):
    result, shown = _mission(tmp_path, "--fault", "right_actuator", "--at", "10", "--seed", "4")
    assert_completed(result, shown)
    assert result["diagnosis"] == "right_actuator" and result["recovery"] == "limp", shown
    assert {p["reached_by"] for p in result["waypoints"]} == {"faulty"}, shown


def test_frozen_odometry_faulty_drives_guided_by_helpers_fixes(tmp_path):
    result, shown = _mission(tmp_path, "--fault", "odometry", "--at", "10", "--seed", "12")
    assert_completed(result, shown)
    assert result["diagnosis"] == "odometry" and result["recovery"] == "guided", shown
    assert {p["reached_by"] for p in result["waypoints"]} == {"faulty"}, shown
