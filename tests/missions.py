"""What a mission run must show, shared by the tests that run ``rason_diagnosis.mission``."""

from __future__ import annotations

from pathlib import Path

from turtlebot_model.kobuki import BODY_RADIUS

#: The suite's mission worlds: worlds/case_study.yaml's room and robots with a shorter task;
#: compact: a fault at 20 s strikes before the last two waypoints; short: a 3 m task.
COMPACT_WORLD = Path(__file__).parent / "demo" / "mission_compact.yaml"
SHORT_WORLD = Path(__file__).parent / "demo" / "mission_short.yaml"

#: The issue's bar: a waypoint counts as reached within this distance (ground truth, m).
REACHED_WITHIN = 0.3


def assert_completed(result: dict, shown: str) -> None:
    """Every waypoint reached within REACHED_WITHIN by ground truth, in order, and the robots
    never touched; `shown` goes with a failure."""
    assert result["completed"] and not result["error"] and "reason" not in result, shown
    assert len(result["waypoints"]) >= 4
    for point in result["waypoints"]:
        assert point["reached_by"] in ("faulty", "helper"), shown
        assert point["error_m"] is not None and point["error_m"] <= REACHED_WITHIN, shown
    times = [p["at_s"] for p in result["waypoints"]]
    assert times == sorted(times) and result["total_s"] >= times[-1]
    assert result["min_robot_distance_m"] > 2 * BODY_RADIUS, shown      # never touched


def assert_faulty_then_helper(result: dict, faulty_log: str, shown: str) -> None:
    """Faulty reached the first waypoints itself with no alarm before its last own arrival
    (the fault-free part of the mission), and Helper every one after."""
    by = [p["reached_by"] for p in result["waypoints"]]
    first_helper = by.index("helper") if "helper" in by else len(by)
    assert 1 <= first_helper < len(by) and set(by[:first_helper]) == {"faulty"}, shown
    assert set(by[first_helper:]) == {"helper"}, shown
    last_own = faulty_log.index(f"reached waypoint {first_helper}\n")
    assert "MONITOR:" in faulty_log and "MONITOR:" not in faulty_log[:last_own], faulty_log[-3000:]
