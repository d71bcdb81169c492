"""A node's inbound connections do not wait behind one that never sends its header (#39).

rospy handles an accepted TCPROS connection in its accept loop, reading the handshake with a
60 s timeout: one silent connection (a client that gave up half-way, a port probe) kept a
decomposer from accepting any subscriber for a minute, and a freshly started agent's first
action failed no_decomposer. Here a raw socket connects to an echo decomposer's TCPROS port and
stays silent; a real subscriber of its jason/event must still connect at once (well within the
60 s the silent one holds its own thread).
"""

from __future__ import annotations

import socket
import xmlrpc.client

import pytest
import rosgraph
from polling import wait_until

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros


def tcpros_address(ros: RosHarness, node: str, topic: str) -> tuple[str, int]:
    """Where `node` accepts TCPROS connections for `topic` (the slave API's requestTopic)."""
    caller = "/rason_test_accept"
    uri = rosgraph.Master(caller, master_uri=ros.master_uri).lookupNode(node)
    code, message, protocol = xmlrpc.client.ServerProxy(uri).requestTopic(
        caller, topic, [["TCPROS"]])
    assert code == 1, message
    return protocol[1], int(protocol[2])


def test_a_silent_connection_does_not_hold_up_a_subscriber(ros: RosHarness):
    import rospy
    from jason_msgs.msg import Event

    decomposer = ros.rosrun("rason", "echo_decomposer", ns="/acc")
    ros.wait_for_topic("/acc/jason/event", watch=[decomposer])
    host, port = tcpros_address(ros, "/acc/echo_decomposer", "/acc/jason/event")
    with socket.create_connection((host, port), timeout=10) as silent:
        # the decomposer accepted it (its handshake wait began) before the subscriber comes
        silent.settimeout(0.5)
        with pytest.raises(socket.timeout):
            silent.recv(1)
        ros.init_rospy()
        subscriber = rospy.Subscriber("/acc/jason/event", Event, lambda _msg: None)
        try:
            # rospy lists a connection at once; its header, once the decomposer answered
            wait_until(lambda: any(getattr(c, "header", None)
                                   for c in subscriber.impl.connections),
                       "the subscriber's handshake with the decomposer", timeout=20,
                       watch=[decomposer])
        finally:
            subscriber.unregister()
