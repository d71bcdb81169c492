"""With a shared key, only signed presence keeps a robot driving (#14 items 1 and 7).

A keyed agent node drives a simulated Faulty (pybullet, real time) through a keyed motion
decomposer; a forger on the graph keeps publishing presence beats in the agent's name:
unsigned, with a made-up signature, and replays of the agent's own signed beats. After the
agent is killed (SIGKILL: no cancel, no goodbye) the decomposer must stop the robot when the
agent's signed beats lapse, as if the forger were not there. Without a key the same forged
beats do keep the action running: the open behaviour docs/faults.md documents, and the proof that the
forger is heard.
"""

from __future__ import annotations

import os
import secrets
import signal
import threading
import time
from collections.abc import Iterator
from copy import deepcopy
from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, start_agent
from geometry_msgs.msg import Twist
from jason_msgs.msg import AgentMessage, Event
from polling import wait_until

from rason.process.harness import RosHarness
from rason.ros.feedback import parse_feedback
from rason.ros.presence import PRESENCE

pytestmark = pytest.mark.ros

#: One simulated robot; its name is the test's namespace (private parameters such as
#: ~auth_key_file stay on the parameter server after a node ends: a namespace per test).
WORLD = """\
robots:
  - {{name: {robot}, kind: faulty, x: 0.0, y: 0.0, yaw: 0.0}}
"""
#: The turn is tried again until it runs: the first one may fail when the agent's or the
#: decomposer's connections take longer than the agent's 1 s wait plus its 2 s ~ack_timeout
#: (no_decomposer), or odometry longer than the decomposer's 1 s no_progress_timeout.
DRIVER = """
    !go.
    +!go <- .wait(1000); turn(700).
    -!go[error_msg(M)] <- .print("the turn failed (", M, "), trying again"); !go.
    """
PRESENCE_TIMEOUT = 3.5        # the decomposer's default ~presence_timeout
TICK = 0.05                   # its watchdog period


class Scene:
    """The test's view of the robot: velocity commands and action feedback, in ROS time."""

    def __init__(self, ns: str) -> None:
        self.ns = ns
        self.lock = threading.Lock()
        self.cmd: list[tuple[float, bool]] = []
        self.feedback: list[tuple[float, object]] = []
        self.signed_beats: list[AgentMessage] = []
        self.subs = [
            rospy.Subscriber(f"{ns}/mobile_base/commands/velocity", Twist, self._on_cmd,
                             queue_size=100, tcp_nodelay=True),
            rospy.Subscriber(f"{ns}/jason/event", Event, self._on_event, queue_size=100),
            rospy.Subscriber(f"{ns}/jason/presence", AgentMessage, self._on_message,
                             queue_size=100)]

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()

    def _on_cmd(self, msg: Twist) -> None:
        moving = abs(msg.linear.x) > 1e-9 or abs(msg.angular.z) > 1e-9
        with self.lock:
            self.cmd.append((rospy.get_time(), moving))

    def _on_event(self, msg: Event) -> None:
        feedback = parse_feedback(msg)
        if feedback is not None and msg.agent == "driver":
            with self.lock:
                self.feedback.append((rospy.get_time(), feedback))

    def _on_message(self, msg: AgentMessage) -> None:
        if msg.sender == "driver" and msg.performative == PRESENCE and msg.signature:
            with self.lock:
                self.signed_beats.append(msg)

    def wait(self, what: str, probe, timeout: float):
        """``probe()`` (run with the scene's lock held) once it is true."""
        def locked():
            with self.lock:
                return probe()
        return wait_until(locked, what, timeout)


class Forger:
    """Publishes presence beats in the driver's name at 20 Hz: unsigned, with a made-up
    signature, and replays of the driver's own signed beats."""

    def __init__(self, scene: Scene) -> None:
        self.scene = scene
        self.pub = rospy.Publisher(f"{scene.ns}/jason/presence", AgentMessage, queue_size=100)
        self.sent = 0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(0.05):
            kind = self.sent % 3
            if kind == 2:
                with self.scene.lock:
                    captured = self.scene.signed_beats[-1:]
                if not captured:
                    kind = 0
            if kind == 2:
                msg = deepcopy(captured[0])                      # a replay, bit for bit
            else:
                msg = AgentMessage(sender="driver", receiver="", performative=PRESENCE,
                                   content="", reply_with="", in_reply_to="",
                                   stamp=rospy.Time.now(), nonce=secrets.token_hex(8),
                                   signature="" if kind == 0 else
                                   "hmac-sha256:" + secrets.token_hex(32))
            self.pub.publish(msg)
            self.sent += 1

    def close(self) -> None:
        self._stop.set()
        self._thread.join(2)
        self.pub.unregister()


@pytest.fixture
def rig(ros: RosHarness, tmp_path: Path) -> Iterator[tuple[RosHarness, Path]]:
    ros.init_rospy()
    key = tmp_path / "fleet.key"
    key.write_text(secrets.token_urlsafe(32) + "\n")
    os.chmod(key, 0o600)
    yield ros, key


def drive_and_kill(ros: RosHarness, tmp_path: Path, key: Path | None):
    """Sim + decomposer + forger + driver agent (keyed when `key`); kill the driver once the
    robot turns. Returns the scene, the forger and the ROS time of the kill."""
    robot = "keyed" if key else "open"
    ns = f"/{robot}"
    keyed = {"auth_key_file": str(key)} if key else {}
    world = tmp_path / f"{robot}.yaml"
    world.write_text(WORLD.format(robot=robot))
    sim = ros.rosrun("turtlebot_sim", "sim", f"_world:={world}", "_camera_rate:=0")
    decomposer = ros.rosrun("rason", "motion_decomposer",
                            "cmd_vel:=mobile_base/commands/velocity", "odom:=mobile_base/odom",
                            ns=ns, params=keyed)
    ros.wait_for_topic(f"{ns}/mobile_base/odom", timeout=60, watch=[sim, decomposer])
    ros.wait_for_subscriber(f"{ns}/jason/presence", timeout=30, watch=[decomposer])
    scene = Scene(ns)
    forger = Forger(scene)
    # the forged beats must reach the decomposer
    wait_until(lambda: connected_to(forger.pub, f"{ns}/motion_decomposer"),
               "the forger's connection to the decomposer", timeout=20, period=0.05)
    agent = start_agent(ros, tmp_path, "driver", DRIVER, ns=ns, **keyed)
    scene.wait("turning command", lambda: any(m for _, m in scene.cmd), 60)
    if key:
        scene.wait("signed beat to replay", lambda: scene.signed_beats, 10)
    time.sleep(0.5)                             # the turn under way for a while (its pace)
    agent.signal_group(signal.SIGKILL)          # no cancel, no goodbye: only silence
    agent.wait(5)
    return scene, forger, rospy.get_time()


def test_with_a_key_forged_presence_does_not_keep_the_robot_driving(rig):
    ros, key = rig
    scene, forger, killed = drive_and_kill(ros, key.parent, key)
    try:
        t_end, feedback = scene.wait(
            "feedback for the killed driver", lambda: scene.feedback[:1] and scene.feedback[0],
            PRESENCE_TIMEOUT + 5)
        assert feedback.result == "cancelled" and "not heard" in feedback.message, feedback
        print(f"kill -> cancelled: {t_end - killed:.2f} s, with {forger.sent} forged beats sent")
        assert t_end - killed <= PRESENCE_TIMEOUT + 2 * TICK + 0.5
        # A sentinel on cmd_vel would be a later motion, which a keyed decomposer only takes
        # from a present, keyed agent: none is left, so a second is given to late commands.
        time.sleep(1.0)
        with scene.lock:
            stops = [t for t, m in scene.cmd if not m and t >= killed]
            late = [t for t, m in scene.cmd if m and t > t_end + 0.1]
        assert stops, "no stop command after the kill"
        assert late == [], f"still commanded to move {len(late)} times after the cancel"
        assert forger.sent > 50
    finally:
        forger.close()
        scene.close()


def test_without_a_key_the_same_forged_presence_keeps_the_action_running(rig):
    ros, key = rig
    scene, forger, killed = drive_and_kill(ros, key.parent, None)
    try:
        # the sentinel: a command to move stamped a second past the presence timeout (the
        # decomposer would have cancelled by then); till then, no feedback
        scene.wait("a command to move past the presence timeout", lambda: any(
            m for t, m in scene.cmd if t > killed + PRESENCE_TIMEOUT + 1.0), PRESENCE_TIMEOUT + 10)
        with scene.lock:
            assert scene.feedback == []
    finally:
        forger.close()
        scene.close()
