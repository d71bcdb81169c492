"""``rosrun rason act`` says at once why no feedback will come, and prints a failed result."""

from __future__ import annotations

import pytest

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

#: far longer than the test waits: an early exit shows act did not wait for the feedback
LONG = "600"


def test_without_a_decomposer_act_names_the_topic_nobody_subscribes(ros: RosHarness):
    act = ros.rosrun("rason", "act", "x", "move(1)", "--timeout", LONG, ns="/act_none")
    assert act.wait(60) == 2, act.output()
    assert "no decomposer: nothing subscribes to /act_none/jason/action" in act.output()
    assert "rosrun rason motion_decomposer __ns:=/act_none" in act.output()


def _act_beside_echo(ros: RosHarness, ns: str, action: str):
    """``act`` against an echo decomposer that handles ``move`` in ``ns``."""
    dec = ros.rosrun("rason", "echo_decomposer", ns=ns, params={"actions": ["move"]})
    ros.wait_for_subscriber(f"{ns}/jason/action", timeout=60, watch=[dec])
    return ros.rosrun("rason", "act", "x", action, "--timeout", LONG, ns=ns)


def test_an_action_no_decomposer_handles_is_named_with_the_listeners(ros: RosHarness):
    act = _act_beside_echo(ros, "/act_unknown", "fly(1)")
    assert act.wait(60) == 2, act.output()
    assert "no decomposer acknowledged fly within 2 s" in act.output()
    assert "/act_unknown/echo_decomposer" in act.output()


def test_a_failed_result_is_printed(ros: RosHarness):
    act = _act_beside_echo(ros, "/act_fail", "move(1, no_progress)")
    assert act.wait(60) == 1, act.output()
    assert "feedback: no_progress (echo: move(1, no_progress))" in act.output()
