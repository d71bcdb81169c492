"""The base's safety rules (rason.execution.safety), without ROS: which events stop a motion,
which new motions an active hazard refuses, and what the results say."""

from __future__ import annotations

import pytest

from rason.execution.results import BUMPER, CLIFF, WHEEL_DROP
from rason.execution.safety import BaseSafety, Hazard, Side

FORWARD, BACK, LEFT, RIGHT = (1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)


def test_a_press_is_a_hazard_that_begins_and_a_release_ends_it():
    safety = BaseSafety()
    hazard = safety.event(BUMPER, 1, True)
    assert hazard == Hazard(BUMPER, Side.CENTRE)
    assert hazard.what == "centre bumper pressed"
    assert safety.refusal("move(1)", *FORWARD) is not None
    assert safety.event(BUMPER, 1, False) is None
    assert safety.refusal("move(1)", *FORWARD) is None


def test_a_repeated_press_stops_again_and_a_release_of_another_part_changes_nothing():
    safety = BaseSafety()
    assert safety.event(BUMPER, 0, True) is not None
    assert safety.event(BUMPER, 0, True) is not None       # pressed again: stop again
    assert safety.event(BUMPER, 2, False) is None          # the right one was not pressed
    assert safety.refusal("move(1)", *FORWARD) is not None


@pytest.mark.parametrize("kind", [BUMPER, CLIFF])
@pytest.mark.parametrize("side, refused, allowed", [
    (0, [FORWARD, LEFT], [BACK, RIGHT]),
    (1, [FORWARD], [BACK, LEFT, RIGHT]),
    (2, [FORWARD, RIGHT], [BACK, LEFT]),
])
def test_front_hazards_refuse_what_drives_into_them_and_allow_the_way_out(kind, side, refused,
                                                                           allowed):
    safety = BaseSafety()
    safety.event(kind, side, True)
    for linear, angular in refused:
        verdict = safety.refusal("move(x)", linear, angular)
        assert verdict is not None and verdict.result == kind, (linear, angular)
        assert "refused" in verdict.message and "back off" in verdict.message
    for linear, angular in allowed:
        assert safety.refusal("move(x)", linear, angular) is None, (linear, angular)
    assert safety.refusal("move(0)", 0.0, 0.0) is None      # nothing to do is never refused


def test_a_dropped_wheel_refuses_every_motion_until_it_is_raised():
    safety = BaseSafety()
    hazard = safety.event(WHEEL_DROP, 1, True)
    assert hazard is not None and hazard.what == "right wheel dropped"
    for direction in (FORWARD, BACK, LEFT, RIGHT):
        verdict = safety.refusal("turn(5)", *direction)
        assert verdict is not None and verdict.result == WHEEL_DROP
        assert "right wheel dropped: turn(5) refused" in verdict.message
    safety.event(WHEEL_DROP, 1, False)
    assert safety.refusal("turn(5)", *LEFT) is None


def test_the_stop_verdict_names_the_part_and_the_motion():
    verdict = Hazard(CLIFF, Side.LEFT).stopped("move(1)", "0.420 m of 1.000 m")
    assert verdict.result == CLIFF and not verdict.ok
    assert verdict.message == "left cliff sensor sees a cliff: move(1) stopped after 0.420 m " \
                              "of 1.000 m"


@pytest.mark.parametrize("kind, index", [(BUMPER, 3), (CLIFF, -1), (WHEEL_DROP, 2),
                                          ("button", 0)])
def test_unknown_parts_are_refused_with_a_clear_error(kind, index):
    with pytest.raises(ValueError, match=r"Kobuki has|unknown safety event"):
        BaseSafety().event(kind, index, True)
