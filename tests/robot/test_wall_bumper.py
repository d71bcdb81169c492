"""Driven into a wall, a move ends ``bumper`` (#35 "done when"), in both simulator profiles.

The simulator (``_drivers:=sim`` on simulated time, ``_drivers:=stock`` on wall time) presses a
Kobuki bumper when the base touches a wall; the motion decomposer, wired straight to the base
(as a robot without its fault injector), must stop there and answer ``bumper`` naming the
centre bumper, then let the robot back away, and drive forward again once the bumper is
released.
"""

from __future__ import annotations

import threading
from pathlib import Path

import pytest
import rospy
from jason_msgs.msg import Action, Event
from polling import wait_until

from rason.process.harness import RosHarness
from rason.ros.feedback import parse_feedback

pytestmark = pytest.mark.ros

WALL_WORLD = """\
# One robot 0.6 m in front of the +x wall of a 3 x 3 m room, facing it.
room: {size: [3.0, 3.0]}
robots:
  - {name: bot, kind: plain, x: 0.7, y: 0.0, yaw: 0.0}
"""
#: Each profile's odometry name as kobuki_node (through turtlebot_bringup) publishes it.
ODOM = {"sim": "mobile_base/odom", "stock": "odom"}


@pytest.mark.parametrize("drivers", ["sim", "stock"])
def test_a_move_into_a_wall_ends_bumper_and_backing_off_is_allowed(ros: RosHarness,
                                                                    tmp_path: Path, drivers: str):
    ns = f"/bumpwall_{drivers}"
    world = tmp_path / "wall.yaml"
    world.write_text(WALL_WORLD)
    if drivers == "sim":
        ros.set_param("/use_sim_time", True)
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns, params={"world": str(world),
                                                            "drivers": drivers})
    ros.wait_for_topic(f"{ns}/bot/{ODOM[drivers]}", timeout=60, watch=[sim])
    node = ros.rosrun("rason", "motion_decomposer", f"odom:={ODOM[drivers]}",
                      "cmd_vel:=mobile_base/commands/velocity", ns=f"{ns}/bot",
                      params={"settle_time": 0.0})
    ros.wait_for_subscriber(f"{ns}/bot/jason/action", watch=[node, sim])
    ros.init_rospy()
    lock, events = threading.Lock(), []

    def on_event(msg: Event) -> None:
        with lock:
            events.append(msg)

    sub = rospy.Subscriber(f"{ns}/bot/jason/event", Event, on_event, queue_size=100)
    actions = rospy.Publisher(f"{ns}/bot/jason/action", Action, queue_size=10)
    wait_until(lambda: sub.get_num_connections() > 0 and actions.get_num_connections() > 0,
               "the decomposer's connections", timeout=20, period=0.05)

    def perform(action_id: int, metres: str) -> tuple[str, str]:
        actions.publish(Action(agent="tester", action_id=action_id, action="move",
                               parameters=[metres]))
        def answered() -> list:
            with lock:
                return [fb for fb in map(parse_feedback, events)
                        if fb is not None and fb.action_id == action_id]
        done = wait_until(answered, f"feedback for move({metres})", timeout=60, period=0.05)
        return done[0].result, done[0].message

    try:
        result, message = perform(1, "1.5")
        assert result == "bumper", message
        assert message.startswith("centre bumper pressed: move(1.5) stopped after "), message
        result, message = perform(2, "0.3")              # still pressed: refused
        assert result == "bumper" and "refused" in message, message
        result, message = perform(3, "-0.3")             # backing away is allowed
        assert result == "OK", message
        result, message = perform(4, "0.1")              # released: forward again
        assert result == "OK", message
    finally:
        sub.unregister()
        actions.unregister()
