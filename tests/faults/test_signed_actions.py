"""With a key on both ends, actions and their feedback are signed (#37 item 1).

A keyed agent node runs ``move(60)`` on a keyed echo decomposer (which holds it 60 s). The
decomposer's signed acknowledgement and beats reach the agent (else the move would fail with
no_decomposer or decomposer_lost); a forger's unsigned or made-up ``action_feedback OK`` for the
move is ignored with a warning (the move stays pending); its unsigned or made-up actions in the
agent's name are ignored by the decomposer, never acknowledged.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, key_file, mind, start_agent, wait_heard
from jason_msgs.msg import Action, Event
from polling import wait_until

from rason.process.harness import RosHarness
from rason.ros.auth import AUTH_PARAMETER
from rason.ros.feedback import parse_accepted

pytestmark = pytest.mark.ros

NS = "/signed_actions"
MOVER = """
    !go.
    +!go <- move(60); .print("moved").
    -!go[error(E)] <- .print("move failed: ", E).
    """


def test_forged_feedback_and_forged_actions_are_ignored(ros: RosHarness, tmp_path: Path):
    key = key_file(tmp_path, "robot.key")
    ros.init_rospy()
    lock = threading.Lock()
    events: list[Event] = []

    def on_event(msg: Event) -> None:
        with lock:
            events.append(msg)
    sub = rospy.Subscriber(f"{NS}/jason/event", Event, on_event)
    forged_events = rospy.Publisher(f"{NS}/jason/event", Event, queue_size=10)
    forged_actions = rospy.Publisher(f"{NS}/jason/action", Action, queue_size=10)
    try:
        decomposer = ros.rosrun("rason", "echo_decomposer", ns=NS,
                                params={"delay": 60.0, "auth_key_file": key})
        ros.wait_for_subscriber(f"{NS}/jason/cancel", watch=[decomposer])
        # the decomposer says "accepted" once, unlatched: heard only if our jason/event
        # subscriber is connected to it before the agent asks
        wait_heard(ros, decomposer_node(ros), [f"{NS}/jason/event"], watch=[decomposer])
        agent = start_agent(ros, tmp_path, "mover", MOVER, ns=NS, auth_key_file=key)

        def accepted() -> list[Event]:
            with lock:
                return [e for e in events if parse_accepted(e) is not None]
        wait_until(accepted, "move(60) to be accepted", timeout=20)
        action_id = str(parse_accepted(accepted()[0]))
        assert accepted()[0].parameters[-1].startswith(AUTH_PARAMETER)
        wait_until(lambda: connected_to(forged_events, f"{NS}/jason/mover"), "a connection", timeout=10)
        for signature in ([], [f"{AUTH_PARAMETER}1:00:hmac-sha256:{'0' * 64}"]):
            forged_events.publish(Event(agent="mover", event_type="action_feedback",
                                        parameters=["OK", action_id, "forged", *signature]))
        agent.wait_for_line(r"\[mover\] ignored a unsigned action_feedback event", timeout=15)
        agent.wait_for_line(r"\[mover\] ignored a forged action_feedback event", timeout=15)
        wait_until(lambda: connected_to(forged_actions, decomposer_node(ros)),
                   "a connection to the decomposer", timeout=10)
        for action_id_forged, signature in ((901, []), (902, [f"{AUTH_PARAMETER}x:y:z"])):
            forged_actions.publish(Action(agent="mover", action_id=action_id_forged,
                                          action="move", parameters=["1", *signature]))
        decomposer.wait_for_line(r"ignored a unsigned action move claiming to be from 'mover'",
                                 timeout=15)
        decomposer.wait_for_line(r"ignored a forged action move claiming to be from 'mover'",
                                 timeout=15)
        time.sleep(4.0)   # beyond ~ack_timeout and ~decomposer_timeout: the signed ones count
        out = agent.output()
        assert "moved" not in out and "move failed" not in out, out
        assert any(p.startswith(f"{action_id}: move(60)")
                   for p in mind(ros, NS, "mover")["pending_actions"])
        with lock:
            assert not [e for e in events if parse_accepted(e) in (901, 902)], events
        assert "any sender" not in decomposer.output() + out      # keyed: not open
    finally:
        for endpoint in (sub, forged_events, forged_actions):
            endpoint.unregister()


def decomposer_node(ros: RosHarness) -> str:
    """The echo decomposer's node name in the test's namespace."""
    return next(n for n in ros.nodes() if n.startswith(f"{NS}/echo_decomposer"))
