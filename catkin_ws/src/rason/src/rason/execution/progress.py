"""Progress and trajectory checks of the motion decomposer (thesis 6.3), without rospy.

A :class:`MotionMonitor` watches one ``move`` or ``turn`` through the odometry poses it is fed
(with their ROS times, in seconds) and says when it is over:

* ``OK`` - the odometry change reached ``|value|``: the straight-line distance from the start
  pose for ``move``, the accumulated (unwrapped) yaw change in the commanded direction for
  ``turn``. With ``settle_time`` > 0 the verdict waits until the base has also come to rest
  (odometry unchanged for that long, or ``settle_timeout`` after the goal), so that whoever
  looks next (a camera, an agent) sees the robot where it stopped, not where it was coasting.
* ``no_progress`` - the odometry has not changed (by more than a small epsilon) for more than
  ``no_progress_timeout`` seconds. Checked on every pose and also by :meth:`MotionMonitor.check`
  without a new pose, so a silent odometry topic is caught too.
* ``bad_move`` (``move`` only) - once the robot is ``min_travel`` from the start, the dot
  product of the unit vectors start->goal and start->current dropped below ``min_alignment``
  (0.99, about 8.1 degrees off the line). On a base that curves by itself (a ``curvature``
  k, rad/m, the limp mode of a weak wheel) a move is the arc of that curvature: the expected
  direction of start->current at chord length c is the start heading plus ``asin(c k / 2)``
  (:func:`arc_pre_turn` gives the turn that makes the arc's chord point where the move should).

Everything here is plain arithmetic on :class:`Pose2D`, so it is unit-tested on recorded or
synthetic odometry sequences.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rason.execution.results import BAD_MOVE, NO_PROGRESS, OK, Verdict
from turtlebot_model.geometry import wrap_rad

__all__ = ["BAD_MOVE", "MOVE", "NO_PROGRESS", "OK", "TURN", "CheckParams", "MotionMonitor",
           "Pose2D", "Verdict", "advance", "arc_pre_turn", "parse_target"]

MOVE = "move"
TURN = "turn"
#: Largest ``|move|`` (m) and ``|turn|`` (deg) accepted by default: a room, two full turns.
MAX_DISTANCE = 10.0
MAX_ANGLE = 720.0


@dataclass(frozen=True)
class Pose2D:
    """A planar pose: position (m) and heading (rad, counter-clockwise from x)."""

    x: float
    y: float
    yaw: float


@dataclass(frozen=True)
class CheckParams:
    """Thresholds of the checks (defaults as in the thesis where it gives one)."""

    no_progress_timeout: float = 1.0     # s without odometry change -> no_progress
    position_epsilon: float = 1e-4       # m: smaller position changes are "no change"
    yaw_epsilon: float = math.radians(0.05)  # rad: smaller heading changes are "no change"
    min_alignment: float = 0.99          # dot product of unit vectors below this -> bad_move
    min_travel: float = 0.05             # m from the start before bad_move is checked
    settle_time: float = 0.0             # s at rest required after the goal (0: report at once)
    settle_timeout: float = 1.0          # s after the goal at which OK is reported anyway


class MotionMonitor:
    """Watches one motion from its start pose.

    Args:
        kind: ``move`` (target in metres, negative = backwards) or ``turn`` (target in
            radians, positive = counter-clockwise).
        target: the signed goal.
        start: the odometry pose when the motion started.
        start_time: ROS time (s) of the start.
        curvature: rad/m (counter-clockwise positive) a forward ``move`` curves by itself: its
            trajectory check follows that arc (0: the straight line).
    """

    def __init__(self, kind: str, target: float, start: Pose2D, start_time: float,
                 params: CheckParams | None = None, curvature: float = 0.0):
        if kind not in (MOVE, TURN):
            raise ValueError(f"unknown motion {kind!r}")
        self.kind = kind
        self.target = target
        self.curvature = curvature
        self.start = start
        self.params = params or CheckParams()
        self.pose = start
        self.turned = 0.0                    # accumulated signed yaw change (rad)
        self._still_pose = start             # pose when the odometry last changed
        self._still_since = start_time       # ROS time of that change
        self.reached_at: float | None = None  # ROS time the goal was reached (then: settling)
        heading = start.yaw if target >= 0 else start.yaw + math.pi
        self.goal_direction = (math.cos(heading), math.sin(heading))

    # -- progress ---------------------------------------------------------------------------
    @property
    def travelled(self) -> float:
        """Straight-line distance (m) from the start pose to the current one."""
        return math.hypot(self.pose.x - self.start.x, self.pose.y - self.start.y)

    @property
    def progress(self) -> float:
        """How far the motion went toward |target|, in its unit (m or rad, >= 0 forward)."""
        if self.kind == MOVE:
            return self.travelled
        return self.turned if self.target >= 0 else -self.turned

    @property
    def remaining(self) -> float:
        """|target| minus progress (m or rad); <= 0 when done."""
        return abs(self.target) - self.progress

    @property
    def alignment(self) -> float:
        """Dot product of the unit vectors start->goal and start->current (1 when unknown)."""
        distance = self.travelled
        if distance == 0.0:
            return 1.0
        dx, dy = self.pose.x - self.start.x, self.pose.y - self.start.y
        ux, uy = self.goal_direction
        if self.curvature:
            heading = math.atan2(uy, ux) + math.asin(
                max(-1.0, min(1.0, distance * self.curvature / 2.0)))
            ux, uy = math.cos(heading), math.sin(heading)
        return (dx * ux + dy * uy) / distance

    # -- checks -----------------------------------------------------------------------------
    def update(self, pose: Pose2D, now: float) -> Verdict | None:
        """Take a new odometry pose at ROS time `now` (s); return the verdict if it is over."""
        self.turned += wrap_rad(pose.yaw - self.pose.yaw)
        self.pose = pose
        if self._changed(pose):
            self._still_pose, self._still_since = pose, now
        if self.reached_at is not None:
            return self.check(now)
        if self.remaining <= 0.0:
            if self.params.settle_time <= 0.0:
                return self.done()
            self.reached_at = now
            return self.check(now)
        if (self.kind == MOVE and self.travelled >= self.params.min_travel
                and self.alignment < self.params.min_alignment):
            angle = math.degrees(math.acos(max(-1.0, min(1.0, self.alignment))))
            return Verdict(BAD_MOVE, f"off course: {angle:.1f} deg from the line to the goal "
                                     f"after {self.travelled:.3f} m "
                                     f"(dot product {self.alignment:.3f} < "
                                     f"{self.params.min_alignment})")
        return self.check(now)

    @property
    def settling(self) -> bool:
        """True once the goal is reached while waiting for the base to come to rest."""
        return self.reached_at is not None

    def check(self, now: float) -> Verdict | None:
        """At `now`: OK once settled after the goal; no_progress if the odometry has not
        changed for too long before it."""
        still = now - self._still_since
        if self.reached_at is not None:
            settling = now - self.reached_at
            at_rest = min(still, settling) >= self.params.settle_time
            if at_rest or settling >= self.params.settle_timeout:
                state = "at rest" if at_rest else "still moving"
                return self.done(f", {state} {settling:.2f} s after the goal")
            return None
        if still > self.params.no_progress_timeout:
            return Verdict(NO_PROGRESS, f"odometry unchanged for {still:.2f} s after "
                                        f"{self.progress_text()}")
        return None

    def _changed(self, pose: Pose2D) -> bool:
        ref = self._still_pose
        return (math.hypot(pose.x - ref.x, pose.y - ref.y) > self.params.position_epsilon
                or abs(wrap_rad(pose.yaw - ref.yaw)) > self.params.yaw_epsilon)

    def progress_text(self) -> str:
        """How far the motion got, e.g. ``0.420 m of 1.000 m``."""
        if self.kind == MOVE:
            return f"{self.travelled:.3f} m of {abs(self.target):.3f} m"
        return f"{math.degrees(self.progress):.1f} deg of {math.degrees(abs(self.target)):.1f} deg"

    def done(self, note: str = "") -> Verdict:
        """The OK verdict: the goal was reached (`note` is appended to the message)."""
        if self.kind == MOVE:
            return Verdict(OK, f"moved {self.travelled:.3f} m (goal {abs(self.target):.3f} m)"
                               + note)
        return Verdict(OK, f"turned {math.degrees(self.turned):.1f} deg "
                           f"(goal {math.degrees(self.target):.1f} deg)" + note)


def arc_pre_turn(chord: float, curvature: float) -> float:
    """The turn (rad, counter-clockwise) before a forward arc of `curvature` (rad/m) whose chord
    of `chord` m should point along the heading the robot had: ``-asin(chord * curvature / 2)``.
    ValueError when no arc of that curvature has such a chord (longer than ``2 / |curvature|``)."""
    half = chord * curvature / 2.0
    if abs(half) > 1.0:
        raise ValueError(f"move: {chord:g} m is longer than the longest arc of curvature "
                         f"{curvature:g} rad/m can reach ({2.0 / abs(curvature):.3f} m)")
    return -math.asin(half)


def advance(pose: Pose2D, linear: float, angular: float, dt: float) -> Pose2D:
    """`pose` after `dt` s at (`linear` m/s, `angular` rad/s): exact on the arc."""
    turned = angular * dt
    if abs(turned) < 1e-9:
        return Pose2D(pose.x + linear * dt * math.cos(pose.yaw),
                      pose.y + linear * dt * math.sin(pose.yaw), pose.yaw)
    radius = linear / angular
    yaw = pose.yaw + turned
    return Pose2D(pose.x + radius * (math.sin(yaw) - math.sin(pose.yaw)),
                  pose.y - radius * (math.cos(yaw) - math.cos(pose.yaw)), wrap_rad(yaw))


def parse_target(kind: str, parameters: list[str], turn_clockwise: bool = True,
                 max_distance: float = MAX_DISTANCE, max_angle: float = MAX_ANGLE) -> float:
    """The signed goal of ``move(meters)`` (m) or ``turn(degrees)`` (rad, counter-clockwise).

    ``turn(d)`` with positive ``d`` turns clockwise (to the right) when `turn_clockwise`, as
    the thesis' Helper expects (``turn(5)`` steps right; ``turn(Deg)`` with ``Deg < 0``, a
    robot left of the image centre, turns left). Raises ValueError (-> ``bad_parameters``)
    unless there is exactly one finite number within ``max_distance`` m / ``max_angle`` deg.
    """
    if len(parameters) != 1:
        raise ValueError(f"{kind} takes one number, got {len(parameters)} parameters")
    text = parameters[0].strip()
    try:
        value = float(text)
    except ValueError:
        raise ValueError(f"{kind}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise ValueError(f"{kind}: {text!r} is not a finite number")
    if kind == MOVE:
        if abs(value) > max_distance:
            raise ValueError(f"move: {text} m is beyond the limit of {max_distance:g} m")
        return value
    if kind == TURN:
        if abs(value) > max_angle:
            raise ValueError(f"turn: {text} deg is beyond the limit of {max_angle:g} deg")
        radians = math.radians(value)
        return -radians if turn_clockwise else radians
    raise ValueError(f"unknown motion {kind!r}")
