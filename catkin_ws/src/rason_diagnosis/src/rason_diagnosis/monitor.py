"""Watches a cooperative-diagnosis run from outside, in simulated time.

A rospy subscriber set in the demo process that timestamps the three steps of thesis ch. 7 from
what crosses the wire (Faulty's first ``move`` action, its ``helpme`` broadcast, Helper's ``found``
tell, Faulty's ``thanks``), records both robots' true paths and Faulty's odometry path, and keeps
Helper's camera frame from the moment Helper reports its feedback.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np
import rospy
from jason_msgs.msg import Action, AgentMessage
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Image, PointCloud2

from turtlebot_model.geometry import yaw_from_quaternion


@dataclass
class Path2D:
    """Timestamped (t, x, y, yaw) samples, thinned to about 10 Hz."""

    samples: list[tuple[float, float, float, float]] = field(default_factory=list)

    def add(self, t: float, x: float, y: float, yaw: float) -> None:
        if not self.samples or t - self.samples[-1][0] >= 0.1 or t < self.samples[-1][0]:
            self.samples.append((t, x, y, yaw))

    def array(self) -> np.ndarray:
        return np.array(self.samples, dtype=float).reshape(-1, 4)


def _yaw(msg: Odometry) -> float:
    q = msg.pose.pose.orientation
    return yaw_from_quaternion(q.x, q.y, q.z, q.w)


@dataclass
class StepTimes:
    """Simulated-time stamps of the run's milestones (None until seen)."""

    move_start: float | None = None     # Faulty publishes its first move action
    help_request: float | None = None   # Faulty broadcasts achieve helpme
    found: float | None = None          # Helper tells found(...)
    feedback: float | None = None       # Helper sends achieve feedback(...)
    diagnosis: float | None = None      # Faulty concludes (thanks sent / diagnosis belief seen)


class RunMonitor:
    """Subscribes to a running scenario; all times are ROS (simulated) seconds.

    With ``sensors=False`` (real robots over Wi-Fi: :mod:`rason_diagnosis.workstation`) it
    hears only the agents' actions and messages: no ground truth (there is none), no odometry,
    no camera frames (megabytes a second that would cross the robots' link)."""

    def __init__(self, faulty: str = "faulty", helper: str = "helper", odom_topic: str = "odom",
                 image_topic: str = "camera/rgb/image_raw",
                 cloud_topic: str | None = "camera/depth_registered/points",
                 sensors: bool = True):
        """``odom_topic``: Faulty's odometry as its nodes read it; ``image_topic``: Helper's
        colour image; ``cloud_topic``: its cloud, None for none (all relative to the robot's
        namespace)."""
        self.faulty, self.helper = faulty, helper
        self.times = StepTimes()
        self.paths = {"faulty_true": Path2D(), "helper_true": Path2D(), "faulty_odom": Path2D()}
        self.messages: list[tuple[float, str, str, str, str]] = []
        self._lock = threading.Lock()
        self._image: Image | None = None
        self._cloud: PointCloud2 | None = None
        self.feedback_frame: tuple[Image, PointCloud2 | None] | None = None
        self._subs = [
            rospy.Subscriber(f"/{faulty}/jason/action", Action, self.on_action),
            rospy.Subscriber("/jason/messages", AgentMessage, self.on_message, queue_size=100)]
        if not sensors:
            return
        self._subs += [
            rospy.Subscriber(f"/{faulty}/ground_truth/odom", Odometry,
                             lambda m: self._path("faulty_true", m)),
            rospy.Subscriber(f"/{helper}/ground_truth/odom", Odometry,
                             lambda m: self._path("helper_true", m)),
            rospy.Subscriber(f"/{faulty}/{odom_topic}", Odometry,
                             lambda m: self._path("faulty_odom", m)),
            rospy.Subscriber(f"/{helper}/{image_topic}", Image, self.on_image,
                             queue_size=1, buff_size=2**24),
        ]
        if cloud_topic is not None:
            self._subs.append(rospy.Subscriber(f"/{helper}/{cloud_topic}", PointCloud2,
                                               self.on_cloud, queue_size=1, buff_size=2**25))

    def close(self) -> None:
        for sub in self._subs:
            sub.unregister()

    # -- callbacks ------------------------------------------------------------------------------
    def on_action(self, msg: Action) -> None:
        if msg.action == "move" and self.times.move_start is None:
            self.times.move_start = rospy.get_time()

    def on_message(self, msg: AgentMessage) -> None:
        if msg.performative == "presence":
            return
        now = rospy.get_time()
        with self._lock:
            self.messages.append((now, msg.sender, msg.receiver, msg.performative, msg.content))
        t = self.times
        if msg.sender == self.faulty and msg.performative == "achieve":
            if msg.content.startswith("helpme") and t.help_request is None:
                t.help_request = now
            elif msg.content.startswith("thanks") and t.diagnosis is None:
                t.diagnosis = now
        elif msg.sender == self.helper and msg.performative == "tell" \
                and msg.content.startswith("found") and t.found is None:
            t.found = now
        elif msg.sender == self.helper and msg.content.startswith("feedback"):
            t.feedback = now
            with self._lock:
                if self._image is not None:
                    self.feedback_frame = (self._image, self._cloud)

    def on_image(self, msg: Image) -> None:
        with self._lock:
            self._image = msg

    def on_cloud(self, msg: PointCloud2) -> None:
        with self._lock:
            self._cloud = msg

    def _path(self, key: str, msg: Odometry) -> None:
        p = msg.pose.pose.position
        with self._lock:
            self.paths[key].add(msg.header.stamp.to_sec() or rospy.get_time(), p.x, p.y, _yaw(msg))

    def last_frame(self) -> tuple[Image, PointCloud2 | None] | None:
        """The feedback-moment frame, or the latest one if feedback never came."""
        with self._lock:
            if self.feedback_frame is not None:
                return self.feedback_frame
            return (self._image, self._cloud) if self._image is not None else None
