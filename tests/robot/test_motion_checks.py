"""Progress and trajectory checks of the motion decomposer on odometry sequences.

Synthetic sequences are integrated with a unicycle model at 50 Hz, the rate a Kobuki publishes
odometry, from the velocities a faulty or healthy base would execute. Recorded ones
(``data/odom_<fault>.csv``, made by ``record_odometry.py``) are what the decomposer saw from
turtlebot_sim behind the fault injector while the base was driven at 0.2 m/s.
"""

from __future__ import annotations

import csv
import math
from collections.abc import Iterator
from pathlib import Path

import pytest

from rason.execution.progress import (
    BAD_MOVE,
    MOVE,
    NO_PROGRESS,
    OK,
    TURN,
    CheckParams,
    MotionMonitor,
    Pose2D,
    advance,
    arc_pre_turn,
    parse_target,
)
from rason.execution.ramp import SpeedLimits, next_speed
from turtlebot_model.geometry import wrap_rad, yaw_from_quaternion

RATE = 50.0
DATA = Path(__file__).resolve().parent / "data"
ORIGIN = Pose2D(0.0, 0.0, 0.0)


def drive(v: float, w: float, seconds: float, start: Pose2D = ORIGIN,
          t0: float = 0.0) -> Iterator[tuple[Pose2D, float]]:
    """Odometry poses (and times) of a base moving at (v, w) from `start`."""
    x, y, yaw = start.x, start.y, start.yaw
    dt = 1.0 / RATE
    for i in range(1, int(seconds * RATE) + 1):
        x += v * math.cos(yaw) * dt
        y += v * math.sin(yaw) * dt
        yaw = wrap_rad(yaw + w * dt)
        yield Pose2D(x, y, yaw), t0 + i * dt


def run(monitor: MotionMonitor, poses) -> tuple[str | None, float, Pose2D]:
    """Feed poses until a verdict; return (result, time, pose) at that moment."""
    pose, t = monitor.start, 0.0
    for pose, t in poses:
        verdict = monitor.update(pose, t)
        if verdict:
            return verdict.result, t, pose
    return None, t, pose


# -- move ----------------------------------------------------------------------------------------
def test_straight_move_ends_ok_at_the_distance():
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    result, t, pose = run(monitor, drive(0.25, 0.0, 10))
    assert result == OK
    assert pose.x == pytest.approx(1.0, abs=0.25 / RATE)
    assert t == pytest.approx(4.0, abs=0.05)


def test_backward_move_in_any_heading_ends_ok():
    start = Pose2D(2.0, -1.0, math.radians(135))
    monitor = MotionMonitor(MOVE, -0.5, start, 0.0)
    result, _, pose = run(monitor, drive(-0.2, 0.0, 10, start))
    assert result == OK
    assert math.hypot(pose.x - 2.0, pose.y + 1.0) == pytest.approx(0.5, abs=0.01)


@pytest.mark.parametrize(("w", "side"), [(0.2, 1), (-0.2, -1)])
def test_actuator_fault_curve_is_a_bad_move(w, side):
    # Eq. 6.2/6.3 for x = 0.2: v = 0.1, w = +-0.2 -> a 0.5 m circle toward the faulty wheel.
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    result, _, pose = run(monitor, drive(0.1, w, 20))
    assert result == BAD_MOVE
    assert math.copysign(1, pose.y) == side
    # arccos(0.99) = 8.1 deg off the line = half the heading change on a circle.
    assert monitor.alignment < 0.99
    assert monitor.travelled == pytest.approx(2 * 0.5 * math.sin(math.acos(0.99)), abs=0.01)


@pytest.mark.parametrize("k", [2.0, -2.0])
def test_a_limp_move_is_the_arc_of_the_curvature_it_expects(k):
    # A weak wheel's base curves at k rad/m; turned by arc_pre_turn first, the arc's chord
    # points along the heading the robot had, and the check follows the arc, not the line.
    turn = arc_pre_turn(0.8, k)
    assert turn == pytest.approx(-math.asin(0.8 * k / 2))
    start = Pose2D(0.0, 0.0, turn)
    monitor = MotionMonitor(MOVE, 0.8, start, 0.0, curvature=k)
    result, _, pose = run(monitor, drive(0.1, 0.1 * k, 30, start))
    assert result == OK
    assert (pose.x, pose.y) == pytest.approx((0.8, 0.0), abs=0.01)
    straight = MotionMonitor(MOVE, 0.8, start, 0.0)         # the same arc, checked as a line
    assert run(straight, drive(0.1, 0.1 * k, 30, start))[0] == BAD_MOVE
    wrong = MotionMonitor(MOVE, 0.8, start, 0.0, curvature=-k)  # the other wheel: off the arc
    assert run(wrong, drive(0.1, 0.1 * k, 30, start))[0] == BAD_MOVE
    with pytest.raises(ValueError, match="longest arc"):
        arc_pre_turn(1.01, k)


def test_advance_follows_the_arc_exactly():
    quarter = advance(Pose2D(0.0, 0.0, 0.0), 0.5, 1.0, math.pi / 2)   # radius 0.5 m
    assert (quarter.x, quarter.y, quarter.yaw) == pytest.approx((0.5, 0.5, math.pi / 2))
    straight = advance(Pose2D(1.0, 1.0, math.pi), 0.2, 0.0, 2.0)
    assert (straight.x, straight.y) == pytest.approx((0.6, 1.0))


def test_reversing_instead_of_advancing_is_a_bad_move():
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    assert run(monitor, drive(-0.2, 0.0, 5))[0] == BAD_MOVE


def test_noise_before_the_minimum_travel_is_not_a_bad_move():
    # Sideways jitter of 1 cm near the start: way off the line, but under min_travel (5 cm).
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    jitter = [(Pose2D(0.005 * i, 0.01 * (-1) ** i, 0.0), i / RATE) for i in range(1, 9)]
    assert run(monitor, jitter)[0] is None
    assert monitor.alignment < 0.99


def test_slight_drift_within_tolerance_completes():
    # 3 deg off the line (dot 0.9986) is not a bad move.
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    assert run(monitor, drive(0.25, 0.0, 10, Pose2D(0, 0, math.radians(3))))[0] == OK


# -- no progress ------------------------------------------------------------------------------------
def test_frozen_odometry_is_no_progress_after_one_second():
    start = Pose2D(0.3, 0.1, 0.2)
    monitor = MotionMonitor(MOVE, 1.0, start, 0.0)
    frozen = [(start, i / RATE) for i in range(1, 200)]
    result, t, _ = run(monitor, frozen)
    assert result == NO_PROGRESS
    assert 1.0 < t <= 1.0 + 1.5 / RATE


def test_progress_that_stops_midway_is_no_progress_one_second_later():
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    moving = list(drive(0.2, 0.0, 2.0))
    last, t_last = moving[-1]
    stuck = [(last, t_last + i / RATE) for i in range(1, 200)]
    result, t, _ = run(monitor, moving + stuck)
    assert result == NO_PROGRESS
    assert t - t_last == pytest.approx(1.0, abs=1.5 / RATE)


def test_check_without_new_odometry_reports_no_progress():
    monitor = MotionMonitor(TURN, math.pi / 2, Pose2D(0, 0, 0), 10.0)
    assert monitor.check(10.9) is None
    verdict = monitor.check(11.05)
    assert verdict is not None and verdict.result == NO_PROGRESS


def test_drift_below_epsilon_per_second_is_no_progress():
    # 0.05 mm/s (encoder noise, say) stays under the 0.1 mm epsilon for over a second.
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0)
    creeping = [(Pose2D(1e-6 * i, 0.0, 0.0), i / RATE) for i in range(1, 100)]
    assert run(monitor, creeping)[0] == NO_PROGRESS


def test_slow_but_steady_motion_is_progress():
    monitor = MotionMonitor(MOVE, 0.1, Pose2D(0, 0, 0), 0.0)
    assert run(monitor, drive(0.02, 0.0, 10))[0] == OK


def test_timeout_is_a_parameter():
    monitor = MotionMonitor(MOVE, 1.0, Pose2D(0, 0, 0), 0.0, CheckParams(no_progress_timeout=3.0))
    assert monitor.check(2.9) is None
    assert monitor.check(3.1) is not None


# -- recorded in the simulator ---------------------------------------------------------------------
def recorded(fault: str) -> list[dict[str, float]]:
    with open(DATA / f"odom_{fault}.csv", encoding="utf-8") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def replay(fault: str, target: float = 1.0) -> tuple[str | None, float, dict[str, float]]:
    """Feed a recorded sequence to a move(target) monitor: (result, time, row at the verdict)."""
    rows = recorded(fault)
    monitor = MotionMonitor(MOVE, target, Pose2D(0, 0, 0), 0.0)
    for row in rows:
        verdict = monitor.update(Pose2D(row["x"], row["y"], row["yaw"]), row["t"])
        if verdict:
            return verdict.result, row["t"], row
    return None, rows[-1]["t"], rows[-1]


def test_recorded_healthy_drive_reaches_one_metre():
    result, t, row = replay("none")
    assert result == OK
    assert row["gt_x"] == pytest.approx(1.0, abs=0.01)
    assert 5.0 < t < 5.5                     # 1 m at 0.2 m/s, plus the base's acceleration


@pytest.mark.parametrize(("fault", "side"), [("left_actuator", 1), ("right_actuator", -1)])
def test_recorded_actuator_fault_is_a_bad_move_toward_the_faulty_side(fault, side):
    result, t, row = replay(fault)
    assert result == BAD_MOVE
    assert row["gt_y"] * side > 0 and row["gt_yaw"] * side > 0
    assert t < 2.0


@pytest.mark.parametrize("fault", ["both_actuators", "odometry"])
def test_recorded_stuck_odometry_is_no_progress_after_one_second(fault):
    result, t, _ = replay(fault)
    assert result == NO_PROGRESS
    assert 1.0 < t <= 1.0 + 1.5 / RATE


def test_recorded_encoder_fault_hides_real_motion():
    # What only an outside observer can tell: the base moved while the odometry froze.
    _, _, row = replay("odometry")
    assert row["x"] == 0.0 and row["gt_x"] > 0.15
    _, _, row = replay("both_actuators")
    assert abs(row["gt_x"]) < 0.001


# -- turn -------------------------------------------------------------------------------------------
@pytest.mark.parametrize("degrees", [90, -90, 30, 450])
def test_turn_accumulates_yaw_across_the_wrap(degrees):
    target = math.radians(degrees)
    start = Pose2D(0, 0, math.radians(170))
    monitor = MotionMonitor(TURN, target, start, 0.0)
    w = math.copysign(0.8, target)
    result, _, _ = run(monitor, drive(0.0, w, 20, start))
    assert result == OK
    assert monitor.turned == pytest.approx(target, abs=0.8 / RATE)


def test_turning_the_wrong_way_never_completes():
    monitor = MotionMonitor(TURN, math.radians(90), Pose2D(0, 0, 0), 0.0)
    assert run(monitor, drive(0.0, -0.8, 3))[0] is None
    assert monitor.remaining > math.radians(90)


def test_turn_is_not_checked_for_bad_move():
    # Rotation with the wheel-level fault model drifts the centre: still a valid turn.
    monitor = MotionMonitor(TURN, math.radians(90), Pose2D(0, 0, 0), 0.0)
    assert run(monitor, drive(0.0288, 0.6, 5))[0] == OK


# -- settling after the goal ------------------------------------------------------------------------
SETTLE = CheckParams(settle_time=0.3, settle_timeout=1.0)


def coast_then_stop(w: float, coast: float, start: Pose2D = ORIGIN):
    """A turn at `w` that goes on for `coast` s after the goal, then stands still."""
    poses = list(drive(0.0, w, 2.0 + coast, start))
    last, t_last = poses[-1]
    return poses + [(last, t_last + i / RATE) for i in range(1, int(2 * RATE))]


def test_ok_waits_until_the_base_is_at_rest():
    monitor = MotionMonitor(TURN, math.radians(-90), ORIGIN, 0.0, SETTLE)
    # -0.8 rad/s reaches -90 deg after 1.96 s; the base coasts until 2.5 s, then stands still
    verdict_time = None
    for pose, t in coast_then_stop(-0.8, 0.5):
        verdict = monitor.update(pose, t)
        if t < 1.95:
            assert not monitor.settling
        if verdict:
            verdict_time = t
            break
    assert verdict.result == OK and "at rest" in verdict.message
    assert verdict_time == pytest.approx(2.5 + 0.3, abs=2.5 / RATE)
    assert math.degrees(monitor.turned) < -100        # the coasting is in the final figure


def test_a_base_that_never_stops_is_reported_at_the_settle_timeout():
    monitor = MotionMonitor(TURN, math.radians(30), ORIGIN, 0.0, SETTLE)
    verdict, t = None, 0.0
    for pose, t in drive(0.0, 0.8, 5):
        verdict = monitor.update(pose, t)
        if verdict:
            break
    assert verdict.result == OK and "still moving" in verdict.message
    assert t == pytest.approx(math.radians(30) / 0.8 + 1.0, abs=2.5 / RATE)


def test_settling_is_also_checked_without_new_odometry():
    monitor = MotionMonitor(TURN, math.radians(10), ORIGIN, 0.0, SETTLE)
    pose, t = None, 0.0
    for pose, t in drive(0.0, 0.8, 0.3):
        assert monitor.update(pose, t) is None or monitor.settling
    assert monitor.settling
    assert monitor.check(t + 0.1) is None
    assert monitor.check(t + 0.35).result == OK      # odometry silent (still) for 0.3 s


def test_no_settling_reports_at_the_goal_as_the_thesis_did():
    monitor = MotionMonitor(TURN, math.radians(90), ORIGIN, 0.0)
    result, t, _ = run(monitor, drive(0.0, 0.8, 5))
    assert result == OK and t == pytest.approx(math.radians(90) / 0.8, abs=1.5 / RATE)


# -- helpers ----------------------------------------------------------------------------------------
def test_yaw_from_quaternion():
    half = math.radians(120) / 2
    assert yaw_from_quaternion(0, 0, math.sin(half), math.cos(half)) == pytest.approx(
        math.radians(120))


def test_parse_target():
    assert parse_target(MOVE, ["-1"]) == -1.0
    assert parse_target(MOVE, [" 0.3 "]) == 0.3
    assert parse_target(TURN, ["90"]) == pytest.approx(-math.pi / 2)        # clockwise
    assert parse_target(TURN, ["90"], turn_clockwise=False) == pytest.approx(math.pi / 2)


@pytest.mark.parametrize("params", [[], ["1", "2"], ["one"], ['"1"'], ["nan"], ["inf"], ["X"]])
def test_parse_target_rejects_non_numbers(params):
    with pytest.raises(ValueError):
        parse_target(MOVE, params)


def test_speed_ramp_accelerates_cruises_and_brakes():
    limits = SpeedLimits(max_speed=0.25, min_speed=0.02, accel=0.5, decel=0.3)
    assert next_speed(0.0, 1.0, 0.02, limits) == pytest.approx(0.02)       # creep floor
    assert next_speed(0.1, 1.0, 0.02, limits) == pytest.approx(0.11)       # ramp up
    assert next_speed(0.25, 1.0, 0.02, limits) == pytest.approx(0.25)      # cruise
    assert next_speed(0.25, 0.05, 0.02, limits) == pytest.approx(math.sqrt(0.03))  # brake
    assert next_speed(0.05, 1e-5, 0.02, limits) == pytest.approx(0.02)     # creep to the goal
    assert next_speed(0.05, 0.0, 0.02, limits) == 0.0


def test_speed_ramp_reaches_the_goal_without_overshooting():
    limits = SpeedLimits(max_speed=0.25, min_speed=0.02, accel=0.5, decel=0.3)
    x, v, dt, t = 0.0, 0.0, 1.0 / RATE, 0.0
    while x < 1.0 and t < 20:
        v = next_speed(v, 1.0 - x, dt, limits)
        x += v * dt
        t += dt
    assert x == pytest.approx(1.0, abs=0.02 * dt + 1e-9)
    assert t < 6.0
