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

Run-time settings (:data:`SETTINGS`, every private parameter of :class:`MotionParams` but
``~turn_clockwise``), without a restart:
    ``~reload`` (std_srvs/Trigger): read them from the parameter server again (``rosparam set``
        first); a bad value is refused with the reason in the answer and nothing changes.
    ``configure(Key, Value)`` (an action on ``jason/action``, answered at once without stopping
        the running motion): one setting, checked as ``_Key:=Value``; ``OK`` once in force (and
        written to ``~Key``), else ``bad_parameters`` with the reason.
    Speed limits apply from the running motion's next step, the rest from the next motion. With
    ``~curvature`` k (a base whose straight commands curve: a weak wheel), ``move(m)`` turns by
    ``-asin(m k / 2)`` on the spot and then drives the arc whose chord is ``m`` along the heading
    it had, checked against that arc; ``~linear_gain`` and ``~angular_gain`` divide the commands
    so that the base runs at the profile's speeds; ``~reference: command`` drives open loop (the
    commands dead-reckoned, for a base whose odometry cannot be trusted).

Private parameters: :class:`MotionParams` (``rosrun rason motion_decomposer --help`` prints
them), those of every decomposer included. With ``~settle_time`` > 0, OK is reported once the
odometry has been still that long after the goal, so that an agent does not act on camera frames
taken while the base coasts (0 reports at the goal, as the thesis did).

Control runs on every odometry message (so it keeps pace with a simulator at any real-time
factor); a rospy.Timer in ROS time catches odometry that stops arriving. All times are ROS
times, so the node works in simulated time (``/use_sim_time`` + ``/clock``).
"""

from __future__ import annotations

import dataclasses
import math
import threading
from dataclasses import dataclass, field

import rosgraph
import rospy
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action
from kobuki_msgs.msg import BumperEvent, CliffEvent, WheelDropEvent
from nav_msgs.msg import Odometry
from std_srvs.srv import Trigger, TriggerRequest, TriggerResponse

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
    advance,
    arc_pre_turn,
    parse_target,
)
from rason.execution.ramp import SpeedLimits, next_speed
from rason.execution.results import BAD_PARAMETERS
from rason.execution.safety import BUMPER, CLIFF, WHEEL_DROP, BaseSafety
from rosnode_kit.params import ParamError, load, param, with_value
from turtlebot_model.geometry import wrap_rad, yaw_from_quaternion

TURN_TO = "turn_to"
CONFIGURE = "configure"
#: ``~reference``: progress by odometry (closed loop) or by the commands (open loop).
ODOM = "odom"
COMMAND = "command"
REFERENCES = (ODOM, COMMAND)


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
    curvature: float = param(0.0, "rad/m a straight command curves by itself (+ left; a weak "
                             "wheel's limp mode): a move then turns by -asin(m k / 2) first and "
                             "drives the arc whose chord is the move; backward moves are refused "
                             "(0: a straight base)", minimum=-20.0, maximum=20.0)
    linear_gain: float = param(1.0, "the base's speed over the commanded one during a move: "
                               "commands are divided by it", minimum=0.05, maximum=20.0)
    angular_gain: float = param(1.0, "the base's rate over the commanded one during a turn: "
                                "commands are divided by it", minimum=0.05, maximum=20.0)
    reference: str = param(ODOM, "what a motion's progress is measured by: 'odom', or "
                           "'command' (open loop: the commands dead-reckoned with the gains "
                           "and curvature above, at ~watchdog_rate; odometry is not read)")


#: The parameters set at run time (``~reload``, ``configure(Key, Value)``): MotionParams' own
#: but the sign convention of turns, which the agents' plans are written for.
SETTINGS: tuple[str, ...] = tuple(
    f.name for f in dataclasses.fields(MotionParams)
    if f.name not in {g.name for g in dataclasses.fields(DecomposerParams)} | {"turn_clockwise"})


@dataclass
class Reckoning:
    """The open-loop pose (``~reference: command``): where the commands put the robot."""

    pose: Pose2D
    at: float                             # ROS time (s) of the pose
    linear: float = 0.0                   # m/s and rad/s the base is assumed to run at
    angular: float = 0.0


@dataclass
class Phase:
    """One part of a motion: a move (m) or turn (rad, counter-clockwise), and the curvature
    (rad/m) a move's trajectory check follows."""

    kind: str
    target: float
    curvature: float = 0.0


@dataclass
class Motion:
    """A running motion's state: its monitor (None until odometry arrives), speed, and the
    phases still to come (a limp move: the turn before its arc, then the arc)."""

    monitor: MotionMonitor | None = None
    speed: float = 0.0                    # magnitude of the last commanded speed
    last_step: float = 0.0                # ROS time (s) of the last command
    phase: Phase | None = None            # the one running
    next: list[Phase] = field(default_factory=list)


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
    instant = (CONFIGURE,)
    Params = MotionParams

    def setup(self) -> None:
        self.reckoning: Reckoning | None = None   # the open-loop pose (~reference: command)
        self.apply(self.params)
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
        rospy.Service("~reload", Trigger, self.on_reload)

    # -- run-time settings --------------------------------------------------------------------
    def apply(self, p: MotionParams) -> None:
        """Take `p` as the settings in force (checked first: ValueError leaves them as they
        were). Speed limits apply to the running motion from its next step, the rest (the
        checks, curvature, reference) to the next motion."""
        if p.reference not in REFERENCES:
            raise ParamError(f"~reference: one of {', '.join(REFERENCES)}, got {p.reference!r}",
                             "reference")
        linear = SpeedLimits(p.linear_speed, p.min_linear_speed, p.linear_accel, p.linear_decel)
        angular = SpeedLimits(*(math.radians(v) for v in (
            p.angular_speed, p.min_angular_speed, p.angular_accel, p.angular_decel)))
        self.params, self.linear, self.angular = p, linear, angular
        self.checks = CheckParams(
            no_progress_timeout=p.no_progress_timeout, min_alignment=p.min_alignment,
            min_travel=p.min_travel, settle_time=p.settle_time, settle_timeout=p.settle_timeout)
        if p.reference == ODOM:
            self.reckoning = None

    def on_reload(self, request: TriggerRequest) -> TriggerResponse:
        """``~reload``: read the settings (:data:`SETTINGS`) from the parameter server again; a
        bad one is refused with the reason and nothing changes."""
        try:
            given = load(MotionParams)          # the master's answer, without the lock
        except ValueError as err:
            return self.refused(err)
        with self.lock:
            return self.take(given)

    def refused(self, err: Exception) -> TriggerResponse:
        """``~reload``'s answer to settings it cannot take."""
        rospy.logwarn(f"{self.name}: ~reload refused: {err}")
        return TriggerResponse(success=False, message=f"refused, nothing changed: {err}")

    def take(self, given: MotionParams) -> TriggerResponse:
        """Put the settings of `given` in force (the others need a restart)."""
        try:
            fixed = [name for name in dataclasses.asdict(given)
                     if name not in SETTINGS and getattr(given, name) != getattr(self.params,
                                                                                  name)]
            self.apply(dataclasses.replace(
                self.params, **{name: getattr(given, name) for name in SETTINGS}))
        except ValueError as err:
            return self.refused(err)
        message = "reloaded: " + ", ".join(f"{n}={getattr(self.params, n)}" for n in SETTINGS)
        if fixed:
            message += f" (not changed at run time: ~{', ~'.join(fixed)}; restart the node)"
        rospy.loginfo(f"{self.name}: {message}")
        return TriggerResponse(success=True, message=message)

    def answer(self, action: str, parameters: list[str]) -> Verdict:
        """``configure(Key, Value)``: one setting, checked as ``_Key:=Value`` would be, put in
        force and written to the parameter server (so that ``~reload`` keeps it)."""
        if len(parameters) != 2:
            raise ValueError(f"configure takes a setting and a value, got {len(parameters)} "
                             "parameters")
        name, text = (t.strip().strip("'\"") for t in parameters)
        self.apply(with_value(self.params, name, text, SETTINGS))
        value = getattr(self.params, name)
        # written by a thread of its own: the master's answer never holds up the control loop
        threading.Thread(target=self._store, args=(name, value), daemon=True,
                         name=f"{self.name}-configure").start()
        return Verdict(OK, f"~{name} = {value}")

    def _store(self, name: str, value: object) -> None:
        """Write a setting to ``~name`` (a warning when the master cannot take it)."""
        try:
            rospy.set_param(f"~{name}", value)
        except (OSError, KeyError) as err:
            rospy.logwarn(f"{self.name}: ~{name} = {value} is in force but not on the "
                          f"parameter server (a ~reload would undo it): {err}")

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
        if self.params.reference == COMMAND:
            return self.begin(goal, self.reckon(goal.started), goal.started)
        if self.pose is not None:
            return self.begin(goal, self.pose, goal.started)
        return None

    def step(self, goal: Goal, now: float) -> Verdict | None:
        """The watchdog: odometry that never came, stopped coming, or stopped changing; open
        loop (``~reference: command``), the control step on the dead-reckoned pose."""
        motion: Motion = goal.state
        if self.params.reference == COMMAND:
            pose = self.reckon(now)
            if motion.monitor is None:
                return self.begin(goal, pose, now)
            return self.control(goal, pose, now)
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
        verdict = motion.monitor.check(now)
        if verdict is not None and verdict.ok and motion.next and self.pose is not None:
            return self.next_phase(goal, self.pose, now)       # settled after a phase
        return verdict

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
        if self.reckoning is not None:
            self.reckoning.linear = self.reckoning.angular = 0.0

    def reckon(self, now: float) -> Pose2D:
        """The open-loop pose at `now`: the last one advanced by the speeds commanded since
        (from the last odometry pose, or the origin, at the first open-loop motion)."""
        r = self.reckoning
        if r is None:
            r = self.reckoning = Reckoning(self.pose or Pose2D(0.0, 0.0, 0.0), now)
        r.pose = advance(r.pose, r.linear, r.angular, max(0.0, now - r.at))
        r.at = now
        return r.pose

    def preempted(self, goal: Goal, by: Action) -> Verdict:
        monitor = goal.state.monitor if goal.state is not None else None
        if monitor is not None and monitor.settling and not goal.state.next:  # it did arrive
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
        if self.params.reference == COMMAND:     # open loop: the watchdog's step() controls
            return
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
        curvature = self.params.curvature
        if kind == MOVE and curvature and goal.target:   # limp: turn, then the arc
            if goal.target < 0:
                return Verdict(BAD_PARAMETERS, f"{motion_text(goal)}: backward moves are not "
                                               f"planned on a base curving by itself "
                                               f"(~curvature {curvature:g} rad/m)")
            try:
                turn = arc_pre_turn(goal.target, curvature)
            except ValueError as err:
                return Verdict(BAD_PARAMETERS, str(err))
            motion.next = [Phase(TURN, turn), Phase(MOVE, goal.target, curvature)]
        else:
            motion.next = [Phase(kind, goal.target)]
        return self.next_phase(goal, pose, now)

    def next_phase(self, goal: Goal, pose: Pose2D, now: float) -> Verdict | None:
        """Start the motion's next phase at `pose`; OK when none is left."""
        motion: Motion = goal.state
        while motion.next:
            motion.phase = phase = motion.next.pop(0)
            motion.monitor = MotionMonitor(phase.kind, phase.target, pose, now, self.checks,
                                           phase.curvature)
            motion.speed, motion.last_step = 0.0, now
            if motion.monitor.remaining > 0.0:
                return self.control(goal, pose, now)
        return Verdict(OK, f"nothing to do for {motion_text(goal)}")

    def control(self, goal: Goal, pose: Pose2D, now: float) -> Verdict | None:
        """Check the motion at `pose`; its verdict, or command the next speed."""
        motion: Motion = goal.state
        assert motion.monitor is not None and motion.phase is not None
        verdict = motion.monitor.update(pose, now)
        if verdict is not None:
            if verdict.ok and motion.next:
                return self.next_phase(goal, pose, now)
            return verdict
        if motion.monitor.settling:
            if motion.speed:
                motion.speed = 0.0
                self.publish(motion.phase, 0.0)
            return None
        limits = self.linear if motion.phase.kind == MOVE else self.angular
        motion.speed = next_speed(motion.speed, motion.monitor.remaining,
                                  now - motion.last_step, limits)
        motion.last_step = now
        self.publish(motion.phase, math.copysign(motion.speed, motion.phase.target))
        return None

    def publish(self, phase: Phase, velocity: float) -> None:
        """Command `velocity` (m/s or rad/s, what the base should do) for `phase`, divided by
        the base's gain; the open-loop pose assumes the base does it."""
        p: MotionParams = self.params
        twist = Twist()
        if phase.kind == MOVE:
            twist.linear.x = velocity / p.linear_gain
            linear, angular = velocity, velocity * p.curvature
        else:
            twist.angular.z = velocity / p.angular_gain
            linear, angular = 0.0, velocity
        if self.reckoning is not None:
            self.reckon(rospy.get_time())
            self.reckoning.linear, self.reckoning.angular = linear, angular
        self.cmd_vel.publish(twist)


def main() -> int:
    return run(MotionDecomposer, "motion_decomposer",
               usage="rosrun rason motion_decomposer [__ns:=/robot] [_name:=value ...]")
