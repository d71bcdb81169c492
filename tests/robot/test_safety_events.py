"""Base safety events end motions (#35 item 3), against a real roscore and decomposer node.

``rosrun rason motion_decomposer`` runs alone in a namespace; the test plays the Kobuki base:
it turns the decomposer's ``cmd_vel`` into 50 Hz odometry (a unicycle, no faults) and
publishes kobuki_msgs' BumperEvent / CliffEvent / WheelDropEvent where kobuki_node does. While
a move runs, an event stops it: a zero Twist follows, no drive command after it, and the move
ends with the event's named result. While the hazard lasts, motions into it are refused with
the same result and the way out is allowed. Last, an agent's ``-!g[error(bumper)]`` plan runs.
"""

from __future__ import annotations

import itertools
import math
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
import rospy
from agent_nodes import start_agent
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action, Event
from kobuki_msgs.msg import BumperEvent, CliffEvent, WheelDropEvent
from nav_msgs.msg import Odometry
from polling import wait_until

from rason.process.harness import Process, RosHarness
from rason.ros.feedback import parse_feedback

pytestmark = pytest.mark.ros

RATE = 50.0                 # Hz of kobuki_node's odometry
ACTION_TIMEOUT = 30.0       # wall seconds for an action's feedback on a busy machine
NAMESPACES = (f"/safety{i}" for i in itertools.count())   # one per test


def moving(msg: Twist) -> bool:
    return bool(msg.linear.x or msg.angular.z)


@dataclass
class Base:
    """The test's Kobuki: integrates cmd_vel into odometry, publishes the base's events."""

    ns: str
    lock: threading.Lock = field(default_factory=threading.Lock)
    cmds: list[Twist] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    ids: Iterator[int] = field(default_factory=lambda: itertools.count(1))

    def __post_init__(self) -> None:
        self.stopping = threading.Event()
        self.odom = rospy.Publisher(f"{self.ns}/odom", Odometry, queue_size=10)
        self.actions = rospy.Publisher(f"{self.ns}/jason/action", Action, queue_size=10)
        self.bumper = rospy.Publisher(f"{self.ns}/mobile_base/events/bumper", BumperEvent,
                                      queue_size=10)
        self.cliff = rospy.Publisher(f"{self.ns}/mobile_base/events/cliff", CliffEvent,
                                     queue_size=10)
        self.wheel_drop = rospy.Publisher(f"{self.ns}/mobile_base/events/wheel_drop",
                                          WheelDropEvent, queue_size=10)
        self.subs = [rospy.Subscriber(f"{self.ns}/cmd_vel", Twist, self._on_cmd, queue_size=100),
                     rospy.Subscriber(f"{self.ns}/jason/event", Event, self._on_event,
                                      queue_size=100)]
        self.thread = threading.Thread(target=self._drive, daemon=True)
        self.thread.start()

    def close(self) -> None:
        self.stopping.set()
        self.thread.join(5)
        for endpoint in (*self.subs, self.odom, self.actions, self.bumper, self.cliff,
                         self.wheel_drop):
            endpoint.unregister()

    def connected(self, timeout: float = 20.0) -> None:
        endpoints = (*self.subs, self.odom, self.actions, self.bumper, self.cliff,
                     self.wheel_drop)
        wait_until(lambda: all(e.get_num_connections() > 0 for e in endpoints),
                   "the decomposer's connections", timeout=timeout, period=0.05)

    def _on_cmd(self, msg: Twist) -> None:
        with self.lock:
            self.cmds.append(msg)

    def _on_event(self, msg: Event) -> None:
        with self.lock:
            self.events.append(msg)

    def _drive(self) -> None:
        period = 1.0 / RATE
        while not self.stopping.is_set():
            with self.lock:
                cmd = self.cmds[-1] if self.cmds else Twist()
                self.yaw += cmd.angular.z * period
                self.x += cmd.linear.x * period * math.cos(self.yaw)
                self.y += cmd.linear.x * period * math.sin(self.yaw)
                msg = Odometry()
                msg.header.stamp = rospy.Time.now()
                msg.pose.pose.position.x, msg.pose.pose.position.y = self.x, self.y
                msg.pose.pose.orientation.z = math.sin(self.yaw / 2)
                msg.pose.pose.orientation.w = math.cos(self.yaw / 2)
            self.odom.publish(msg)
            time.sleep(period)                         # the base's odometry rate (its pace)

    def send(self, action: str, *params: str) -> int:
        action_id = next(self.ids)
        self.actions.publish(Action(agent="tester", action_id=action_id, action=action,
                                    parameters=list(params)))
        return action_id

    def feedback(self, action_id: int) -> tuple[str, str]:
        def found() -> tuple[str, str] | None:
            with self.lock:
                for event in self.events:
                    fb = parse_feedback(event)
                    if fb is not None and fb.action_id == action_id:
                        return fb.result, fb.message
            return None
        return wait_until(found, f"feedback for action {action_id}", timeout=ACTION_TIMEOUT)

    def wait_moving(self) -> int:
        """Wait for a drive command; the number of commands so far."""
        def driving() -> int:
            with self.lock:
                return len(self.cmds) if self.cmds and moving(self.cmds[-1]) else 0
        return wait_until(driving, "a drive command to the base", timeout=ACTION_TIMEOUT,
                          period=0.01)

    def commands_since(self, index: int) -> list[Twist]:
        with self.lock:
            return list(self.cmds[index:])

    def raise_event(self, kind: str, index: int, on: bool) -> None:
        if kind == "bumper":
            self.bumper.publish(BumperEvent(bumper=index, state=int(on)))
        elif kind == "cliff":
            self.cliff.publish(CliffEvent(sensor=index, state=int(on), bottom=0))
        else:
            self.wheel_drop.publish(WheelDropEvent(wheel=index, state=int(on)))


@pytest.fixture
def base(ros: RosHarness) -> Iterator[tuple[Base, Process]]:
    ros.init_rospy()
    ns = next(NAMESPACES)
    node = ros.rosrun("rason", "motion_decomposer", ns=ns, params={"settle_time": 0.0})
    ros.wait_for_subscriber(f"{ns}/mobile_base/events/wheel_drop", watch=[node])
    robot = Base(ns)
    robot.connected()
    yield robot, node
    robot.close()


def assert_stopped_at_once(robot: Base, since: int, sentinel: int) -> None:
    """After the event (commands from `since` on): a zero Twist, and no forward command once it
    came, up to the command at `sentinel` (one the decomposer published later, on the same
    topic: whatever it published before is in by then)."""
    after = robot.commands_since(since)[:sentinel - since]
    stops = [i for i, cmd in enumerate(after) if not moving(cmd)]
    assert stops, "no zero Twist after the event"
    assert not any(cmd.linear.x > 0 for cmd in after[stops[0]:]), "drove on after the stop"


def first_turn_since(robot: Base, index: int) -> int:
    """Wait for a turn command at or after `index`: its index."""
    def found() -> int | None:
        cmds = robot.commands_since(index)
        return next((index + i for i, cmd in enumerate(cmds) if cmd.angular.z), None)
    return wait_until(found, "a turn command", timeout=ACTION_TIMEOUT)


@pytest.mark.parametrize("kind, index, named", [
    ("bumper", 1, "centre bumper pressed"),
    ("cliff", 0, "left cliff sensor sees a cliff"),
    ("wheel_drop", 1, "right wheel dropped"),
])
def test_an_event_stops_the_move_and_names_the_part(base: tuple[Base, Process], kind: str,
                                                    index: int, named: str):
    robot, node = base
    action = robot.send("move", "2")
    since = robot.wait_moving()
    robot.raise_event(kind, index, True)
    result, message = robot.feedback(action)
    assert result == kind, message
    assert message.startswith(f"{named}: move(2) stopped after "), message
    # while it lasts, a forward move is refused with the same result and nothing drives (the
    # check that no forward command came waits for the sentinel turn, below)
    result, message = robot.feedback(robot.send("move", "0.5"))
    assert (result, "refused" in message) == (kind, True), message
    if kind == "wheel_drop":                       # every motion, even backwards
        result, message = robot.feedback(robot.send("move", "-0.1"))
        assert result == kind, message
    else:                                          # backing away is the way out
        result, message = robot.feedback(robot.send("move", "-0.1"))
        assert result == "OK", message
    robot.raise_event(kind, index, False)          # released / floor again / wheel raised

    # The release and the next action come on different topics, so the action may be handled
    # first: until the release is, a motion is refused as before (and drives nothing). A turn
    # once allowed is the sentinel on cmd_vel: no forward command came from the stop to it.
    count = len(robot.commands_since(0))

    def turn_allowed() -> bool:
        result, message = robot.feedback(robot.send("turn", "10"))
        assert result in ("OK", kind), message
        return result == "OK"
    wait_until(turn_allowed, "a turn allowed after the release", timeout=10)
    assert_stopped_at_once(robot, since, first_turn_since(robot, count))

    def forward_allowed() -> bool:
        result, message = robot.feedback(robot.send("move", "0.1"))
        assert result in ("OK", kind), message
        return result == "OK"
    wait_until(forward_allowed, "a forward move allowed after the release", timeout=10)
    assert "Traceback" not in node.output()


def test_turns_toward_a_pressed_side_bumper_are_refused_and_away_allowed(
        base: tuple[Base, Process]):
    robot, _ = base
    robot.raise_event("bumper", 0, True)           # left bumper, nothing running
    # turn(d) > 0 turns clockwise (right) by default: away from the left bumper. The press and
    # the action come on different topics: until the press is handled, the turn runs.
    refusals: list[str] = []

    def toward_refused() -> bool:
        result, message = robot.feedback(robot.send("turn", "-10"))
        assert result in ("OK", "bumper"), message
        refusals.append(message)
        # a turn sent before the press was handled runs, and the press then stops it ("stopped
        # after"); the next one must be refused
        return result == "bumper" and "refused" in message
    wait_until(toward_refused, "a turn toward the pressed bumper refused", timeout=10)
    assert "left bumper pressed: turn(-10) refused" in refusals[-1], refusals[-1]
    result, message = robot.feedback(robot.send("turn", "10"))
    assert result == "OK", message
    # turn_to a heading to the left (counter-clockwise from here) is refused too
    result, message = robot.feedback(robot.send("turn_to", "-90"))
    assert result == "bumper", message


def test_a_remapped_event_topic_is_heard(ros: RosHarness):
    ros.init_rospy()
    ns = "/safety_remap"
    node = ros.rosrun("rason", "motion_decomposer",
                      "mobile_base/events/bumper:=/safety_remap_base/bumper", ns=ns)
    ros.wait_for_subscriber("/safety_remap_base/bumper", watch=[node])
    robot = Base(ns)
    try:
        robot.bumper.unregister()
        robot.bumper = rospy.Publisher("/safety_remap_base/bumper", BumperEvent, queue_size=10)
        robot.connected()
        action = robot.send("move", "2")
        robot.wait_moving()
        robot.raise_event("bumper", 2, True)
        result, message = robot.feedback(action)
        assert result == "bumper" and message.startswith("right bumper pressed"), message
    finally:
        robot.close()


AGENT = """\
!go.
+!go <- move(2); .print("arrived").
-!go[error(bumper), error_msg(M)]
   <- .print("bumped: ", M);
      move(-0.1);
      .print("backed off").
-!go[error(R)] <- .print("other failure ", R).
"""


def test_an_agent_plan_for_error_bumper_runs(ros: RosHarness, tmp_path: Path):
    ros.init_rospy()
    ns = "/safety_agent"
    node = ros.rosrun("rason", "motion_decomposer", ns=ns, params={"settle_time": 0.0})
    ros.wait_for_subscriber(f"{ns}/mobile_base/events/bumper", watch=[node])
    robot = Base(ns)
    try:
        robot.actions.unregister()                 # the agent issues the actions here
        robot.subs[1].unregister()
        wait_until(lambda: robot.odom.get_num_connections() > 0
                   and robot.bumper.get_num_connections() > 0,
                   "the decomposer's odometry and bumper connections", timeout=20, period=0.05)
        agent = start_agent(ros, tmp_path, "bumpy", AGENT, ns=ns)
        robot.wait_moving()
        robot.raise_event("bumper", 1, True)
        agent.wait_for_line(r"\[bumpy\] bumped: centre bumper pressed: move\(2\) stopped",
                            timeout=ACTION_TIMEOUT)
        agent.wait_for_line(r"\[bumpy\] backed off", timeout=ACTION_TIMEOUT)
        assert "arrived" not in agent.output() and "other failure" not in agent.output()
    finally:
        robot.close()
