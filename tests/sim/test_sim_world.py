"""The simulator's world file: a clear one-line error for a missing or bad one, the case study's
world without ``~world``, and the robot namespaces it says to use (real roscore)."""

from __future__ import annotations

import pytest

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros


@pytest.mark.parametrize(("content", "why"), [
    (None, "no such world file: {path}"),
    ("- a list, not a map\n", "{path} is not a valid world file: "),
])
def test_a_missing_or_bad_world_is_one_line_and_exit_2(ros: RosHarness, tmp_path, content, why):
    path = tmp_path / "world.yaml"
    if content is not None:
        path.write_text(content)
    ns = "/simworld_bad"
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns, params={"world": str(path)})
    assert sim.wait(60) == 2, sim.output()
    assert f"turtlebot_sim: ~world: {why.format(path=path)}" in sim.output()
    assert "Traceback" not in sim.output()
    with pytest.raises(KeyError):            # cleared: the next run falls back to the default
        ros.get_param(f"{ns}/turtlebot_sim/world")


def test_without_world_the_case_study_world_runs_and_names_its_namespaces(ros: RosHarness):
    ns = "/simworld_default"
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns, params={"camera_rate": 0})
    sim.wait_for_line(r"world .*rason_diagnosis/worlds/case_study\.yaml", timeout=60)
    sim.wait_for_line(f"run each robot's nodes in its namespace: __ns:={ns}/faulty, "
                      f"__ns:={ns}/helper", timeout=60)
    sim.wait_for_line(r"/use_sim_time is not true", timeout=60)
    ros.wait_for_topic(f"{ns}/faulty/mobile_base/odom", timeout=60, watch=[sim])


def test_a_decomposer_outside_the_robots_namespaces_says_where_odometry_is(ros: RosHarness):
    sim = ros.rosrun("turtlebot_sim", "sim", ns="/simworld_ns", params={"camera_rate": 0})
    injector = ros.rosrun("kobuki_fault_injector", "fault_injector", ns="/simworld_ns/faulty")
    ros.wait_for_topic("/simworld_ns/faulty/odom", timeout=60, watch=[sim, injector])
    dec = ros.rosrun("rason", "motion_decomposer", ns="/simworld_ns/robot")
    ros.wait_for_subscriber("/simworld_ns/robot/jason/action", timeout=60, watch=[dec])
    act = ros.rosrun("rason", "act", "x", "move(0.1)", ns="/simworld_ns/robot")
    assert act.wait(90) == 1, act.output()
    assert "nobody publishes /simworld_ns/robot/odom; odometry is on" in act.output()
    assert "/simworld_ns/faulty/odom" in act.output()
