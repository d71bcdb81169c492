"""The robot-side nodes under the stock driver names (docs/drivers.md), with real nodes.

turtlebot_sim ``_drivers:=stock`` (wall time, the driver publishes ``odom``), the fault injector
with ``_odom_input:=odom _odom_output:=fault_injector/odom`` and the motion decomposer reading
``fault_injector/odom``: an odometry fault freezes what the decomposer sees, so a ``move`` ends
``no_progress`` while the robot drives. Left with its default names, the injector hears nothing
and says so by name.
"""

from __future__ import annotations

import threading
from pathlib import Path

import pytest
from agent_nodes import wait_heard
from polling import wait_until

from kobuki_fault_injector.node import InjectorParams
from kobuki_fault_injector.srv import FaultInjector
from rason_diagnosis.drivers import INJECTED_ODOM, STOCK

pytestmark = pytest.mark.ros

WORLD = """\
robots:
  - {name: faulty, kind: faulty, x: -3.0, y: 0.0, yaw: 0.0}
"""


class Poses:
    """x of the last Odometry message of one topic, and all of them."""

    def __init__(self, topic: str) -> None:
        import rospy
        from nav_msgs.msg import Odometry

        self.xs: list[float] = []
        self.lock = threading.Lock()
        self.sub = rospy.Subscriber(topic, Odometry, self._on, queue_size=100)

    def _on(self, msg) -> None:
        with self.lock:
            self.xs.append(msg.pose.pose.position.x)

    def since(self, mark: int) -> list[float]:
        with self.lock:
            return self.xs[mark:]

    def __len__(self) -> int:
        with self.lock:
            return len(self.xs)


def _world(tmp_path: Path) -> Path:
    world = tmp_path / "faulty_alone.yaml"
    world.write_text(WORLD)
    return world


def test_odometry_fault_under_stock_names_freezes_what_the_decomposer_sees(ros, tmp_path):
    from jason_msgs.msg import Action, Event

    from rason.ros.feedback import parse_feedback

    ns = "/faulty"
    sim = ros.rosrun("turtlebot_sim", "sim", params={"world": str(_world(tmp_path)),
                                                     **STOCK.sim_params()})
    injector = ros.rosrun("kobuki_fault_injector", "fault_injector", ns=ns,
                          params=STOCK.injector_params)
    decomposer = ros.rosrun("rason", "motion_decomposer", *STOCK.odom_reader_args, ns=ns)
    watch = [sim, injector, decomposer]
    ros.wait_for_topic(f"{ns}/{INJECTED_ODOM}", timeout=60, watch=watch)
    ros.wait_for_service(f"{ns}/fault_injector", watch=watch)
    ros.wait_for_subscriber(f"{ns}/jason/action", watch=watch)
    ros.init_rospy()
    import rospy

    driver, seen = Poses(f"{ns}/odom"), Poses(f"{ns}/{INJECTED_ODOM}")
    events: list = []
    events_sub = rospy.Subscriber(f"{ns}/jason/event", Event, events.append, queue_size=100)
    actions = rospy.Publisher(f"{ns}/jason/action", Action, queue_size=10)
    wait_until(lambda: actions.get_num_connections() > 0, "the action publisher's connection",
               timeout=10, period=0.05)
    # the move's feedback comes once; the driver's odometry must be heard from the start
    wait_heard(ros, f"{ns}/motion_decomposer", [f"{ns}/jason/event"], watch=watch)
    wait_heard(ros, "/turtlebot_sim", [f"{ns}/odom"], watch=watch)
    assert rospy.ServiceProxy(f"{ns}/fault_injector", FaultInjector)("odometry").return_message
    # the fault is in force once the service answered: count from odometry published after it
    # (the robot stands still until the move, so a pose still in flight is the frozen one)
    answered = len(seen)
    wait_until(lambda: len(seen) > answered + 1, "odometry under the fault", timeout=10,
               period=0.05)
    marks = len(driver), len(seen)
    actions.publish(Action(agent="faulty", action_id=7, action="move", parameters=["1"]))
    feedback = wait_until(lambda: next((parse_feedback(e) for e in list(events)
                                        if e.event_type == "action_feedback"), None),
                          "feedback for the move", timeout=60, period=0.05)
    assert feedback.result == "no_progress", feedback.message
    moved, frozen = driver.since(marks[0]), seen.since(marks[1])
    assert frozen and len(set(frozen)) == 1, "the decomposer's odometry kept changing"
    assert max(moved) - min(moved) > 0.1, "the driver's odometry shows the robot drove"
    assert injector.alive() and decomposer.alive()
    for sub in (events_sub, driver.sub, seen.sub):
        sub.unregister()


def test_injector_left_on_its_default_names_warns_by_name(ros, tmp_path):
    sim = ros.rosrun("turtlebot_sim", "sim", params={"world": str(_world(tmp_path)),
                                                     **STOCK.sim_params()})
    ros.wait_for_topic("/faulty/odom", timeout=60, watch=[sim])
    # its default names, set explicitly: private parameters outlive a node on the session's master
    defaults = InjectorParams()
    injector = ros.rosrun("kobuki_fault_injector", "fault_injector", ns="/faulty",
                          params={"odom_input": defaults.odom_input,
                                  "odom_output": defaults.odom_output})
    line = injector.wait_for_line(r"nothing on /faulty/mobile_base/odom .*", timeout=30)
    text = line.group(0)
    assert "/faulty/odom" in text and "/turtlebot_sim" in text
    assert "_odom_input:=odom" in text                 # and says how to wire it
