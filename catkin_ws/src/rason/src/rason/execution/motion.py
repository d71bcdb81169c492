"""``rosrun rason motion_decomposer __ns:=/faulty``: the motion decomposer (thesis 6.3).

Turns the agents' ``move(meters)`` and ``turn(degrees)`` into velocity commands and reports
how they ended. Names are relative: run it inside the robot's namespace.

Topics:
    ``jason/action`` (jason_msgs/Action, in): handles ``move``, ``turn`` and ``turn_to``,
        ignores the rest. ``turn_to(degrees)`` turns the short way to a heading of the robot's
        own odometry frame (degrees, positive clockwise with ``turn_clockwise``, as a turn's),
        e.g. a bearing a camera took there (rason_vision's ``seen_at``): the angle is taken from
        the pose when the action starts, so it does not depend on how late the action comes.
    ``jason/event`` (jason_msgs/Event, out): ``action_accepted [action_id]`` when a motion
        starts; ``action_feedback [RESULT, action_id, message]`` when it ends, RESULT one of
        ``OK``, ``no_progress``, ``bad_move``, ``bad_parameters``, ``preempted``, ``cancelled``,
        or the base's safety results ``bumper``, ``cliff``, ``wheel_drop`` (below).
    ``jason/cancel`` (jason_msgs/ActionCancel, in), ``jason/presence`` (the agents'): as every
        decomposer (:mod:`rason.execution.decomposer`): a cancelled action, or one whose agent
        is gone, stops the robot at once and ends ``cancelled``.
    ``cmd_vel`` (geometry_msgs/Twist, out): the drive commands; a zero Twist when a motion
        ends, however it ends. Nothing is published while idle.
    ``odom`` (nav_msgs/Odometry, in): progress and trajectory checks
        (:mod:`rason.execution.progress`).
    ``mobile_base/events/bumper``, ``mobile_base/events/cliff``, ``mobile_base/events/wheel_drop``
        (kobuki_msgs/BumperEvent, CliffEvent, WheelDropEvent, in; kobuki_node's names, remap
        them like any topic): a bumper pressed, a cliff seen or a wheel dropped stops the
        running motion at once (a zero Twist), which ends ``bumper``, ``cliff`` or
        ``wheel_drop`` with a message naming the bumper, sensor or wheel; while it lasts, a
        new motion that would drive into it is refused with the same result (a backward move
        away from a pressed bumper is allowed; :mod:`rason.execution.safety` has the rules).

Private parameters: :class:`MotionParams` (``rosrun rason motion_decomposer --help`` prints
them), those of every decomposer included. With ``~settle_time`` > 0, OK is reported once the
odometry has been still that long after the goal, so that an agent does not act on camera frames
taken while the base coasts (0 reports at the goal, as the thesis did).

Control runs on every odometry message (so it keeps pace with a simulator at any real-time
factor); a rospy.Timer in ROS time catches odometry that stops arriving. All times are ROS
times, so the node works in simulated time (``/use_sim_time`` + ``/clock``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import rosgraph
import rospy
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action
from kobuki_msgs.msg import BumperEvent, CliffEvent, WheelDropEvent
from nav_msgs.msg import Odometry

from rason.execution.decomposer import Decomposer, DecomposerParams, Goal, run
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
from rason.execution.safety import BUMPER, CLIFF, WHEEL_DROP, BaseSafety
from rosnode_kit.params import param
from turtlebot_model.geometry import wrap_rad, yaw_from_quaternion

TURN_TO = "turn_to"


@dataclass(frozen=True)
class MotionParams(DecomposerParams):
    """The motion decomposer's private parameters (speeds in m/s or deg/s, accelerations per
    second), besides those of every decomposer."""

    linear_speed: float = param(0.25, "cruise speed of move (m/s)", minimum=0.001)
    min_linear_speed: float = param(0.02, "creep speed near the goal (m/s)", minimum=0.001)
    linear_accel: float = param(0.5, "m/s^2", minimum=0.001)
    linear_decel: float = param(0.3, "braking to the goal (m/s^2)", minimum=0.001)
    angular_speed: float = param(45.0, "cruise speed of turn (deg/s)", minimum=0.01)
    min_angular_speed: float = param(4.0, "creep speed near the goal (deg/s)", minimum=0.01)
    angular_accel: float = param(90.0, "deg/s^2", minimum=0.01)
    angular_decel: float = param(60.0, "braking to the goal (deg/s^2)", minimum=0.01)
    turn_clockwise: bool = param(True, "positive turn degrees turn right, as the thesis' Helper "
                                 "expects")
    max_distance: float = param(MAX_DISTANCE, "larger |move| (m) ends 'bad_parameters'",
                                minimum=0.0)
    max_angle: float = param(MAX_ANGLE, "larger |turn| (deg) ends 'bad_parameters'", minimum=0.0)
    no_progress_timeout: float = param(1.0, "s of unchanged odometry (or none at the start) "
                                       "before 'no_progress'", minimum=0.01)
    min_alignment: float = param(0.99, "dot product of start->goal and start->now below which "
                                 "a move ends 'bad_move'", minimum=-1.0, maximum=1.0)
    min_travel: float = param(0.05, "m from the start before bad_move is checked", minimum=0.0)
    settle_time: float = param(0.3, "s at rest after the goal before OK (0: OK at the goal)",
                               minimum=0.0)
    settle_timeout: float = param(1.0, "s after the goal at which OK is reported anyway",
                                  minimum=0.0)
    odom_timeout: float = param(1.0, "s of silent odometry during a motion before the robot "
                                "stops, 'no_progress'", minimum=0.01)


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


def motion_text(goal: Goal) -> str:
    """``move(1)``: the action as the agent wrote it."""
    return f"{goal.action}({', '.join(goal.parameters)})"


class MotionDecomposer(Decomposer):
    """move(m) and turn(deg) actions to cmd_vel, checked against odom (thesis 6.3)."""

    actions = (MOVE, TURN, TURN_TO)
    Params = MotionParams

    def setup(self) -> None:
        p: MotionParams = self.params
        self.linear = SpeedLimits(p.linear_speed, p.min_linear_speed, p.linear_accel,
                                  p.linear_decel)
        self.angular = SpeedLimits(*(math.radians(v) for v in (
            p.angular_speed, p.min_angular_speed, p.angular_accel, p.angular_decel)))
        self.checks = CheckParams(
            no_progress_timeout=p.no_progress_timeout, min_alignment=p.min_alignment,
            min_travel=p.min_travel, settle_time=p.settle_time, settle_timeout=p.settle_timeout)
        self.pose: Pose2D | None = None
        self.odom_at = 0.0                    # ROS time (s) of the last odometry message
        self.cmd_vel = rospy.Publisher("cmd_vel", Twist, queue_size=10)
        self.odom_sub = self.subscribe("odom", Odometry, self.on_odom, queue_size=10)
        self.safety = BaseSafety()
        self.subscribe("mobile_base/events/bumper", BumperEvent, lambda msg: self.on_hazard(
            BUMPER, msg.bumper, msg.state == BumperEvent.PRESSED), queue_size=10)
        self.subscribe("mobile_base/events/cliff", CliffEvent, lambda msg: self.on_hazard(
            CLIFF, msg.sensor, msg.state == CliffEvent.CLIFF), queue_size=10)
        self.subscribe("mobile_base/events/wheel_drop", WheelDropEvent, lambda msg: self.on_hazard(
            WHEEL_DROP, msg.wheel, msg.state == WheelDropEvent.DROPPED), queue_size=10)

    # -- the protocol's hooks ----------------------------------------------------------------
    def parse(self, action: str, parameters: list[str]) -> float:
        p: MotionParams = self.params
        if action == TURN_TO:       # a heading (rad, counter-clockwise); the turn: in begin()
            return parse_target(TURN, parameters, p.turn_clockwise, p.max_distance, 360.0)
        return parse_target(action, parameters, p.turn_clockwise, p.max_distance, p.max_angle)

    def start(self, goal: Goal) -> Verdict | None:
        goal.state = Motion(last_step=goal.started)
        if goal.action != TURN_TO:                 # a heading's turn is known in begin()
            refused = self.refusal(goal, goal.action, goal.target)
            if refused is not None:
                return refused
        if self.pose is not None:
            return self.begin(goal, self.pose, goal.started)
        return None

    def step(self, goal: Goal, now: float) -> Verdict | None:
        """The watchdog: odometry that never came, stopped coming, or stopped changing."""
        motion: Motion = goal.state
        if motion.monitor is None:
            waited = now - goal.started
            if waited > self.checks.no_progress_timeout:
                return Verdict(NO_PROGRESS, f"no odometry on odom for {waited:.2f} s"
                                            f"{self._odometry_hint()}")
            return None
        silent = now - self.odom_at
        if silent > self.params.odom_timeout:
            return Verdict(NO_PROGRESS, f"no odometry on odom for {silent:.2f} s during "
                                        f"{goal.action}")
        return motion.monitor.check(now)

    def _odometry_hint(self) -> str:
        """When nobody publishes this node's odom: where odometry is published (the namespace
        must be a robot's, e.g. one of the simulated world's robots); else nothing."""
        topic = self.odom_sub.resolved_name
        try:
            published = rosgraph.Master(rospy.get_name()).getPublishedTopics("")
        except (OSError, rosgraph.MasterException):
            return ""
        if any(name == topic for name, _ in published):
            return ""
        others = sorted(name for name, kind in published if kind == "nav_msgs/Odometry")
        if not others:
            return f" (nobody publishes {topic})"
        return (f" (nobody publishes {topic}; odometry is on {', '.join(others)}: run the "
                "decomposer in a robot's namespace, with its fault_injector beside it)")

    def halt(self, goal: Goal) -> None:
        self.cmd_vel.publish(Twist())

    def preempted(self, goal: Goal, by: Action) -> Verdict:
        monitor = goal.state.monitor if goal.state is not None else None
        if monitor is not None and monitor.settling:          # it did reach its goal
            return monitor.done(", next action before it came to rest")
        return super().preempted(goal, by)

    # -- the base's safety events (called with the lock held) ---------------------------------
    def on_hazard(self, kind: str, index: int, on: bool) -> None:
        """A bumper, cliff or wheel-drop event: a hazard that begins stops every motion."""
        hazard = self.safety.event(kind, index, on)
        if hazard is None:
            return
        for goal in self.running():
            motion: Motion = goal.state
            doing = (motion.monitor.progress_text() if motion.monitor is not None
                     else "nothing (no odometry yet)")
            self.finish(goal, hazard.stopped(motion_text(goal), doing))

    def refusal(self, goal: Goal, kind: str, target: float) -> Verdict | None:
        """The verdict refusing `goal` (a `kind` of signed `target`) if it would drive into an
        active safety hazard."""
        linear, angular = (target, 0.0) if kind == MOVE else (0.0, target)
        return self.safety.refusal(motion_text(goal), linear, angular)

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
        if goal.action == TURN_TO:  # from the heading to the turn that reaches it from here
            goal.target = wrap_rad(goal.target - pose.yaw)
        kind = TURN if goal.action == TURN_TO else goal.action
        if goal.action == TURN_TO:
            refused = self.refusal(goal, kind, goal.target)
            if refused is not None:
                return refused
        motion.monitor = MotionMonitor(kind, goal.target, pose, now, self.checks)
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
    return run(MotionDecomposer, "motion_decomposer",
               usage="rosrun rason motion_decomposer [__ns:=/robot] [_name:=value ...]")
