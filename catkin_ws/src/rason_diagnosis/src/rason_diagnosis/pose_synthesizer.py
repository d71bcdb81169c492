"""``rosrun rason_diagnosis pose_synthesizer __ns:=/robot``: a robot's pose and mission as percepts.

The agents of a mission (agents/mission/) navigate by their own odometry: this synthesizer turns
``odom`` (nav_msgs/Odometry, relative name) into the percepts, at most ``~rate`` times a second of
ROS time:

* ``pose(X, Y, Yaw)``: the odometry pose in the world (room) frame, the odometry frame placed at
  ``~origin_x``, ``~origin_y``, ``~origin_yaw`` (the robot's start pose in the world); X, Y in
  m, Yaw in degrees, counter-clockwise from the world's x axis;
* ``heading(H)``: the current heading as the motion decomposer's ``turn_to`` reads a heading
  (degrees of the odometry frame, positive clockwise), so ``turn_to(H - T)`` turns T degrees
  counter-clockwise from here;
* ``waypoint(I, X, Y)``: the robot's task, ``~waypoints`` (world frame, m), I from 1;
* ``mission_option(no_recovery)``: with ``~no_recovery``, the mission's baseline (no recovery).

With a frozen odometry (the ``odometry`` fault) the pose freezes too, as the robot believes.
"""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass

import rospy
import yaml
from nav_msgs.msg import Odometry

from rason.execution.synthesizer import BadFrame, Synthesizer, SynthesizerParams, run
from rosnode_kit.params import param
from turtlebot_model.geometry import wrap_deg, yaw_from_quaternion


@dataclass(frozen=True)
class PoseParams(SynthesizerParams):
    """The pose synthesizer's parameters (besides every synthesizer's)."""

    origin_x: float = param(0.0, "world x of the odometry frame's origin (m)")
    origin_y: float = param(0.0, "world y of the odometry frame's origin (m)")
    origin_yaw: float = param(0.0, "world heading of the odometry frame (deg, counter-clockwise)")
    rate: float = param(5.0, "most percept lists a second (ROS time)", minimum=0.1)
    waypoints: str = param("[]", "the robot's task: [[x, y], ...] in the world frame (m, YAML)")
    no_recovery: bool = param(False, "add mission_option(no_recovery): the mission's baseline")


@dataclass(frozen=True)
class Frame:
    """Where the odometry frame lies in the world: origin (m) and heading (deg, ccw)."""

    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0

    def pose_percepts(self, ox: float, oy: float, oyaw_rad: float) -> list[str]:
        """``pose`` and ``heading`` for the odometry pose (ox, oy, oyaw_rad)."""
        c, s = math.cos(math.radians(self.yaw)), math.sin(math.radians(self.yaw))
        x, y = self.x + c * ox - s * oy, self.y + s * ox + c * oy
        odom_deg = math.degrees(oyaw_rad)
        yaw = wrap_deg(self.yaw + odom_deg)
        return [f"pose({x:.3f}, {y:.3f}, {yaw:.2f})", f"heading({wrap_deg(-odom_deg):.2f})"]


def task_percepts(waypoints: object, no_recovery: bool) -> list[str]:
    """``waypoint(I, X, Y)`` per waypoint (I from 1), and the mission's options; ValueError
    unless ``waypoints`` is a list of [x, y] pairs of finite numbers."""
    if not isinstance(waypoints, list) or not all(
            isinstance(w, list) and len(w) == 2 and all(
                isinstance(v, (int, float)) and math.isfinite(v) for v in w) for w in waypoints):
        raise ValueError(f"not a list of [x, y]: {waypoints!r}")
    out = [f"waypoint({i}, {float(x):.3f}, {float(y):.3f})"
           for i, (x, y) in enumerate(waypoints, start=1)]
    if no_recovery:
        out.append("mission_option(no_recovery)")
    return out


class PoseSynthesizer(Synthesizer):
    """Odometry to pose(X, Y, Yaw) and heading(H) percepts in the world frame, with the robot's
    waypoints."""

    inputs = (("odom", Odometry),)
    source_suffix = "_pose"
    Params = PoseParams

    def setup(self) -> None:
        p: PoseParams = self.params
        self.frame = Frame(p.origin_x, p.origin_y, p.origin_yaw)
        try:
            self.task = task_percepts(yaml.safe_load(p.waypoints) or [], p.no_recovery)
        except (TypeError, ValueError, yaml.YAMLError) as err:
            rospy.logfatal(f"{self.name}: ~waypoints must be [[x, y], ...]: {err}")
            raise SystemExit(2) from None
        self.period = 1.0 / p.rate
        self.last = -math.inf

    def on_frame(self, *msgs: Odometry) -> None:
        now = rospy.get_time()
        if 0.0 <= now - self.last < self.period:
            return
        self.last = now
        super().on_frame(*msgs)

    def perceive(self, msg: Odometry) -> list[str]:
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w)
        if not all(math.isfinite(v) for v in (p.x, p.y, yaw)):
            raise BadFrame(f"odometry pose is not finite: {p.x}, {p.y}, {yaw}")
        return self.frame.pose_percepts(p.x, p.y, yaw) + self.task


def main() -> int:
    return run(PoseSynthesizer, "pose_synthesizer",
               usage="rosrun rason_diagnosis pose_synthesizer [__ns:=/robot] [_name:=value ...]")


if __name__ == "__main__":
    sys.exit(main())
