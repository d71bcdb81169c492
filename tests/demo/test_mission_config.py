"""The mission's pure parts, without ROS: the world file's ``mission`` key, the pose and task
percepts Faulty navigates by, and what the runner reads of Faulty's beliefs."""

from __future__ import annotations

import math

import pytest

from rason_diagnosis.mission import (
    MissionError,
    Waypoint,
    default_at,
    default_fault,
    load_mission,
    mission_waypoints,
    read_mind,
)
from rason_diagnosis.paths import world_file
from rason_diagnosis.pose_synthesizer import Frame, task_percepts
from rason_diagnosis.scenario import FAULTS


def test_the_shipped_world_has_four_waypoints_spread_over_the_room():
    points = load_mission(world_file())
    assert len(points) >= 4
    xs, ys = {p.x for p in points}, {p.y for p in points}
    assert max(xs) - min(xs) >= 3.0 and max(ys) - min(ys) >= 1.0
    # none on Helper's start (the origin): 1 m of room for both robots' bodies at least
    assert all(math.hypot(p.x, p.y) > 1.0 for p in points)


def test_waypoints_are_read_in_order():
    world = {"mission": {"waypoints": [[1, 2], [-1.5, 0.5]]}}
    assert mission_waypoints(world) == [Waypoint(1.0, 2.0), Waypoint(-1.5, 0.5)]


@pytest.mark.parametrize("world, says", [
    ({}, "no mission key"),
    ({"mission": [[1, 2]]}, "mapping"),
    ({"mission": {"waypoints": [[1, 2]], "speed": 3}}, "mapping"),
    ({"mission": {"waypoints": []}}, "non-empty"),
    ({"mission": {"waypoints": [[1, 2], [3]]}}, "waypoints[2]"),
    ({"mission": {"waypoints": [[1, "a"]]}}, "waypoints[1]"),
    ({"mission": {"waypoints": [[1, float("nan")]]}}, "waypoints[1]"),
    ({"mission": {"waypoints": [[True, 1]]}}, "waypoints[1]"),
    ({"mission": {"waypoints": [[6, 0]]}, "room": {"size": [10, 10]}}, "outside the room"),
])
def test_a_bad_mission_key_gets_a_clear_error(world, says):
    with pytest.raises(MissionError, match=r".*" + says.replace("[", r"\[").replace("]", r"\]")):
        mission_waypoints(world)


def test_the_seed_draws_every_fault_none_included_and_a_moment_in_range():
    assert {default_fault(seed) for seed in range(200)} == set(FAULTS)
    assert default_fault(7) == default_fault(7) and default_at(7) == default_at(7)
    assert all(2.0 <= default_at(seed) <= 30.0 for seed in range(200))


def test_pose_percepts_place_the_odometry_frame_in_the_world():
    frame = Frame(x=0.0, y=-1.5, yaw=90.0)          # odometry x along the world's +y
    pose, heading = frame.pose_percepts(1.0, 0.0, math.radians(-30.0))
    assert pose == "pose(0.000, -0.500, 60.00)"
    assert heading == "heading(30.00)"              # turn_to's convention: clockwise positive


def test_task_percepts_and_a_bad_task():
    assert task_percepts([[1, 2], [3.5, -4]], no_recovery=True) == [
        "waypoint(1, 1.000, 2.000)", "waypoint(2, 3.500, -4.000)", "mission_option(no_recovery)"]
    with pytest.raises(ValueError):
        task_percepts([[1, 2, 3]], no_recovery=False)
    with pytest.raises(ValueError):
        task_percepts("[[1, 2]]", no_recovery=False)


def test_the_runner_reads_faultys_knowledge():
    view = read_mind(["reached(1,faulty)[source(self)]", "reached(2, helper)[source(self)]",
                      "diagnosis(both_actuators)[source(self)]", "recovery(delegate)",
                      'gaveUp(delegate_failed(not_arrived))[source(self)]', "waypoint(1,2,3)"])
    assert view.reached == {1: "faulty", 2: "helper"}
    assert (view.diagnosis, view.recovery) == ("both_actuators", "delegate")
    assert view.gave_up == "delegate_failed(not_arrived)" and not view.done
    assert read_mind(["missionDone[source(self)]"]).done
