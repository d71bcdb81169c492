"""No silent hang when the decomposer dies (#37 item 6): an agent whose decomposer is killed
(SIGKILL: no feedback, no goodbye) 3 s into ``move(30)`` fails the action with
``decomposer_lost`` within a few seconds of ROS time, not at ``~action_timeout`` (120 s), so a
``-!g[error(decomposer_lost)]`` plan handles it; the action is cancelled on jason/cancel with
that reason. Real roscore, the echo decomposer (it holds the move: ``~delay`` 60 s) and a real
agent node."""

from __future__ import annotations

import signal
import threading
from pathlib import Path

import pytest
import rospy
from agent_nodes import start_agent, wait_heard
from jason_msgs.msg import ActionCancel, Event
from polling import wait_until

from rason.process.harness import RosHarness
from rason.ros.feedback import CancelReason, accepted_beat_period, parse_accepted, parse_running

pytestmark = pytest.mark.ros

NS = "/lost1"
MOVER = """
    !go.
    +!go <- move(30); .print("moved").
    -!go[error(E)] <- .print("move failed: ", E).
    """
#: the generous bound the issue sets, in ROS time, between the kill and the failure
BOUND = 10.0


def test_a_killed_decomposer_fails_the_action_with_decomposer_lost(ros: RosHarness,
                                                                   tmp_path: Path):
    ros.init_rospy()
    lock = threading.Lock()
    events: list[Event] = []
    cancels: list[tuple[float, ActionCancel]] = []

    def on_event(msg: Event) -> None:
        with lock:
            events.append(msg)

    def on_cancel(msg: ActionCancel) -> None:
        with lock:
            cancels.append((rospy.get_time(), msg))
    subs = [rospy.Subscriber(f"{NS}/jason/event", Event, on_event),
            rospy.Subscriber(f"{NS}/jason/cancel", ActionCancel, on_cancel)]
    try:
        decomposer = ros.rosrun("rason", "echo_decomposer", ns=NS, params={"delay": 60.0})
        ros.wait_for_subscriber(f"{NS}/jason/cancel", watch=[decomposer])
        # the decomposer says "accepted" once, unlatched: heard only if our jason/event
        # subscriber is connected to it before the agent asks
        wait_heard(ros, f"{NS}/echo_decomposer", [f"{NS}/jason/event"], watch=[decomposer])
        agent = start_agent(ros, tmp_path, "mover", MOVER, ns=NS)
        # the agent's cancel comes once too: our jason/cancel subscriber hears its node first
        wait_heard(ros, f"{NS}/jason/mover", [f"{NS}/jason/cancel"], watch=[agent])

        def accepted() -> list[Event]:
            with lock:
                return [e for e in events if parse_accepted(e) is not None]
        wait_until(accepted, "move(30) to be accepted", timeout=20)
        assert accepted_beat_period(accepted()[0]) == 1.0
        accepted_at = rospy.get_time()
        wait_until(lambda: rospy.get_time() - accepted_at >= 3.0, "3 s of the move", timeout=10)
        with lock:
            assert any(parse_running(e) for e in events), events     # it beat meanwhile
        decomposer.signal_group(signal.SIGKILL)
        killed_at = rospy.get_time()
        agent.wait_for_line(r"\[mover\] move failed: decomposer_lost", timeout=30)
        failed_at = rospy.get_time()
        assert failed_at - killed_at < BOUND, failed_at - killed_at

        def reasons() -> list[tuple[str, str]]:
            with lock:
                return [(c.agent, c.reason) for _, c in cancels]
        # the cancel comes over ROS, the line through the agent's output: either may be first
        wait_until(lambda: ("mover", CancelReason.DECOMPOSER_LOST) in reasons(),
                   "the cancel with decomposer_lost", timeout=10, watch=[agent])
        assert "moved" not in agent.output()
        assert agent.alive()
        # a node without a key says once that it is open
        assert decomposer.output().count("accepts actions from any sender") == 1
        assert agent.output().count("accepts any sender on the ROS graph") == 1
    finally:
        for sub in subs:
            sub.unregister()
