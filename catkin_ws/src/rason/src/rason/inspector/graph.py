"""The inspector's ROS side: finds agents and robots on the graph and feeds the store.

Agents are found through presence on ``/jason/messages`` (the same announcements the agents use
for ``.all_names``, expired with the same :class:`rason.ros.presence.Directory`); the master's
topic list then gives each agent's ``.../jason/NAME/mind_state`` topic, wherever its namespace.
Robots are found by their topics: ``/R/odom`` and ``/R/ground_truth/odom`` (nav_msgs/Odometry),
``/R/jason/perception`` (jason_msgs/Perception), ``/R/camera/rgb/image_raw`` (sensor_msgs/Image,
subscribed only while a page is open) and ``/diagnostics``.
"""

from __future__ import annotations

import threading

import rospy
from diagnostic_msgs.msg import DiagnosticArray
from jason_msgs.msg import AgentMessage, Perception
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image
from std_msgs.msg import String

from rason.inspector.store import MAX_NAME, BadMindState, CameraFrame, InspectorStore, Pose
from rason.ros.presence import GOODBYE, MESSAGES_TOPIC, PRESENCE, Directory
from rosnode_kit.badinput import shorten
from turtlebot_model.geometry import yaw_from_quaternion

MIND_STATE_SUFFIX = "/mind_state"
ODOM = "nav_msgs/Odometry"
CAMERA_SUFFIX = "/camera/rgb/image_raw"


class GraphWatcher:
    """Subscriptions of the inspector node; call :meth:`start` after ``rospy.init_node``."""

    def __init__(self, store: InspectorStore, presence_timeout: float = 3.5,
                 scan_period: float = 1.0) -> None:
        self.store = store
        self.directory = Directory(presence_timeout)
        self.scan_period = scan_period
        self._subscribers: dict[str, rospy.Subscriber] = {}
        self._camera_topics: dict[str, str] = {}          # topic -> robot
        self._camera_subs: dict[str, rospy.Subscriber] = {}
        self._camera_wanted = False
        self._camera_seq = 0
        self._lock = threading.Lock()

    def start(self) -> None:
        rospy.Subscriber(MESSAGES_TOPIC, AgentMessage, self.on_message, queue_size=200)
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.on_diagnostics, queue_size=20)
        rospy.Timer(rospy.Duration(self.scan_period), self.on_scan)
        self.scan()

    # -- agents ----------------------------------------------------------------------------------
    def on_message(self, msg: AgentMessage) -> None:
        if msg.performative == PRESENCE and msg.content == GOODBYE:
            self.directory.forget(msg.sender)
            self.store.agent_gone(msg.sender)
            return
        if not msg.sender or len(msg.sender) > MAX_NAME:
            return
        self.directory.heard(msg.sender, rospy.get_time())
        refused = self.store.refused
        if not self.store.agent_heard(msg.sender) and self.store.refused > refused:
            rospy.logwarn_throttle(10.0, "mind inspector: %d agents listed (~max_agents): %d "
                                   "newcomers ignored so far", self.store.max_agents, refused + 1)

    def on_mind_state(self, msg: String, name: str) -> None:
        try:
            self.store.add_state(name, msg.data, rospy.get_time())
        except (BadMindState, KeyError) as err:
            rospy.logwarn_throttle(10.0, "mind_state of %s ignored: %s", name,
                                   shorten(str(err)))

    # -- the graph ---------------------------------------------------------------------------------
    def on_scan(self, _event: rospy.timer.TimerEvent) -> None:
        try:
            self.scan()
        except Exception as err:  # a master that is gone for a moment must not stop the node
            rospy.logwarn_throttle(30.0, "mind inspector: cannot read the graph: %s", err)

    def scan(self) -> None:
        """Expire silent agents; subscribe to new mind_state, odometry, perception topics."""
        for gone in self.directory.expire(rospy.get_time()):
            self.store.agent_gone(gone)
        topics = rospy.get_published_topics()
        waiting = set(self.store.without_topic())
        for topic, kind in topics:
            parts = topic.strip("/").split("/")
            if kind == "std_msgs/String" and topic.endswith(MIND_STATE_SUFFIX) \
                    and len(parts) >= 3 and parts[-3] == "jason" and parts[-2] in waiting:
                # also a topic subscribed before: an agent that lapsed before its first state
                # was forgotten, and is back without one
                name = parts[-2]
                if topic not in self._subscribers:
                    self._subscribe(topic, String, self.on_mind_state, name)
                self.store.set_topic(name, topic)
            elif topic in self._subscribers:
                continue
            elif kind == ODOM and len(parts) == 2 and parts[1] == "odom":
                self._subscribe(topic, Odometry, self.on_odom, (parts[0], False))
            elif kind == ODOM and parts[1:] == ["ground_truth", "odom"]:
                self._subscribe(topic, Odometry, self.on_odom, (parts[0], True))
            elif kind == "jason_msgs/Perception" and parts[1:] == ["jason", "perception"]:
                self._subscribe(topic, Perception, self.on_perception, parts[0])
            elif kind == "sensor_msgs/Image" and topic.endswith(CAMERA_SUFFIX) and len(parts) == 4:
                with self._lock:
                    self._camera_topics[topic] = parts[0]
        self._update_cameras()

    def _subscribe(self, topic: str, kind: type, callback, arg) -> None:
        self._subscribers[topic] = rospy.Subscriber(topic, kind, callback, callback_args=arg,
                                                    queue_size=5)

    # -- robots ------------------------------------------------------------------------------------
    def on_odom(self, msg: Odometry, key: tuple[str, bool]) -> None:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.store.robots.pose(key[0], key[1], Pose(
            p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w), msg.header.stamp.to_sec()))

    def on_perception(self, msg: Perception, robot: str) -> None:
        self.store.robots.perception(robot, msg.source, list(msg.perception))

    def on_diagnostics(self, msg: DiagnosticArray) -> None:
        for status in msg.status:
            self.store.robots.diagnostic(status.name, int.from_bytes(status.level, "little")
                                         if isinstance(status.level, bytes) else int(status.level),
                                         status.message, {kv.key: kv.value for kv in status.values},
                                         msg.header.stamp.to_sec())

    def want_camera(self, wanted: bool) -> None:
        """Subscribe to the cameras only while someone looks (a frame is 0.9 MB, 15 a second)."""
        with self._lock:
            self._camera_wanted = wanted
        self._update_cameras()

    def _update_cameras(self) -> None:
        with self._lock:
            if self._camera_wanted:
                for topic, robot in self._camera_topics.items():
                    if topic not in self._camera_subs:
                        self._camera_subs[topic] = rospy.Subscriber(
                            topic, Image, self.on_image, callback_args=robot, queue_size=1,
                            buff_size=4 * 1024 * 1024)
            else:
                for sub in self._camera_subs.values():
                    sub.unregister()
                self._camera_subs.clear()

    def on_image(self, msg: Image, robot: str) -> None:
        self._camera_seq += 1
        self.store.robots.camera(robot, CameraFrame(
            self._camera_seq, msg.header.stamp.to_sec(), msg.width, msg.height, msg.encoding,
            bytes(msg.data)))
