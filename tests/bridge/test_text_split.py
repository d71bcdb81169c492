"""Top-level comma splitting shared by action texts and the perception filter (no ROS)."""

from __future__ import annotations

import pytest

from rason.ros.feedback import split_action, split_top_level
from rason.ros.perceptions import PerceptionFilter


def test_split_top_level_ignores_commas_in_brackets_and_quotes():
    parts, stop, balanced = split_top_level('1, f(a, b), "x,y", [1, 2]) [z]')
    assert parts == ["1", "f(a, b)", '"x,y"', "[1, 2]"]
    assert stop == 25 and balanced


def test_split_top_level_reports_an_unclosed_bracket_or_quote():
    assert split_top_level("a, f(b")[2] is False
    assert split_top_level('a, "b')[2] is False


@pytest.mark.parametrize("text, expected", [
    ("stop", ("stop", [])),
    ("move(1)", ("move", ["1"])),
    ('say("a, b", [1, 2], p(q, r))', ("say", ['"a, b"', "[1, 2]", "p(q, r)"])),
    ("turn( )", ("turn", [])),
])
def test_split_action(text, expected):
    assert split_action(text) == expected


@pytest.mark.parametrize("text", ["Move(1)", "move(1", "move(1,)", 'move("a)', "move(f(1)))", "1(2)"])
def test_split_action_rejects_malformed_text(text):
    with pytest.raises(ValueError):
        split_action(text)


def test_filter_by_functor_and_arity():
    wanted = PerceptionFilter.from_lists(["robot/4", "obstacle"])
    assert wanted.wants_text("robot(1, 2.5, f(a, b), \"x,y\")[source(kinect)]")
    assert not wanted.wants_text("robot(1, 2)")
    assert wanted.wants_text("obstacle") and wanted.wants_text("~obstacle(3)")
    assert not wanted.wants_text("battery(10)")
