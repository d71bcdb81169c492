"""``rosrun rason act`` says at once why no feedback will come, and prints a failed result."""

from __future__ import annotations

import pytest
import rospy
from jason_msgs.msg import ActionCancel
from polling import wait_until

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


def test_the_cancel_of_an_action_given_up_reaches_each_subscriber(ros: RosHarness):
    """act sends its cancel once: a node that subscribed to ``jason/cancel`` before act
    started hears it (act sends its action once its cancel is connected to each)."""
    ros.init_rospy()
    heard: list[ActionCancel] = []
    sub = rospy.Subscriber("/act_cancel/jason/cancel", ActionCancel, heard.append)
    try:
        ros.wait_for_subscriber("/act_cancel/jason/cancel")
        act = _act_beside_echo(ros, "/act_cancel", "fly(1)")
        assert act.wait(60) == 2, act.output()
        wait_until(lambda: heard, "the cancel act sent", timeout=10)
    finally:
        sub.unregister()
    assert [(c.agent, c.reason) for c in heard] == [("x", "act: not acknowledged within 2 s")]


def test_a_failed_result_is_printed(ros: RosHarness):
    act = _act_beside_echo(ros, "/act_fail", "move(1, no_progress)")
    assert act.wait(60) == 1, act.output()
    assert "feedback: no_progress (echo: move(1, no_progress))" in act.output()
