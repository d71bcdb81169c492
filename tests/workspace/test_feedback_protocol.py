"""The agent/decomposer action protocol helpers (no ROS needed)."""

from types import SimpleNamespace

import pytest

from rason.ros.feedback import (
    Feedback,
    accepted_beat_period,
    parse_accepted,
    parse_feedback,
    parse_running,
    split_action,
)


def event(kind: str, *params: str) -> SimpleNamespace:
    return SimpleNamespace(agent="faulty", event_type=kind, parameters=list(params))


def test_feedback_in_thesis_order():
    assert parse_feedback(event("action_feedback", "no_progress", "7", "stuck")) == \
        Feedback(7, "no_progress", "stuck")


def test_feedback_in_public_code_order_is_accepted():
    assert parse_feedback(event("action_feedback", "12", "OK")) == Feedback(12, "OK")


def test_feedback_ambiguous_numbers_read_in_thesis_order():
    assert parse_feedback(event("action_feedback", "3", "4")) == Feedback(4, "3")


@pytest.mark.parametrize("params", [(), ("OK",), ("OK", "x")])
def test_malformed_feedback_is_none(params):
    assert parse_feedback(event("action_feedback", *params)) is None


def test_other_event_types_are_not_feedback():
    assert parse_feedback(event("something", "OK", "1")) is None
    assert parse_accepted(event("action_accepted", "42")) == 42
    assert parse_accepted(event("action_feedback", "42")) is None


def test_beats_announced_on_acceptance_and_beats_themselves():
    assert parse_accepted(event("action_accepted", "42", "1")) == 42     # thesis agents: same
    assert accepted_beat_period(event("action_accepted", "42", "0.5")) == 0.5
    for params in (("42",), ("42", "nan"), ("42", "0"), ("42", "-1"), ("42", "inf"), ("42", "x")):
        assert accepted_beat_period(event("action_accepted", *params)) is None
    assert parse_running(event("action_running", "3", "x", "4")) == [3, 4]
    assert parse_running(event("action_feedback", "OK", "3")) is None
    assert parse_feedback(event("action_running", "3")) is None


def test_split_action_respects_nesting_and_quotes():
    assert split_action("move(1)") == ("move", ["1"])
    assert split_action('say("a, b", f(x, [1, 2]), -3.5)') == \
        ("say", ['"a, b"', "f(x, [1, 2])", "-3.5"])
    assert split_action("stop") == ("stop", [])


@pytest.mark.parametrize("bad", ["", "Move(1)", "move(1", "move(1))", "move(,1)", "f(a]"])
def test_split_action_rejects_bad_text(bad):
    with pytest.raises(ValueError):
        split_action(bad)
