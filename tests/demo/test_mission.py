"""``./run.sh mission`` end to end (issue 38): the real runner process, with its roscore, the
simulator, fault injectors, motion decomposers, pose and vision synthesizers and both mission
agents, all started with rosrun; the fault injected with the real service during the task.

Two runs. In one, Faulty reaches the first waypoints on its own (the fault-free mission,
without a false alarm), then both actuators break, the team diagnoses the fault and Helper takes
the remaining waypoints over (delegation). In the other, one wheel weakens and Faulty learns
how it moves now and limps on to every waypoint itself. Every waypoint is reached within 0.3 m
by ground truth, and the robots never touch.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from turtlebot_model.kobuki import BODY_RADIUS

pytestmark = [pytest.mark.ros, pytest.mark.demo]

#: The issue's bar: a waypoint counts as reached within this distance (ground truth, m).
REACHED_WITHIN = 0.3


def _mission(tmp_path, *args: str) -> tuple[dict, str]:
    out = tmp_path / "run"
    done = subprocess.run([sys.executable, "-m", "rason_diagnosis.mission", "--quiet", "--json",
                           "--no-inspector", "--out", str(out), *args],
                          capture_output=True, text=True, timeout=900)
    result = json.loads((out / "result.json").read_text())
    # --json ends the output with the same object
    assert json.loads(done.stdout[done.stdout.rindex("\n{"):]) == result, done.stdout[-3000:]
    return result, done.stdout[-3000:] + done.stderr[-2000:]


def _assert_completed(result: dict, shown: str) -> None:
    assert result["completed"] and not result["error"] and "reason" not in result, shown
    assert len(result["waypoints"]) >= 4
    for point in result["waypoints"]:
        assert point["reached_by"] in ("faulty", "helper"), shown
        assert point["error_m"] is not None and point["error_m"] <= REACHED_WITHIN, shown
    times = [p["at_s"] for p in result["waypoints"]]
    assert times == sorted(times) and result["total_s"] >= times[-1]
    assert result["min_robot_distance_m"] > 2 * BODY_RADIUS, shown      # never touched


def test_faulty_goes_alone_until_both_actuators_break_then_helper_takes_over(tmp_path):
    """One run covers what a fault-free mission and a delegated one check: Faulty reaches the
    first waypoints itself with no false alarm (no MONITOR line before its last arrival), the
    fault strikes 20 s in, and Helper reaches the rest."""
    result, shown = _mission(tmp_path, "--fault", "both_actuators", "--at", "20", "--seed", "2")
    _assert_completed(result, shown)
    assert result["diagnosis"] == "both_actuators" and result["recovery"] == "delegate", shown
    assert result["injected_at_s"] >= 20
    by = [p["reached_by"] for p in result["waypoints"]]
    first_helper = by.index("helper")
    assert first_helper >= 1 and set(by[:first_helper]) == {"faulty"}, shown
    assert set(by[first_helper:]) == {"helper"}, shown
    log = (tmp_path / "run" / "logs" / "faulty_agent.log").read_text()
    last_own = log.index(f"reached waypoint {first_helper}\n")
    assert "MONITOR:" in log and "MONITOR:" not in log[:last_own], log[-3000:]


def test_one_weak_wheel_faulty_limps_on_to_every_waypoint(tmp_path):
    # Injected late (on the way to waypoint 2), so that the run stays short.
    result, shown = _mission(tmp_path, "--fault", "right_actuator", "--at", "20", "--seed", "4")
    _assert_completed(result, shown)
    assert result["diagnosis"] == "right_actuator" and result["recovery"] == "limp", shown
    assert {p["reached_by"] for p in result["waypoints"]} == {"faulty"}, shown
