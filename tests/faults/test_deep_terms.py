"""A term nested 100,000 deep (about 300 kB) in a perception or a tell leaves the agent node
alive and answering (#37 item 2): it is refused with a warning naming the depth limit
(rason.asl.limits), where it once crashed the node with SIGSEGV. Real roscore, real node; the
deep messages come from a plain rospy publisher, as any process on the graph could send them.
"""

from __future__ import annotations

from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, mind, start_agent
from jason_msgs.msg import AgentMessage, Perception
from polling import wait_until

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

NS = "/deep1"
STURDY = """
    +seen(X)[source(percept)] <- .print("seen ", X).
    +told(X)[source(S)] <- .print("told ", X, " by ", S).
    """
DEEP = "f(" * 100_000 + "1" + ")" * 100_000


def test_a_deep_perception_and_a_deep_tell_leave_the_node_alive_and_answering(
        ros: RosHarness, tmp_path: Path):
    agent = start_agent(ros, tmp_path, "sturdy", STURDY, ns=NS)
    ros.init_rospy()
    percepts = rospy.Publisher(f"{NS}/jason/perception", Perception, queue_size=10)
    messages = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10)
    for pub in (percepts, messages):
        wait_until(lambda p=pub: connected_to(p, f"{NS}/jason/sturdy"), "a connection", timeout=10)
    percepts.publish(Perception(source="fuzz", perception=[f"seen({DEEP})"]))
    messages.publish(AgentMessage(sender="fuzzer", receiver="sturdy", performative="tell",
                                  content=f"told({DEEP})", reply_with="d1"))
    agent.wait_for_line(r"dropped message from fuzzer with unreadable content .*"
                        r"nested deeper than 200 levels", timeout=30)
    agent.wait_for_line(r"seen\(f\(f\(.*nested deeper than 200 levels", timeout=30)
    # still perceives, hears and answers its mind service: the good perception and message,
    # on the same publishers after the deep ones, are the sentinels (no sleep before them)
    percepts.publish(Perception(source="fuzz", perception=["seen(2)"]))
    messages.publish(AgentMessage(sender="friend", receiver="sturdy", performative="tell",
                                  content="told(3)", reply_with="d2"))
    agent.wait_for_line(r"\[sturdy\] seen 2", timeout=15)
    agent.wait_for_line(r"\[sturdy\] told 3 by friend", timeout=15)
    assert agent.alive(), agent.output()[-3000:]
    beliefs = mind(ros, NS, "sturdy")["beliefs"]
    assert any(b.startswith("told(3)") for b in beliefs), beliefs
    assert not any("f(f(" in b for b in beliefs), beliefs
    percepts.unregister()
    messages.unregister()
    assert "Traceback" not in agent.output()
