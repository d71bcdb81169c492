"""The robot layer end to end: roscore + turtlebot_sim + fault injector + motion decomposer.

One simulated Faulty (no Helper, so no camera to render) runs in simulated time for the whole
module; the tests drive it as an agent would, publishing ``jason_msgs/Action`` on
``/faulty/jason/action`` and reading ``/faulty/jason/event``, and judge the motion by the
simulator's ground truth. Faults are injected through the service and cancelled after each test.
Each test measures its motion relative to where the robot stands, so no pose reset is needed.
"""

from __future__ import annotations

import itertools
import math
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

import pytest
import rospy
from agent_nodes import wait_heard
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from jason_msgs.msg import Action, Event
from nav_msgs.msg import Odometry
from polling import wait_until
from std_msgs.msg import String
from std_srvs.srv import Trigger

from kobuki_fault_injector.srv import FaultInjector
from rason.execution.motion import SETTINGS
from rason.process.harness import RosHarness
from rason.ros.feedback import ACTION_RUNNING, parse_accepted, parse_feedback
from turtlebot_model.geometry import yaw_from_quaternion

pytestmark = pytest.mark.ros

NS = "/faulty"
WORLD = """\
# Faulty alone in the room, 3 m behind the centre so every test has room to drive.
robots:
  - {name: faulty, kind: faulty, x: -3.0, y: 0.0, yaw: 0.0}
"""
#: Sim seconds per wall second. Faster is possible, but above ~3x the simulator delivers
#: odometry in bursts and the decomposer's commands lag by tenths of sim seconds.
REAL_TIME_FACTOR = 2.0
#: Wall-clock limit for one action (the sim runs at least at real time).
ACTION_TIMEOUT = 30.0


def yaw_of(msg: Odometry) -> float:
    q = msg.pose.pose.orientation
    return yaw_from_quaternion(q.x, q.y, q.z, q.w)


@dataclass
class Outcome:
    """How one action went: its events and the ground-truth motion during it."""

    accepted: bool
    result: str
    message: str
    forward: float      # ground-truth displacement along the start heading (m)
    lateral: float      # ... to the left of the start heading (m)
    turned: float       # ground-truth yaw change (deg, counter-clockwise positive)

    @property
    def distance(self) -> float:
        return math.hypot(self.forward, self.lateral)


class Robot:
    """The test's handle on the simulated Faulty: actions, faults, ground truth."""

    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.events: list[Event] = []
        self.truth: Odometry | None = None
        self.ids = itertools.count(1000)
        self.actions = rospy.Publisher(f"{NS}/jason/action", Action, queue_size=10)
        self.fault_service = rospy.ServiceProxy(f"{NS}/fault_injector", FaultInjector)
        self._subscribers = [
            rospy.Subscriber(f"{NS}/jason/event", Event, self._on_event, queue_size=100),
            rospy.Subscriber(f"{NS}/ground_truth/odom", Odometry, self._on_truth, queue_size=10)]

    def close(self) -> None:
        for sub in self._subscribers:
            sub.unregister()
        self.actions.unregister()

    def _on_event(self, msg: Event) -> None:
        with self.lock:
            self.events.append(msg)

    def _on_truth(self, msg: Odometry) -> None:
        with self.lock:
            self.truth = msg

    def ground_truth(self) -> Odometry:
        return wait_until(lambda: self.truth, "ground truth from the simulator", timeout=10)

    def inject(self, fault: str) -> str:
        return self.fault_service(fault).return_message

    def send(self, action: str, *params: str, agent: str = "faulty") -> int:
        action_id = next(self.ids)
        self.actions.publish(Action(agent=agent, action_id=action_id, action=action,
                                    parameters=list(params)))
        return action_id

    def events_for(self, action_id: int) -> list[Event]:
        with self.lock:
            return [e for e in self.events
                    if (parse_accepted(e) == action_id
                        or getattr(parse_feedback(e), "action_id", None) == action_id)]

    def wait_feedback(self, action_id: int, timeout: float = ACTION_TIMEOUT) -> Event:
        done = wait_until(lambda: [e for e in self.events_for(action_id)
                                   if e.event_type == "action_feedback"],
                          f"feedback for action {action_id}", timeout=timeout)
        return done[0]

    def settle(self, seconds: float = 0.3) -> None:
        """Let the base come to rest (wall time; the sim runs at least at real time)."""
        time.sleep(seconds)                 # physical rest, not an event to wait for

    def perform(self, action: str, *params: str) -> Outcome:
        """Send one action, wait for its feedback, return it with the ground-truth motion."""
        start = self.ground_truth()
        action_id = self.send(action, *params)
        feedback = self.wait_feedback(action_id)
        self.settle()
        end = self.ground_truth()
        accepted = any(e.event_type == "action_accepted" for e in self.events_for(action_id))
        assert feedback.agent == "faulty"
        parsed = parse_feedback(feedback)
        assert parsed is not None and feedback.parameters[1] == str(action_id)
        yaw0 = yaw_of(start)
        dx = end.pose.pose.position.x - start.pose.pose.position.x
        dy = end.pose.pose.position.y - start.pose.pose.position.y
        turned = math.remainder(yaw_of(end) - yaw0, 2 * math.pi)
        out = Outcome(accepted, parsed.result, parsed.message,
                      forward=dx * math.cos(yaw0) + dy * math.sin(yaw0),
                      lateral=-dx * math.sin(yaw0) + dy * math.cos(yaw0),
                      turned=math.degrees(turned))
        print(f"{action}({', '.join(params)}) -> {out.result} ({out.message}); ground truth: "
              f"forward {out.forward:+.4f} m, lateral {out.lateral:+.4f} m, "
              f"turned {out.turned:+.2f} deg")   # shown with pytest -s
        return out


@pytest.fixture(scope="module")
def robot(ros_session: RosHarness, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Robot]:
    """Sim (sim time, Faulty alone) + injector + decomposer in /faulty, for the whole module."""
    ros = ros_session
    ros.init_rospy()                     # before /use_sim_time: this process keeps wall time
    checkpoint = ros.checkpoint()
    world = Path(tmp_path_factory.mktemp("world")) / "faulty_alone.yaml"
    world.write_text(WORLD)
    ros.set_param("/use_sim_time", True)
    try:
        sim = ros.rosrun("turtlebot_sim", "sim", f"_world:={world}",
                         f"_real_time_factor:={REAL_TIME_FACTOR}")
        injector = ros.rosrun("kobuki_fault_injector", "fault_injector", ns=NS)
        decomposer = ros.rosrun("rason", "motion_decomposer", ns=NS)
        watch = [sim, injector, decomposer]
        ros.wait_for_topic("/clock", watch=watch)
        ros.wait_for_topic(f"{NS}/odom", watch=watch)
        ros.wait_for_service(f"{NS}/fault_injector", watch=watch)
        ros.wait_for_subscriber(f"{NS}/jason/action", watch=watch)
        handle = Robot()
        handle.ground_truth()
        # The publisher's connection to the decomposer must exist before the first action.
        wait_until(lambda: handle.actions.get_num_connections() > 0,
                   "the action publisher's connection to the decomposer", timeout=10)
        # and its answers, each sent once, must reach the test's subscriber
        wait_heard(ros, f"{NS}/motion_decomposer", [f"{NS}/jason/event"], watch=watch)
        yield handle
        handle.close()
    finally:
        ros.rollback(checkpoint)
        ros.set_param("/use_sim_time", False)


@pytest.fixture(autouse=True)
def no_fault_after(robot: Robot) -> Iterator[None]:
    yield
    robot.inject("cancel")
    robot.settle(0.2)


# -- no fault -----------------------------------------------------------------------------------
def test_move_one_metre_ends_ok_within_2_cm(robot: Robot):
    out = robot.perform("move", "1")
    assert out.accepted
    assert out.result == "OK", out.message
    assert out.forward == pytest.approx(1.0, abs=0.02)
    assert abs(out.lateral) < 0.02


def test_move_back_one_metre(robot: Robot):
    out = robot.perform("move", "-1")
    assert out.result == "OK", out.message
    assert out.forward == pytest.approx(-1.0, abs=0.02)


@pytest.mark.parametrize(("degrees", "expected"), [("90", -90.0), ("-90", 90.0)])
def test_turn_ends_within_2_degrees(robot: Robot, degrees: str, expected: float):
    # Positive degrees turn clockwise (right), as the thesis' Helper expects.
    out = robot.perform("turn", degrees)
    assert out.result == "OK", out.message
    assert out.turned == pytest.approx(expected, abs=2.0)
    assert out.distance < 0.02


@pytest.mark.parametrize(("ahead", "expected"), [(120.0, -120.0), (200.0, 160.0)])
def test_turn_to_faces_a_heading_of_the_odometry_frame_the_short_way(robot: Robot, ahead: float,
                                                                      expected: float):
    # turn_to(H): H a heading of the robot's odometry frame, clockwise degrees as turn's; the
    # decomposer turns the short way from wherever the robot stands when the action starts.
    odom = rospy.wait_for_message(f"{NS}/odom", Odometry, timeout=10)
    here = -math.degrees(yaw_of(odom))                      # clockwise, as a camera bearing
    goal = math.remainder(here + ahead, 360.0)
    out = robot.perform("turn_to", f"{goal:.2f}")
    assert out.result == "OK", out.message
    # (within 6 degrees: on a loaded machine the base coasts a few degrees past a long turn)
    assert out.turned == pytest.approx(expected, abs=6.0)
    odom = rospy.wait_for_message(f"{NS}/odom", Odometry, timeout=10)
    assert math.remainder(-math.degrees(yaw_of(odom)) - goal, 360.0) == pytest.approx(0.0, abs=6.0)


# -- faults ---------------------------------------------------------------------------------------
def test_both_actuators_gives_no_progress_and_the_robot_stays(robot: Robot):
    assert "both_actuators" in robot.inject("both_actuators")
    out = robot.perform("move", "1")
    assert out.result == "no_progress", out.message
    assert out.distance < 0.01


def test_odometry_fault_gives_no_progress_while_the_robot_moves(robot: Robot):
    robot.inject("odometry")
    out = robot.perform("move", "1")
    assert out.result == "no_progress", out.message
    assert out.forward > 0.1           # ground truth: it drove for over a second


@pytest.mark.parametrize(("fault", "side"), [("left_actuator", 1.0), ("right_actuator", -1.0)])
def test_actuator_fault_gives_bad_move_curving_to_the_faulty_side(robot: Robot, fault: str,
                                                                  side: float):
    robot.inject(fault)
    out = robot.perform("move", "1")
    assert out.result == "bad_move", out.message
    assert out.forward > 0.05
    assert out.lateral * side > 0.005, f"lateral {out.lateral:.3f} m"
    assert out.turned * side > 5.0     # heading turned toward the faulty wheel


def test_turn_with_an_actuator_fault_still_completes(robot: Robot):
    # Rotation model: the faulty wheel gives half speed, the turn runs at 3/4 rate and the
    # centre drifts a little; odometry integrates the real wheel motion, so the angle is right.
    robot.inject("left_actuator")
    out = robot.perform("turn", "90")
    assert out.result == "OK", out.message
    assert out.turned == pytest.approx(-90.0, abs=2.0)
    assert 0.005 < out.distance < 0.1


def test_unknown_fault_is_refused_and_the_robot_still_drives(robot: Robot, ros_session):
    reply = ros_session.check_output(["rosservice", "call", f"{NS}/fault_injector",
                                      "fault: 'flat_tyre'"])
    assert "unknown fault 'flat_tyre'" in reply
    for name in ("left_actuator", "right_actuator", "both_actuators", "odometry", "cancel"):
        assert name in reply
    status = rospy.wait_for_message(f"{NS}/fault_injector/status", String, timeout=5)
    assert status.data == "none"
    out = robot.perform("move", "0.5")
    assert out.result == "OK", out.message
    assert out.forward == pytest.approx(0.5, abs=0.02)


def test_active_fault_is_published_on_status_and_diagnostics(robot: Robot):
    robot.inject("right_actuator")
    # Latched, and published before the service answered.
    status = rospy.wait_for_message(f"{NS}/fault_injector/status", String, timeout=5)
    assert status.data == "right_actuator"
    # /diagnostics is periodic (1 Hz sim time) besides on change.
    array = rospy.wait_for_message("/diagnostics", DiagnosticArray, timeout=5)
    ours = next(s for s in array.status if s.name == "faulty: fault_injector")
    assert ours.level == DiagnosticStatus.WARN
    assert "right_actuator" in ours.message
    robot.inject("cancel")
    assert rospy.wait_for_message(f"{NS}/fault_injector/status", String, timeout=5).data == "none"


# -- protocol -------------------------------------------------------------------------------------
def test_new_motion_preempts_the_running_one(robot: Robot):
    first = robot.send("move", "1")
    wait_until(lambda: robot.events_for(first), "the first action accepted", timeout=10)
    time.sleep(0.3)                     # the first one runs a while
    second = robot.send("turn", "30")
    preempted = parse_feedback(robot.wait_feedback(first))
    done = parse_feedback(robot.wait_feedback(second))
    assert preempted is not None and preempted.result == "preempted"
    assert done is not None and done.result == "OK", done.message


def test_bad_parameters_and_other_actions(robot: Robot):
    bad = robot.send("move", "far")
    feedback = robot.wait_feedback(bad, timeout=5)
    assert list(feedback.parameters[:2]) == ["bad_parameters", str(bad)]
    assert not [e for e in robot.events_for(bad) if e.event_type == "action_accepted"]
    other = robot.send("say", "hello")
    # the sentinel: an action sent after it is answered (one subscriber thread, in order)
    robot.wait_feedback(robot.send("move", "far"), timeout=5)
    assert robot.events_for(other) == []


def test_agents_parameter_restricts_and_silent_odometry_is_no_progress(robot: Robot, ros_session):
    # A second decomposer, for agent "faulty" only, in a namespace where no odometry arrives.
    ros = ros_session
    checkpoint = ros.checkpoint()
    try:
        node = ros.rosrun("rason", "motion_decomposer", ns="/lonely", params={"agents": ["faulty"]})
        ros.wait_for_subscriber("/lonely/jason/action", watch=[node])
        events: list[Event] = []
        sub = rospy.Subscriber(           # the decomposer's running beats are not answers
            "/lonely/jason/event", Event,
            lambda e: e.event_type != ACTION_RUNNING and events.append(e), queue_size=10)
        pub = rospy.Publisher("/lonely/jason/action", Action, queue_size=10)
        wait_until(lambda: pub.get_num_connections() > 0 and sub.get_num_connections() > 0,
                   "the connections to the second decomposer", timeout=10)
        pub.publish(Action(agent="helper", action_id=1, action="move", parameters=["1"]))
        pub.publish(Action(agent="faulty", action_id=2, action="move", parameters=["1"]))
        wait_until(lambda: len(events) >= 2, "two answers of the second decomposer", timeout=10)
        sub.unregister()
        pub.unregister()
        assert [(e.agent, e.event_type, e.parameters[0]) for e in events] == [
            ("faulty", "action_accepted", "2"), ("faulty", "action_feedback", "no_progress")]
        assert "no odometry" in events[1].parameters[2]
    finally:
        ros.rollback(checkpoint)


# -- run-time settings (docs/agent-node.md, "The motion decomposer's settings") ------------------
DECOMPOSER = f"{NS}/motion_decomposer"


@pytest.fixture
def settings(robot: Robot, ros_session: RosHarness) -> Iterator[Callable[[], str]]:
    """Calls ``~reload``, returning its answer; afterwards every setting set by the test is
    deleted from the parameter server and reloaded (the defaults again)."""
    reload = rospy.ServiceProxy(f"{DECOMPOSER}/reload", Trigger)
    reload.wait_for_service(timeout=10)

    def call() -> str:
        answer = reload()
        return ("" if answer.success else "refused: ") + answer.message

    yield call
    for name in SETTINGS:
        if rospy.has_param(f"{DECOMPOSER}/{name}"):
            rospy.delete_param(f"{DECOMPOSER}/{name}")
    assert not call().startswith("refused")


def test_reload_and_configure_change_settings_without_a_restart(robot: Robot, settings):
    rospy.set_param(f"{DECOMPOSER}/max_distance", 0.4)
    assert "max_distance=0.4" in settings()
    refused = robot.wait_feedback(robot.send("move", "0.5"), timeout=5)
    assert refused.parameters[0] == "bad_parameters", refused.parameters
    # a bad value is refused with the reason and nothing changes
    rospy.set_param(f"{DECOMPOSER}/min_alignment", 1.5)
    answer = settings()
    assert answer.startswith("refused") and "~min_alignment: must be at most 1.0" in answer
    rospy.delete_param(f"{DECOMPOSER}/min_alignment")
    # an agent's configure(Key, Value): answered at once, the running move goes on
    moving = robot.send("move", "0.3")
    time.sleep(0.3)                     # the move runs a while (its pace)
    configured = robot.wait_feedback(robot.send("configure", "max_distance", "10"), timeout=5)
    assert list(configured.parameters[:1]) == ["OK"] and "~max_distance = 10" in \
        configured.parameters[2]
    assert parse_feedback(robot.wait_feedback(moving)).result == "OK"
    wait_until(lambda: rospy.get_param(f"{DECOMPOSER}/max_distance") == 10.0,   # ~reload keeps it
               "max_distance 10 on the parameter server", timeout=5, period=0.05)
    for bad in (["turn_clockwise", "false"], ["linear_gain", "0"], ["reference", "gps"],
                ["curvature"]):
        answer = robot.wait_feedback(robot.send("configure", *bad), timeout=5)
        assert answer.parameters[0] == "bad_parameters", (bad, list(answer.parameters))
    out = robot.perform("move", "0.5")
    assert out.result == "OK", out.message
    assert out.forward == pytest.approx(0.5, abs=0.02)


@pytest.mark.parametrize(("fault", "curvature"), [("left_actuator", "2"),
                                                  ("right_actuator", "-2")])
def test_limp_mode_drives_the_arc_to_the_point_ahead(robot: Robot, settings, fault: str,
                                                     curvature: str):
    # The weak wheel's fault maths (kobuki_fault_injector.faults): a straight command curves
    # at 2 rad/m toward the faulty side at half speed; turns run at 3/4 rate.
    robot.inject(fault)
    for name, value in (("curvature", curvature), ("linear_gain", "0.5"),
                        ("angular_gain", "0.75")):
        answer = robot.wait_feedback(robot.send("configure", name, value), timeout=5)
        assert answer.parameters[0] == "OK", list(answer.parameters)
    out = robot.perform("move", "0.8")
    assert out.result == "OK", out.message
    assert out.forward == pytest.approx(0.8, abs=0.06)
    assert abs(out.lateral) < 0.06
    refused = robot.perform("move", "1.2")           # beyond the longest arc (1 m)
    assert refused.result == "bad_parameters" and "longest arc" in refused.message
    assert refused.distance < 0.01


def test_open_loop_drives_by_the_commands_when_odometry_is_frozen(robot: Robot, settings):
    robot.inject("odometry")
    answer = robot.wait_feedback(robot.send("configure", "reference", "command"), timeout=5)
    assert answer.parameters[0] == "OK", list(answer.parameters)
    out = robot.perform("move", "0.5")
    assert out.result == "OK", out.message
    assert out.forward == pytest.approx(0.5, abs=0.05)
    out = robot.perform("turn", "-90")
    assert out.result == "OK", out.message
    assert out.turned == pytest.approx(90.0, abs=6.0)
