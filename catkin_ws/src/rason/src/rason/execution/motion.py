"""``rosrun rason motion_decomposer __ns:=/faulty``: the motion decomposer (thesis 6.3).

Turns the agents' ``move(meters)`` and ``turn(degrees)`` into velocity commands and reports
how they ended. Names are relative: run it inside the robot's namespace.

Topics:
    ``jason/action`` (jason_msgs/Action, in): handles ``move`` and ``turn``, ignores the rest.
    ``jason/event`` (jason_msgs/Event, out): ``action_accepted [action_id]`` when a motion
        starts; ``action_feedback [RESULT, action_id, message]`` when it ends, RESULT one of
        ``OK``, ``no_progress``, ``bad_move``, ``bad_parameters``, ``preempted``.
    ``cmd_vel`` (geometry_msgs/Twist, out): the drive commands; a zero Twist when a motion
        ends, however it ends. Nothing is published while idle.
    ``odom`` (nav_msgs/Odometry, in): progress and trajectory checks
        (:mod:`rason.execution.progress`).

Private parameters (speeds in m/s or deg/s, accelerations per second):
    ``~agents`` (list of str, default []: every agent) handle only these agents' actions.
    ``~linear_speed`` 0.25, ``~min_linear_speed`` 0.02, ``~linear_accel`` 0.5,
    ``~linear_decel`` 0.3; ``~angular_speed`` 45, ``~min_angular_speed`` 4,
    ``~angular_accel`` 90, ``~angular_decel`` 60.
    ``~turn_clockwise`` (true): positive ``turn`` degrees turn right, as the thesis' Helper
    expects.
    ``~no_progress_timeout`` 1.0 s, ``~min_alignment`` 0.99, ``~min_travel`` 0.05 m.
    ``~settle_time`` 0.3 s: after the goal, OK is reported once the odometry has been still
    this long (at most ``~settle_timeout`` 1.0 s after the goal); 0 reports at the goal, as
    the thesis did. Without it an agent acts on camera frames taken while the base coasts.
    ``~watchdog_rate`` 20 Hz: how often (ROS time) a silent odometry topic is checked.

Control runs on every odometry message (so it keeps pace with a simulator at any real-time
factor); a rospy.Timer in ROS time catches odometry that stops arriving. All times are ROS
times, so the node works in simulated time (``/use_sim_time`` + ``/clock``).
"""

from __future__ import annotations

import math
import threading
from dataclasses import dataclass

import rospy
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action, Event
from nav_msgs.msg import Odometry

from rason.execution.progress import (
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
from rason.ros.feedback import ACTION_ACCEPTED, ACTION_FEEDBACK
from turtlebot_model.geometry import yaw_from_quaternion

BAD_PARAMETERS = "bad_parameters"
PREEMPTED = "preempted"
MOTIONS = (MOVE, TURN)


@dataclass
class Motion:
    """The running action: who asked, what, and its monitor (None until odometry arrives)."""

    agent: str
    action_id: int
    kind: str
    target: float
    received: float                       # ROS time (s) the action arrived
    monitor: MotionMonitor | None = None
    speed: float = 0.0                    # magnitude of the last commanded speed
    last_step: float = 0.0                # ROS time (s) of the last command


def pose_of(msg: Odometry) -> Pose2D:
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    return Pose2D(p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w))


class MotionDecomposer:
    """The node's state, callbacks and control step (one lock around all of them)."""

    def __init__(self) -> None:
        # -- parameters ---------------------------------------------------------------------
        agents = rospy.get_param("~agents", [])
        self.agents: set[str] = {agents} if isinstance(agents, str) else set(agents)
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
        self.checks = CheckParams(
            no_progress_timeout=rospy.get_param("~no_progress_timeout", 1.0),
            min_alignment=rospy.get_param("~min_alignment", 0.99),
            min_travel=rospy.get_param("~min_travel", 0.05),
            settle_time=rospy.get_param("~settle_time", 0.3),
            settle_timeout=rospy.get_param("~settle_timeout", 1.0))
        watchdog_rate: float = rospy.get_param("~watchdog_rate", 20.0)

        # -- state --------------------------------------------------------------------------
        self.lock = threading.Lock()
        self.pose: Pose2D | None = None
        self.motion: Motion | None = None

        # -- topics -------------------------------------------------------------------------
        self.events = rospy.Publisher("jason/event", Event, queue_size=50)
        self.cmd_vel = rospy.Publisher("cmd_vel", Twist, queue_size=10)
        rospy.Subscriber("odom", Odometry, self.on_odom, queue_size=10)
        rospy.Subscriber("jason/action", Action, self.on_action, queue_size=50)
        rospy.Timer(rospy.Duration(1.0 / watchdog_rate), self.on_watchdog)

    # -- callbacks --------------------------------------------------------------------------
    def on_action(self, msg: Action) -> None:
        if msg.action not in MOTIONS or (self.agents and msg.agent not in self.agents):
            return
        try:
            target = parse_target(msg.action, list(msg.parameters), self.turn_clockwise)
        except ValueError as err:
            self.feedback(msg.agent, msg.action_id, BAD_PARAMETERS, str(err))
            return
        now = rospy.Time.now().to_sec()
        with self.lock:
            if self.motion is not None:
                old = self.motion
                if old.monitor is not None and old.monitor.settling:   # it did reach its goal
                    self.finish(old.monitor.done(", next action before it came to rest"))
                else:
                    self.finish(Verdict(PREEMPTED, f"preempted by {msg.action}"
                                                   f"({', '.join(msg.parameters)}) "
                                                   f"(action {msg.action_id})"))
                    rospy.loginfo("motion_decomposer: action %d preempted", old.action_id)
            self.motion = Motion(msg.agent, msg.action_id, msg.action, target, now, last_step=now)
            self.publish_event(msg.agent, ACTION_ACCEPTED, [str(msg.action_id)])
            rospy.loginfo("motion_decomposer: %s %s(%s) (action %d)", msg.agent, msg.action,
                          ", ".join(msg.parameters), msg.action_id)
            if self.pose is not None:
                self.begin(self.pose, now)

    def on_odom(self, msg: Odometry) -> None:
        now = rospy.Time.now().to_sec()
        with self.lock:
            self.pose = pose_of(msg)
            motion = self.motion
            if motion is None:
                return
            if motion.monitor is None:
                self.begin(self.pose, now)
            else:
                self.step(self.pose, now)

    def on_watchdog(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.Time.now().to_sec()
        with self.lock:
            motion = self.motion
            if motion is None:
                return
            if motion.monitor is None:
                waited = now - motion.received
                if waited > self.checks.no_progress_timeout:
                    self.finish(Verdict(NO_PROGRESS, f"no odometry on odom for {waited:.2f} s"))
                return
            verdict = motion.monitor.check(now)
            if verdict is not None:
                self.finish(verdict)

    # -- control (called with the lock held) ---------------------------------------------------
    def begin(self, pose: Pose2D, now: float) -> None:
        """Start monitoring the current motion from `pose`, then take the first step."""
        motion = self.motion
        assert motion is not None
        motion.monitor = MotionMonitor(motion.kind, motion.target, pose, now, self.checks)
        if motion.monitor.remaining <= 0.0:          # move(0), turn(0)
            self.finish(Verdict(OK, f"nothing to do for {motion.kind}(0)"))
            return
        self.step(pose, now)

    def step(self, pose: Pose2D, now: float) -> None:
        """Check the motion at `pose`; finish it or command the next speed."""
        motion = self.motion
        assert motion is not None and motion.monitor is not None
        verdict = motion.monitor.update(pose, now)
        if verdict is not None:
            self.finish(verdict)
            return
        if motion.monitor.settling:
            if motion.speed:
                motion.speed = 0.0
                self.cmd_vel.publish(Twist())
            return
        limits = self.linear if motion.kind == MOVE else self.angular
        motion.speed = next_speed(motion.speed, motion.monitor.remaining,
                                  now - motion.last_step, limits)
        motion.last_step = now
        velocity = math.copysign(motion.speed, motion.target)
        twist = Twist()
        if motion.kind == MOVE:
            twist.linear.x = velocity
        else:
            twist.angular.z = velocity
        self.cmd_vel.publish(twist)

    def finish(self, verdict: Verdict) -> None:
        """Stop the robot and report how the current motion ended."""
        motion = self.motion
        assert motion is not None
        self.motion = None
        self.cmd_vel.publish(Twist())
        self.feedback(motion.agent, motion.action_id, verdict.result, verdict.message)

    # -- events -----------------------------------------------------------------------------
    def feedback(self, agent: str, action_id: int, result: str, message: str) -> None:
        rospy.loginfo("motion_decomposer: action %d -> %s (%s)", action_id, result, message)
        self.publish_event(agent, ACTION_FEEDBACK, [result, str(action_id), message])

    def publish_event(self, agent: str, event_type: str, parameters: list[str]) -> None:
        self.events.publish(Event(agent=agent, event_type=event_type, parameters=parameters))

    def shutdown(self) -> None:
        """Leave the robot stopped if the node ends during a motion."""
        with self.lock:
            if self.motion is not None:
                self.cmd_vel.publish(Twist())


def main() -> int:
    rospy.init_node("motion_decomposer")
    node = MotionDecomposer()
    rospy.on_shutdown(node.shutdown)
    rospy.loginfo("motion_decomposer ready in namespace %s", rospy.get_namespace())
    rospy.spin()
    return 0
