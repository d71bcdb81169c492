"""Fault maths of the Kobuki fault injector: eqs. 6.2/6.3, the rotation model, freeze, cancel."""

from __future__ import annotations

import math

import pytest

from kobuki_fault_injector.faults import (
    BOTH_ACTUATORS,
    LEFT_ACTUATOR,
    NO_FAULT,
    ODOMETRY,
    RIGHT_ACTUATOR,
    ROTATION_WHEEL_GAIN,
    VALID_REQUESTS,
    FaultState,
    OdometryFreezer,
    Velocity,
    actuator_fault,
    apply_fault,
    body_velocity,
    wheel_speeds,
)
from turtlebot_model.kobuki import WHEEL_SEPARATION

FULL = Velocity(0.2, 0.01, 0.02, 0.03, 0.04, 0.3)


# -- eqs. 6.2 and 6.3: forward/backward motion ---------------------------------------------------
@pytest.mark.parametrize(("fault", "x", "expected_z"), [
    (LEFT_ACTUATOR, 0.2, 0.2),      # z = x   (left, x > 0): turns left
    (RIGHT_ACTUATOR, -0.2, -0.2),   # z = x   (right, x < 0)
    (RIGHT_ACTUATOR, 0.2, -0.2),    # z = -x  (right, x > 0): turns right
    (LEFT_ACTUATOR, -0.2, 0.2),     # z = -x  (left, x < 0)
])
def test_case_table_of_eq_6_2_and_halving_of_eq_6_3(fault, x, expected_z):
    out = actuator_fault(fault, Velocity(linear_x=x, angular_z=0.7))
    assert out.angular_z == pytest.approx(expected_z)     # commanded z replaced
    assert out.linear_x == pytest.approx(x / 2)


def test_forward_fault_turns_toward_the_faulty_wheel():
    assert actuator_fault(LEFT_ACTUATOR, Velocity(linear_x=0.3)).angular_z > 0    # left = +z
    assert actuator_fault(RIGHT_ACTUATOR, Velocity(linear_x=0.3)).angular_z < 0


def test_actuator_fault_keeps_the_other_components():
    out = actuator_fault(LEFT_ACTUATOR, FULL)
    assert (out.linear_y, out.linear_z, out.angular_x, out.angular_y) == (0.01, 0.02, 0.03, 0.04)


# -- the rotation model ----------------------------------------------------------------------------
def test_wheel_speed_conversion_round_trips():
    left, right = wheel_speeds(0.1, 1.0)
    assert (left, right) == pytest.approx((0.1 - WHEEL_SEPARATION / 2, 0.1 + WHEEL_SEPARATION / 2))
    assert body_velocity(left, right) == pytest.approx((0.1, 1.0))


@pytest.mark.parametrize("w", [0.8, -0.8])
@pytest.mark.parametrize("fault", [LEFT_ACTUATOR, RIGHT_ACTUATOR])
def test_pure_rotation_scales_the_faulty_wheel(fault, w):
    out = actuator_fault(fault, Velocity(angular_z=w))
    left, right = wheel_speeds(out.linear_x, out.angular_z)
    healthy_left, healthy_right = wheel_speeds(0.0, w)
    if fault == LEFT_ACTUATOR:
        assert (left, right) == pytest.approx((healthy_left * ROTATION_WHEEL_GAIN, healthy_right))
    else:
        assert (left, right) == pytest.approx((healthy_left, healthy_right * ROTATION_WHEEL_GAIN))
    # Half-speed wheel: 3/4 of the turn rate, same direction, a slow drift |v| = |w| L / 8.
    assert out.angular_z == pytest.approx(0.75 * w)
    assert abs(out.linear_x) == pytest.approx(abs(w) * WHEEL_SEPARATION / 8)


def test_left_fault_rotation_drifts_along_the_healthy_right_wheel():
    # Turning left (w > 0) the right wheel drives forward: the centre drifts forward.
    assert actuator_fault(LEFT_ACTUATOR, Velocity(angular_z=1.0)).linear_x > 0
    assert actuator_fault(RIGHT_ACTUATOR, Velocity(angular_z=1.0)).linear_x < 0


def test_standing_still_stays_still_under_actuator_faults():
    for fault in (LEFT_ACTUATOR, RIGHT_ACTUATOR):
        assert actuator_fault(fault, Velocity()) == Velocity()


def test_actuator_fault_rejects_other_faults():
    with pytest.raises(ValueError):
        actuator_fault(ODOMETRY, FULL)


# -- both actuators, no fault ----------------------------------------------------------------------
def test_both_actuators_zero_all_six_components():
    assert apply_fault(BOTH_ACTUATORS, FULL) == Velocity(0, 0, 0, 0, 0, 0)


@pytest.mark.parametrize("fault", [None, ODOMETRY])
def test_commands_pass_unchanged_without_an_actuator_fault(fault):
    assert apply_fault(fault, FULL) is FULL


# -- odometry freeze ----------------------------------------------------------------------------------
def test_freezer_holds_the_last_value_before_the_fault():
    freezer: OdometryFreezer[str] = OdometryFreezer()
    assert [freezer.filter(m) for m in ("a", "b")] == ["a", "b"]
    freezer.freeze()
    assert [freezer.filter(m) for m in ("c", "d")] == ["b", "b"]
    freezer.release()
    assert freezer.filter("e") == "e"


def test_freezer_without_earlier_message_freezes_the_first_one():
    freezer: OdometryFreezer[str] = OdometryFreezer()
    freezer.freeze()
    assert [freezer.filter(m) for m in ("x", "y")] == ["x", "x"]


# -- the service's state machine --------------------------------------------------------------------
def test_inject_and_cancel():
    changes: list[str | None] = []
    state = FaultState(on_change=changes.append)
    assert state.status == NO_FAULT
    assert "left_actuator" in state.request("left_actuator")
    assert state.status == LEFT_ACTUATOR
    assert state.command(Velocity(linear_x=0.2)) == Velocity(linear_x=0.1, angular_z=0.2)
    assert "cancel" in state.request("cancel")
    assert state.active is None
    assert state.command(Velocity(linear_x=0.2)) == Velocity(linear_x=0.2)
    assert changes == [LEFT_ACTUATOR, None]


def test_odometry_fault_freezes_and_cancel_releases():
    state = FaultState()
    state.odom("o1")
    state.request("odometry")
    assert [state.odom(m) for m in ("o2", "o3")] == ["o1", "o1"]
    state.request("both_actuators")            # replacing the encoder fault releases it
    assert state.odom("o4") == "o4"
    state.request("odometry")
    assert state.odom("o5") == "o4"
    state.request("cancel")
    assert state.odom("o6") == "o6"


def test_unknown_fault_changes_nothing_and_lists_the_valid_ones():
    changes: list[str | None] = []
    state = FaultState(on_change=changes.append)
    state.request("right_actuator")
    message = state.request("left_wheel_on_fire")
    assert message.startswith("error: unknown fault 'left_wheel_on_fire'")
    assert all(name in message for name in VALID_REQUESTS)
    assert state.active == RIGHT_ACTUATOR
    assert changes == [RIGHT_ACTUATOR]


def test_request_names_are_stripped():
    state = FaultState()
    state.request("  both_actuators\n")
    assert state.active == BOTH_ACTUATORS


def test_eq_6_2_radius_is_independent_of_speed():
    # v' = x/2, w' = x: the faulty robot always circles with radius 0.5 m.
    for x in (0.05, 0.2, 0.5):
        out = actuator_fault(RIGHT_ACTUATOR, Velocity(linear_x=x))
        assert math.isclose(abs(out.linear_x / out.angular_z), 0.5)
