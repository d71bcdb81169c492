"""How a run's answer counts (pure logic, no ROS): a wrong component is never counted as
`unknown`, and the demo and the campaign count alike."""

from __future__ import annotations

import pytest

from rason_diagnosis.__main__ import VERDICTS
from rason_diagnosis.campaign import outcome
from rason_diagnosis.scenario import Outcome, RunResult


@pytest.mark.parametrize(("diagnosis", "correct", "expected"), [
    ("left_actuator", True, Outcome.RIGHT),
    ("unknown", False, Outcome.UNKNOWN),
    (None, False, Outcome.UNKNOWN),
    ("right_actuator", False, Outcome.WRONG),
    ("false_positive", False, Outcome.WRONG),
])
def test_outcome_of_a_run(diagnosis, correct, expected):
    result = RunResult("left_actuator", 1, diagnosis=diagnosis, correct=correct)
    assert result.outcome is expected
    assert outcome({"diagnosis": diagnosis, "correct": correct}) == expected.value


def test_the_demo_says_unknown_apart_from_wrong():
    assert VERDICTS[Outcome.UNKNOWN].startswith("UNKNOWN")
    assert VERDICTS[Outcome.WRONG] == "WRONG" and VERDICTS[Outcome.RIGHT] == "CORRECT"
    assert set(VERDICTS) == set(Outcome)
