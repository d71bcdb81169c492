"""Replays stay out across restarts; keyed directory registrations stay findable (#37 item 5).

Real keyed agent nodes. A signed ``achieve`` captured from the graph and published again after
the receiving node restarted, well within ``~auth_window``, is dropped (the restarted node has
no memory of the nonces its previous run saw). A newcomer that starts more than
``~auth_window`` after another node's ``.df_register`` still finds the service: the registering
node signs its latched registrations again every half window.
"""

from __future__ import annotations

import os
import secrets
from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, start_agent
from jason_msgs.msg import AgentMessage
from polling import wait_until

from rason.process.harness import Process, RosHarness
from rason.ros.auth import START_GRACE, MessageAuth, SignedFields, load_key, new_nonce
from rason.ros.presence import DIRECTORY_TOPIC

pytestmark = pytest.mark.ros

VICTIM = """
    +!go(N)[source(A)] <- .print("went ", N, " for ", A).
    """
SELLER = """
    !start.
    +!start <- .df_register("sell(book)"); .print(registered).
    """
BUYER = """
    !find.
    +!find <- .df_search("sell(book)", L);
              if (L == []) { .wait(300); !find } else { .print("sellers ", L) }.
    """


def key_file(tmp_path: Path) -> Path:
    path = tmp_path / "fleet.key"
    path.write_text(secrets.token_urlsafe(32) + "\n")
    os.chmod(path, 0o600)
    return path


def signed_achieve(auth: MessageAuth, goal: str) -> AgentMessage:
    msg = AgentMessage(sender="boss", receiver="victim", performative="achieve", content=goal,
                       reply_with=secrets.token_hex(4), in_reply_to="", stamp=rospy.Time.now(),
                       nonce=new_nonce())
    msg.signature = auth.sign(SignedFields.of(msg))
    return msg


def test_a_captured_signed_achieve_is_refused_after_the_receiver_restarts(
        ros: RosHarness, tmp_path: Path):
    key = key_file(tmp_path)
    auth = MessageAuth(load_key(key), window=120.0)
    ros.init_rospy()
    pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10)

    def victim() -> Process:
        proc = start_agent(ros, tmp_path, "victim", VICTIM, ns="/replay", auth_key_file=key,
                           auth_window=120.0)
        wait_until(lambda: connected_to(pub, "/replay/jason/victim"), "victim connected", timeout=30)
        return proc

    first = victim()
    captured = signed_achieve(auth, "go(1)")
    pub.publish(captured)
    first.wait_for_line(r"\[victim\] went 1 for boss", timeout=30)
    first.stop()                                    # restarted well within the 120 s window
    # a restarted node trusts what was sent up to START_GRACE before its first check (clock
    # skew between hosts): the replay is refused once the restart is later than that
    later = captured.stamp + rospy.Duration(START_GRACE + 0.2)
    wait_until(lambda: rospy.Time.now() > later, "the restart after START_GRACE", timeout=10)
    second = victim()
    pub.publish(signed_achieve(auth, "go(2)"))      # a fresh one gets in
    second.wait_for_line(r"\[victim\] went 2 for boss", timeout=30)
    pub.publish(captured)                           # the replay does not
    second.wait_for_line(r"dropped a stale achieve message claiming to be from 'boss'",
                         timeout=30)
    pub.publish(signed_achieve(auth, "go(3)"))
    second.wait_for_line(r"\[victim\] went 3 for boss", timeout=30)
    assert "went 1" not in second.output()
    pub.unregister()


def test_a_newcomer_long_after_a_keyed_registration_still_finds_it(ros: RosHarness,
                                                                   tmp_path: Path):
    key = key_file(tmp_path)
    window = 4.0
    ros.init_rospy()
    stamps: list[rospy.Time] = []                 # of the seller's copies of its registration

    def heard(msg: AgentMessage) -> None:
        if msg.sender.startswith("/kdf1/") and "sell(book)" in msg.content:
            stamps.append(msg.stamp)
    directory = rospy.Subscriber(DIRECTORY_TOPIC, AgentMessage, heard)
    seller = start_agent(ros, tmp_path, "seller", SELLER, ns="/kdf1", auth_key_file=key,
                         auth_window=window, presence_period=0.5)
    seller.wait_for_line(r"\[seller\] registered", timeout=30)
    # the sentinel: a copy the seller signed more than a window after the first one this test
    # heard (its registration or a later copy): by then that first copy is stale
    wait_until(lambda: stamps, "the seller's registration", timeout=30)
    first = stamps[0]
    wait_until(lambda: stamps[-1] > first + rospy.Duration(window),
               "a copy of the registration signed a window later", timeout=3 * window + 30)
    directory.unregister()
    buyer = start_agent(ros, tmp_path, "buyer", BUYER, ns="/kdf2", auth_key_file=key,
                        auth_window=window, presence_period=0.5)
    buyer.wait_for_line(r"\[buyer\] sellers \[seller\]", timeout=30)
    assert "dropped" not in buyer.output(), buyer.output()
