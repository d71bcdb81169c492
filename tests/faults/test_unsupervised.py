"""Nothing drives unsupervised (#14 item 1), against real nodes on a real roscore.

One simulated Faulty (pybullet, real time, ROS time = wall time) with a motion decomposer
wired straight to the base (``cmd_vel:=mobile_base/commands/velocity``), and real agent nodes
(``rosrun rason agent``). Each test starts a motion the agent then abandons, or that loses its
supervisor or its odometry, and checks the decomposer's velocity commands in ROS time: a zero
Twist within the bound after the trigger, no non-zero command after it, the action ending
``cancelled`` (or ``no_progress`` / ``bad_parameters``). Motions are turns in place so the
robot never leaves its spot. Latencies are printed (``pytest -s``).
"""

from __future__ import annotations

import itertools
import signal
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, start_agent, wait_heard
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action, ActionCancel, AgentMessage, Event, Perception
from nav_msgs.msg import Odometry
from polling import wait_until

from rason.process.harness import Process, RosHarness
from rason.ros.feedback import parse_accepted, parse_feedback
from rason.ros.presence import PRESENCE

pytestmark = pytest.mark.ros

NS = "/unsup"
WORLD = """\
robots:
  - {name: unsup, kind: faulty, x: 0.0, y: 0.0, yaw: 0.0}
"""
#: The bound the issue sets between an agent's cancel and the robot's stop command.
CANCEL_BOUND = 0.1
PRESENCE_TIMEOUT = 3.5     # the decomposer's default ~presence_timeout
ODOM_TIMEOUT = 1.0         # the motion decomposer's default ~odom_timeout
TICK = 0.05                # its watchdog period (20 Hz)
SENTINEL_TICKS = 4         # watchdog ticks after a stop before the sentinel move is sent


def moving(msg: Twist) -> bool:
    return any(abs(v) > 1e-9 for v in (msg.linear.x, msg.linear.y, msg.linear.z,
                                       msg.angular.x, msg.angular.y, msg.angular.z))


@dataclass
class Log:
    """Everything the test hears, stamped with this process's ROS time on arrival."""

    lock: threading.Lock = field(default_factory=threading.Lock)
    cmd: list[tuple[float, Twist]] = field(default_factory=list)
    cancels: list[tuple[float, ActionCancel]] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    presence: dict[str, float] = field(default_factory=dict)
    odom_at: float = 0.0

    def clear(self) -> None:
        with self.lock:
            self.cmd.clear()
            self.cancels.clear()
            self.events.clear()

    def first_moving(self, timeout: float = 20.0) -> float:
        return self.wait_for("command to move", lambda: next(
            (t for t, m in self.cmd if moving(m)), None), timeout)

    def wait_for(self, what: str, probe, timeout: float = 20.0):
        """``probe()`` (run with the log's lock held) once it is true."""
        def locked():
            with self.lock:
                return probe()
        return wait_until(locked, what, timeout)

    def cancel(self, agent: str, timeout: float = 20.0) -> tuple[float, ActionCancel]:
        return self.wait_for(f"cancel from {agent}",
                             lambda: next(((t, c) for t, c in self.cancels if c.agent == agent),
                                          None), timeout)

    def feedback(self, agent: str, timeout: float = 20.0):
        return self.wait_for(f"feedback for {agent}", lambda: next(
            (parse_feedback(e) for e in self.events
             if e.agent == agent and parse_feedback(e) is not None), None), timeout)

    def stop_after(self, t0: float, timeout: float = 10.0) -> float:
        """ROS time of the first zero Twist at or after `t0`."""
        return self.wait_for("zero cmd_vel", lambda: next(
            (t for t, m in self.cmd if t >= t0 and not moving(m)), None), timeout)

    def turning_between(self, t0: float, t1: float) -> list[float]:
        """ROS times of the turn commands after `t0` and before `t1` (the tests' motions are
        turns; the sentinel is a move)."""
        with self.lock:
            return [t for t, m in self.cmd if m.angular.z and t0 < t < t1]

    def sentinel(self, rig: Rig, after: float) -> float:
        """A short move sent once the decomposer's watchdog has ticked a few times since ROS
        time `after` (a motion driving on would command at each tick), as a sentinel on
        cmd_vel: the ROS time of its first command. The decomposer publishes in order, so a
        turn command it sent before that one has been heard by then. Waits until the move
        ended and its zero Twist came, so that the decomposer is idle for the next test."""
        wait_until(lambda: rospy.get_time() >= after + SENTINEL_TICKS * TICK,
                   "the watchdog's ticks to pass", timeout=10, period=TICK)
        rig.send("sentinel", "move", "0.02")
        t_sentinel = self.wait_for("the sentinel move's first command", lambda: next(
            (t for t, m in self.cmd if m.linear.x), None))
        assert self.feedback("sentinel").result == "OK"
        self.wait_for("the sentinel move's zero Twist", lambda: next(
            (t for t, m in self.cmd if t > t_sentinel and not moving(m)), None))
        return t_sentinel


class Rig:
    """The module's sim + decomposer and this test process's subscriptions."""

    def __init__(self, ros: RosHarness, tmp: Path) -> None:
        self.ros = ros
        self.tmp = tmp
        self.log = Log()
        self.ids = itertools.count(1)
        self.actions = rospy.Publisher(f"{NS}/jason/action", Action, queue_size=10)
        #: tells each agent to go ahead (``+go_ahead``) once we hear what it publishes
        self.gate = rospy.Publisher(f"{NS}/jason/perception", Perception, queue_size=1)
        self.subs = [
            rospy.Subscriber(f"{NS}/mobile_base/commands/velocity", Twist, self._on_cmd,
                             queue_size=100, tcp_nodelay=True),
            rospy.Subscriber(f"{NS}/jason/cancel", ActionCancel, self._on_cancel,
                             queue_size=100, tcp_nodelay=True),
            rospy.Subscriber(f"{NS}/jason/event", Event, self._on_event, queue_size=100),
            rospy.Subscriber(f"{NS}/jason/presence", AgentMessage, self._on_message,
                             queue_size=100),
            rospy.Subscriber(f"{NS}/mobile_base/odom", Odometry, self._on_odom, queue_size=10)]

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()
        self.actions.unregister()
        self.gate.unregister()

    def _on_cmd(self, msg: Twist) -> None:
        with self.log.lock:
            self.log.cmd.append((rospy.get_time(), msg))

    def _on_cancel(self, msg: ActionCancel) -> None:
        with self.log.lock:
            self.log.cancels.append((rospy.get_time(), msg))

    def _on_event(self, msg: Event) -> None:
        with self.log.lock:
            self.log.events.append(msg)

    def _on_message(self, msg: AgentMessage) -> None:
        if msg.performative == PRESENCE:
            with self.log.lock:
                self.log.presence[msg.sender] = rospy.get_time()

    def _on_odom(self, _msg: Odometry) -> None:
        self.log.odom_at = rospy.get_time()

    def agent(self, name: str, source: str, **params: object) -> Process:
        """Start agent `name`, whose `source` begins on ``+go_ahead``: the percept is sent once
        our subscribers hear the agent's node, as its cancel and its presence come once,
        unlatched (under load a subscriber connected seconds after the node was up)."""
        proc = start_agent(self.ros, self.tmp, name, source, ns=NS, **params)
        node = f"{NS}/jason/{name}"
        wait_heard(self.ros, node, (f"{NS}/jason/cancel", f"{NS}/jason/presence"), watch=[proc])
        wait_until(lambda: connected_to(self.gate, node), f"the go-ahead's connection to {node}",
                   watch=[proc])
        self.gate.publish(Perception(source="test", perception=["go_ahead"]))
        return proc

    def send(self, agent: str, action: str, *params: str) -> int:
        action_id = next(self.ids)
        self.actions.publish(Action(agent=agent, action_id=action_id, action=action,
                                    parameters=list(params)))
        return action_id


@pytest.fixture(scope="module")
def rig(ros_session: RosHarness, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Rig]:
    ros = ros_session
    ros.init_rospy()
    ros.set_param("/use_sim_time", False)
    checkpoint = ros.checkpoint()
    tmp = tmp_path_factory.mktemp("unsupervised")
    world = tmp / "world.yaml"
    world.write_text(WORLD)
    try:
        sim = ros.rosrun("turtlebot_sim", "sim", f"_world:={world}", "_camera_rate:=0")
        decomposer = ros.rosrun("rason", "motion_decomposer",
                                "cmd_vel:=mobile_base/commands/velocity",
                                "odom:=mobile_base/odom", ns=NS)
        watch = [sim, decomposer]
        ros.wait_for_topic(f"{NS}/mobile_base/odom", watch=watch)
        ros.wait_for_subscriber(f"{NS}/jason/cancel", watch=watch)
        handle = Rig(ros, tmp)
        handle.sim = sim           # type: ignore[attr-defined]
        wait_until(handle.actions.get_num_connections, f"subscriber of {NS}/jason/action",
                   timeout=10, watch=watch)
        yield handle
        handle.close()
    finally:
        ros.rollback(checkpoint)


@pytest.fixture
def log(rig: Rig, ros_session: RosHarness) -> Iterator[Log]:
    checkpoint = ros_session.checkpoint()
    rig.log.clear()
    yield rig.log
    ros_session.rollback(checkpoint)


def assert_stopped_by_cancel(rig: Rig, log: Log, agent: str, reason: str) -> None:
    t_cancel, cancel = log.cancel(agent)
    assert cancel.reason == reason
    t_stop = log.stop_after(t_cancel - 0.05)
    latency = t_stop - t_cancel
    print(f"cancel ({reason}) -> zero cmd_vel: {latency * 1000:.1f} ms")
    assert latency <= CANCEL_BOUND, f"stop {latency:.3f} s after the cancel"
    assert log.turning_between(t_cancel + CANCEL_BOUND, log.sentinel(rig, t_stop)) == []
    feedback = log.feedback(agent)
    assert feedback.result == "cancelled", feedback
    assert feedback.action_id == cancel.action_id


def test_action_timeout_cancels_and_the_robot_stops(rig: Rig, log: Log):
    agent = rig.agent("timer", """
        +go_ahead[source(percept)] <- !go.
        +!go <- .wait(300); turn(700).
        -!go[error(R)] <- .print("failed: ", R).
        """, action_timeout=1.5)
    t_move = log.first_moving()
    assert_stopped_by_cancel(rig, log, "timer", "action_timeout")
    assert agent.wait_for_line(r"\[timer\] failed: (\w+)", timeout=5).group(1) == \
        "action_timeout"
    t_cancel, _ = log.cancel("timer")
    assert 1.3 <= t_cancel - t_move <= 2.5


@pytest.mark.parametrize("abandon", [".drop_intention(go)", ".fail_goal(go)",
                                     ".succeed_goal(go)", ".drop_all_intentions"])
def test_an_abandoned_intention_cancels_its_action(rig: Rig, log: Log, abandon: str):
    rig.agent("quitter", f"""
        +go_ahead[source(percept)] <- !!go; !!quit.
        +!go <- turn(700); .print("turned").
        -!go <- .print("go failed").
        +!quit <- .wait(1200); {abandon}; .print("abandoned").
        """)
    log.first_moving()
    assert_stopped_by_cancel(rig, log, "quitter", "dropped")


def test_agent_shutdown_cancels_and_the_robot_stops(rig: Rig, log: Log):
    agent = rig.agent("leaver", """
        +go_ahead[source(percept)] <- !go.
        +!go <- turn(700).
        """)
    log.first_moving()
    time.sleep(0.5)                             # a turn under way for a while (its pace)
    agent.signal_group(signal.SIGINT)
    assert_stopped_by_cancel(rig, log, "leaver", "shutdown")


def test_killed_agent_presence_lapses_and_the_robot_stops(rig: Rig, log: Log):
    agent = rig.agent("victim", """
        +go_ahead[source(percept)] <- !go.
        +!go <- .wait(1500); turn(700).
        """)
    t_moving = log.first_moving()
    agent.signal_group(signal.SIGKILL)          # no cancel, no goodbye: only silence
    agent.wait(5)
    # after the turn began: a zero Twist that ended the previous test's move may come late
    t_stop = log.stop_after(t_moving, timeout=PRESENCE_TIMEOUT + 5)
    last_heard = log.presence["victim"]
    after = t_stop - last_heard
    print(f"last presence -> zero cmd_vel: {after:.3f} s (presence timeout {PRESENCE_TIMEOUT})")
    assert PRESENCE_TIMEOUT - 0.2 <= after <= PRESENCE_TIMEOUT + 2 * TICK + CANCEL_BOUND
    assert log.turning_between(t_stop, log.sentinel(rig, t_stop)) == []
    feedback = log.feedback("victim")
    assert feedback.result == "cancelled" and "not heard" in feedback.message
    assert log.cancels == []


def test_silent_odometry_stops_the_robot(rig: Rig, log: Log):
    sim: Process = rig.sim          # type: ignore[attr-defined]
    rig.send("pilot", "turn", "700")
    log.first_moving()
    time.sleep(0.5)                             # a turn under way for a while (its pace)
    sim.signal_group(signal.SIGSTOP)             # the base's odometry stops arriving
    try:
        t_stop = log.stop_after(rospy.get_time() - 0.1, timeout=5)
        last_odom = log.odom_at
        feedback = log.feedback("pilot")
    finally:
        sim.signal_group(signal.SIGCONT)
    after = t_stop - last_odom
    print(f"last odometry -> zero cmd_vel: {after:.3f} s (odom timeout {ODOM_TIMEOUT})")
    assert ODOM_TIMEOUT - 0.1 <= after <= ODOM_TIMEOUT + 2 * TICK + CANCEL_BOUND
    assert feedback.result == "no_progress" and "no odometry" in feedback.message
    assert log.turning_between(t_stop, log.sentinel(rig, t_stop)) == []


@pytest.mark.parametrize(("action", "value"), [
    ("move", "1e9"), ("move", "1e308"), ("move", "nan"), ("move", "inf"), ("move", "-inf"),
    ("move", "10.5"), ("turn", "1e9"), ("turn", "1e308"), ("turn", "NaN"), ("turn", "-Infinity"),
    ("turn", "721")])
def test_bad_parameters_never_move(rig: Rig, log: Log, action: str, value: str):
    bad = rig.send("pilot", action, value)
    feedback = log.feedback("pilot", timeout=5)
    assert feedback.result == "bad_parameters", feedback
    t_sentinel = log.sentinel(rig, rospy.get_time())   # on cmd_vel and jason/event, after it
    with log.lock:
        assert [t for t, _ in log.cmd if t < t_sentinel] == []
        assert bad not in [parse_accepted(e) for e in log.events]


def test_an_agent_sending_move_1e9_gets_bad_parameters(rig: Rig, log: Log):
    agent = rig.agent("bold", """
        +go_ahead[source(percept)] <- !go.
        +!go <- move(1000000000).      // at once: held until the decomposer can answer
        -!go[error(R)] <- .print("failed: ", R).
        """)
    assert agent.wait_for_line(r"\[bold\] failed: (\w+)", timeout=60).group(1) == \
        "bad_parameters"
    with log.lock:
        assert not [m for _, m in log.cmd if moving(m)]


def test_act_giving_up_cancels_and_the_robot_stops(rig: Rig, log: Log):
    # act sends its one cancel on connections it made before sending the action (to our log's
    # subscriber too): once it says "sent", the cancel it will send reaches us
    act = rig.ros.rosrun("rason", "act", "hand", "turn(700)", "--timeout", "2", ns=NS)
    act.wait_for_line(r"^sent turn\(700\) as hand", timeout=30)
    log.first_moving()
    assert act.wait(30) == 2, act.output()
    assert "action cancelled" in act.output()
    assert_stopped_by_cancel(rig, log, "hand", "act: no feedback within 2 s")
