"""The round timer of Jason's current-intention demo (benchmarks/jason_round_times.py): a round
of a goal runs from one print of its name to the next, its wait is read from another goal's
inspection, and what is left is the round's cost."""

from __future__ import annotations

import pytest
from asl_helpers import load_benchmark

timer = load_benchmark("jason_round_times")


def _waiting(goal: str, ms: int) -> str:
    return (f"[sample_agent]      another goal is start({goal})[source(self)] in state "
            f"waiting[reason(wait(1)[time({ms})])]")


def test_a_rounds_cost_is_its_time_beyond_the_wait_another_goal_showed() -> None:
    lines = [(0.0, "[sample_agent] a"), (0.0002, "[sample_agent] b"),
             (1.2, _waiting("a", 1500)),          # b's inspection sees a waiting
             (1.5031, "[sample_agent] a"),        # a's next round: 3.1 ms beyond its wait
             (1.6, _waiting("b", 2899)),          # a's inspection sees b waiting
             (2.9, "[sample_agent] b"),           # b's next round: 0.8 ms beyond its wait
             (3.5, "[sample_agent] a")]           # a's second wait was not shown: not timed
    seen = timer.rounds(lines, 5.0)
    assert (seen.begun, seen.lines) == (5, 7)
    assert seen.beyond_wait == [pytest.approx(3.1), pytest.approx(0.8)]


def test_only_the_lines_within_the_time_count() -> None:
    lines = [(0.0, "[sample_agent] a"), (1.0, _waiting("a", 1000)), (2.0, "[sample_agent] a"),
             (16.0, "[sample_agent] a")]
    seen = timer.rounds(lines, 15.0)
    assert (seen.begun, seen.lines) == (2, 3)
    assert seen.beyond_wait == [pytest.approx(1000.0)]
