"""``rosrun rason motion_decomposer __ns:=/faulty``: the motion decomposer (thesis 6.3).

Turns the agents' ``move(meters)`` and ``turn(degrees)`` into velocity commands and reports
how they ended. Names are relative: run it inside the robot's namespace.

Topics:
    ``jason/action`` (jason_msgs/Action, in): handles ``move`` and ``turn``, ignores the rest.
    ``jason/event`` (jason_msgs/Event, out): ``action_accepted [action_id]`` when a motion
        starts; ``action_feedback [RESULT, action_id, message]`` when it ends, RESULT one of
        ``OK``, ``no_progress``, ``bad_move``, ``bad_parameters``, ``preempted``, ``cancelled``.
    ``jason/cancel`` (jason_msgs/ActionCancel, in), ``/jason/messages`` (presence): as every
        decomposer (:mod:`rason.execution.decomposer`): a cancelled action, or one whose agent
        is gone, stops the robot at once and ends ``cancelled``.
    ``cmd_vel`` (geometry_msgs/Twist, out): the drive commands; a zero Twist when a motion
        ends, however it ends. Nothing is published while idle.
    ``odom`` (nav_msgs/Odometry, in): progress and trajectory checks
        (:mod:`rason.execution.progress`).

Private parameters (speeds in m/s or deg/s, accelerations per second):
    ``~agents`` (list of str, default []: every agent) handle only these agents' actions;
    ``~presence_timeout`` 3.5 s, ``~timeout`` 0 (none): see :mod:`rason.execution.decomposer`.
    ``~max_distance`` 10 m, ``~max_angle`` 720 deg: larger ``|move|`` / ``|turn|`` (and
    anything not a finite number) end ``bad_parameters`` without moving.
    ``~linear_speed`` 0.25, ``~min_linear_speed`` 0.02, ``~linear_accel`` 0.5,
    ``~linear_decel`` 0.3; ``~angular_speed`` 45, ``~min_angular_speed`` 4,
    ``~angular_accel`` 90, ``~angular_decel`` 60.
    ``~turn_clockwise`` (true): positive ``turn`` degrees turn right, as the thesis' Helper
    expects.
    ``~no_progress_timeout`` 1.0 s, ``~min_alignment`` 0.99, ``~min_travel`` 0.05 m.
    ``~settle_time`` 0.3 s: after the goal, OK is reported once the odometry has been still
    this long (at most ``~settle_timeout`` 1.0 s after the goal); 0 reports at the goal, as
    the thesis did. Without it an agent acts on camera frames taken while the base coasts.
    ``~odom_timeout`` 0.5 s: odometry silent this long during a motion stops the robot and
    ends it ``no_progress``.
    ``~watchdog_rate`` 20 Hz: how often (ROS time) a silent odometry topic is checked.

Control runs on every odometry message (so it keeps pace with a simulator at any real-time
factor); a rospy.Timer in ROS time catches odometry that stops arriving. All times are ROS
times, so the node works in simulated time (``/use_sim_time`` + ``/clock``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import rospy
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action
from nav_msgs.msg import Odometry

from rason.execution.decomposer import Decomposer, Goal, run
from rason.execution.progress import (
    MAX_ANGLE,
    MAX_DISTANCE,
    MOVE,
    NO_PROGRESS,
    OK,
    TURN,
    CheckParams,
    MotionMonitor,
    Pose2D,
    Verdict,
    parse_target,
)
from rason.execution.ramp import SpeedLimits, next_speed
from turtlebot_model.geometry import yaw_from_quaternion


@dataclass
class Motion:
    """A running motion's state: its monitor (None until odometry arrives) and speed."""

    monitor: MotionMonitor | None = None
    speed: float = 0.0                    # magnitude of the last commanded speed
    last_step: float = 0.0                # ROS time (s) of the last command


def pose_of(msg: Odometry) -> Pose2D:
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    pose = Pose2D(p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))
    if not all(math.isfinite(v) for v in (pose.x, pose.y, pose.yaw)):
        raise ValueError(f"odometry pose is not finite: {pose}")
    return pose


class MotionDecomposer(Decomposer):
    """``move``/``turn`` -> ``cmd_vel``, checked against ``odom``."""

    actions = (MOVE, TURN)

    def setup(self) -> None:
        self.linear = SpeedLimits(rospy.get_param("~linear_speed", 0.25),
                                  rospy.get_param("~min_linear_speed", 0.02),
                                  rospy.get_param("~linear_accel", 0.5),
                                  rospy.get_param("~linear_decel", 0.3))
        self.angular = SpeedLimits(*(math.radians(rospy.get_param(f"~{name}", default))
                                     for name, default in (("angular_speed", 45.0),
                                                           ("min_angular_speed", 4.0),
                                                           ("angular_accel", 90.0),
                                                           ("angular_decel", 60.0))))
        self.turn_clockwise: bool = rospy.get_param("~turn_clockwise", True)
        self.max_distance = float(rospy.get_param("~max_distance", MAX_DISTANCE))
        self.max_angle = float(rospy.get_param("~max_angle", MAX_ANGLE))
        self.checks = CheckParams(
            no_progress_timeout=rospy.get_param("~no_progress_timeout", 1.0),
            min_alignment=rospy.get_param("~min_alignment", 0.99),
            min_travel=rospy.get_param("~min_travel", 0.05),
            settle_time=rospy.get_param("~settle_time", 0.3),
            settle_timeout=rospy.get_param("~settle_timeout", 1.0))
        self.odom_timeout = float(rospy.get_param("~odom_timeout", 0.5))
        self.pose: Pose2D | None = None
        self.odom_at = 0.0                    # ROS time (s) of the last odometry message
        self.cmd_vel = rospy.Publisher("cmd_vel", Twist, queue_size=10)
        self.subscribe("odom", Odometry, self.on_odom, queue_size=10)

    # -- the protocol's hooks ----------------------------------------------------------------
    def parse(self, action: str, parameters: list[str]) -> float:
        return parse_target(action, parameters, self.turn_clockwise,
                            self.max_distance, self.max_angle)

    def start(self, goal: Goal) -> Verdict | None:
        goal.state = Motion(last_step=goal.started)
        if self.pose is not None:
            return self.begin(goal, self.pose, goal.started)
        return None

    def step(self, goal: Goal, now: float) -> Verdict | None:
        """The watchdog: odometry that never came, stopped coming, or stopped changing."""
        motion: Motion = goal.state
        if motion.monitor is None:
            waited = now - goal.started
            if waited > self.checks.no_progress_timeout:
                return Verdict(NO_PROGRESS, f"no odometry on odom for {waited:.2f} s")
            return None
        silent = now - self.odom_at
        if silent > self.odom_timeout:
            return Verdict(NO_PROGRESS, f"no odometry on odom for {silent:.2f} s during "
                                        f"{goal.action}")
        return motion.monitor.check(now)

    def halt(self, goal: Goal) -> None:
        self.cmd_vel.publish(Twist())

    def preempted(self, goal: Goal, by: Action) -> Verdict:
        monitor = goal.state.monitor if goal.state is not None else None
        if monitor is not None and monitor.settling:          # it did reach its goal
            return monitor.done(", next action before it came to rest")
        return super().preempted(goal, by)

    # -- control (called with the lock held) -------------------------------------------------
    def on_odom(self, msg: Odometry) -> None:
        now = rospy.get_time()
        self.pose = pose_of(msg)
        self.odom_at = now
        for goal in self.running():
            motion: Motion = goal.state
            verdict = (self.begin(goal, self.pose, now) if motion.monitor is None
                       else self.control(goal, self.pose, now))
            if verdict is not None:
                self.finish(goal, verdict)

    def begin(self, goal: Goal, pose: Pose2D, now: float) -> Verdict | None:
        """Start monitoring `goal` from `pose`, then take the first step."""
        motion: Motion = goal.state
        motion.monitor = MotionMonitor(goal.action, goal.target, pose, now, self.checks)
        if motion.monitor.remaining <= 0.0:          # move(0), turn(0)
            return Verdict(OK, f"nothing to do for {goal.action}(0)")
        return self.control(goal, pose, now)

    def control(self, goal: Goal, pose: Pose2D, now: float) -> Verdict | None:
        """Check the motion at `pose`; its verdict, or command the next speed."""
        motion: Motion = goal.state
        assert motion.monitor is not None
        verdict = motion.monitor.update(pose, now)
        if verdict is not None:
            return verdict
        if motion.monitor.settling:
            if motion.speed:
                motion.speed = 0.0
                self.cmd_vel.publish(Twist())
            return None
        limits = self.linear if goal.action == MOVE else self.angular
        motion.speed = next_speed(motion.speed, motion.monitor.remaining,
                                  now - motion.last_step, limits)
        motion.last_step = now
        velocity = math.copysign(motion.speed, goal.target)
        twist = Twist()
        if goal.action == MOVE:
            twist.linear.x = velocity
        else:
            twist.angular.z = velocity
        self.cmd_vel.publish(twist)
        return None


def main() -> int:
    return run(MotionDecomposer, "motion_decomposer")
