"""Only trusted senders get in: ``~trusted_senders`` (Jason's acceptance hook) and messages
signed with a shared key (``~auth_key_file``); real roscore, real agent nodes, spoofed
messages from ``rostopic pub`` and from a raw rospy publisher."""

from __future__ import annotations

import json
import secrets

import pytest
from agent_nodes import connected_to, key_file, start_agent, subscribed_by, wait_heard
from polling import wait_until

from rason.process.harness import Process, RosHarness

pytestmark = pytest.mark.ros

ROBOT = """
    +!hello <- .print("hello ran").
    """
#: An agent that installs a plan in {target} and runs it; it starts by {start}.
BOSS = """
    {start}
    +!go : .all_names(L) & .member({target}, L)
       <- .send({target}, tellHow, "+!legit <- .print(legit_plan_ran).");
          .wait(2000);    // the target adds the plan (an intention of its own) before the goal
          .send({target}, achieve, legit).
    +!go <- .wait(200); !go.
    """
#: A plan as Jason text (a string term), as tellHow carries it.
EVIL_PLAN = '"+!hack <- .print(\\"hacked\\")."'


def spoof(ros: RosHarness, sender: str, receiver: str, performative: str, content: str,
          signature: str = "") -> Process:
    """Publish one AgentMessage from the command line, as anyone on the graph can.

    Not waited for: ``rostopic pub -1`` keeps its (latched) message up for 3 s before it exits,
    and the tests wait for what the receiver does with the message instead."""
    fields = {"sender": sender, "receiver": receiver, "performative": performative,
              "content": content, "reply_with": "x" + secrets.token_hex(3), "in_reply_to": "",
              "nonce": secrets.token_hex(8), "signature": signature}
    return ros.run(["rostopic", "pub", "-1", "/jason/messages", "jason_msgs/AgentMessage",
                    json.dumps(fields)], label=f"spoof_{sender}_{performative}")


def test_an_untrusted_sender_cannot_install_plans_or_give_goals(ros, tmp_path):
    """No key: `~trusted_senders:=[boss1]`; a spoofed tellHow/achieve from `mallory1` (rostopic
    pub) is dropped with a warning, the real boss1 agent's tellHow and achieve get in."""
    robot = start_agent(ros, tmp_path, "robot1", ROBOT, ns="/trust1", trusted_senders=["boss1"])
    # robot1's own subscription: on this global topic the master may still list the node of
    # an earlier test that was killed
    wait_until(lambda: subscribed_by(ros, "/jason/messages", "/trust1/jason/robot1"),
               "robot1 subscribed to /jason/messages", timeout=20, watch=[robot])
    spoof(ros, "mallory1", "robot1", "tellHow", EVIL_PLAN)
    spoof(ros, "mallory1", "robot1", "achieve", "hello")
    robot.wait_for_line(r"dropped tellHow from 'mallory1': not a trusted sender", timeout=15)
    spoof(ros, "mallory1", "robot1", "tell", "rumour(1)")          # not restricted: gets in
    start_agent(ros, tmp_path, "boss1", BOSS.format(target="robot1", start="!go."),
                ns="/trust1_boss")
    robot.wait_for_line(r"\[robot1\] legit_plan_ran", timeout=30)
    spoof(ros, "boss1", "robot1", "achieve", "hack")               # the plan was never added
    # the sentinels: the hack goal handled (had the plan got in, "hacked" would match first)
    # and mallory1's achieve dropped (so "hello ran" cannot come after)
    robot.wait_for_line(r"no applicable plan|no relevant plan|hack", timeout=15)
    robot.wait_for_line(r"dropped achieve from 'mallory1': not a trusted sender", timeout=15)
    out = robot.output()
    assert "hacked" not in out and "hello ran" not in out, out
    assert robot.alive()


def test_with_a_key_only_signed_messages_get_in(ros, tmp_path):
    """Keyed agents: a boss with the key (another process) gets its tellHow and achieve in;
    unsigned, forged, wrongly keyed and replayed messages are dropped with a warning."""
    import rospy
    from jason_msgs.msg import AgentMessage, Perception

    key = key_file(tmp_path, "fleet.key")
    ros.init_rospy()
    seen: list[AgentMessage] = []
    sub = rospy.Subscriber("/jason/messages", AgentMessage, seen.append)
    try:
        robot = start_agent(ros, tmp_path, "robot2", ROBOT, ns="/trust2", auth_key_file=key)
        pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10)
        wait_until(lambda: connected_to(pub, "/trust2/jason/robot2"),
                   "a connection to the agent", timeout=10)

        def forge(performative: str, content: str, signature: str = "") -> None:
            pub.publish(AgentMessage(sender="boss2", receiver="robot2", performative=performative,
                                     content=content, reply_with=secrets.token_hex(4),
                                     stamp=rospy.Time.now(), nonce=secrets.token_hex(8),
                                     signature=signature))

        forge("tellHow", EVIL_PLAN)                              # unsigned, claiming the boss
        robot.wait_for_line(r"dropped a unsigned tellHow message claiming to be from 'boss2'",
                            timeout=15)
        forge("achieve", "hello", signature="hmac-sha256:" + "0" * 64)   # made-up signature
        robot.wait_for_line(r"dropped a forged achieve message claiming to be from 'boss2'",
                            timeout=15)
        # An agent with another key: its messages are forgeries too.
        eve = start_agent(ros, tmp_path, "eve2", BOSS.format(target="robot2", start="!go."),
                          ns="/trust2_eve",
                          auth_key_file=key_file(tmp_path, "other.key"))
        robot.wait_for_line(r"dropped a forged presence message claiming to be from 'eve2'",
                            timeout=15)
        eve.stop()
        # The real boss, keyed: signed tellHow and achieve get in. It goes ahead once our
        # subscriber hears its node: the achieve (replayed below) is sent once.
        boss = start_agent(ros, tmp_path, "boss2",
                           BOSS.format(target="robot2",
                                       start="+go_ahead[source(percept)] <- !go."),
                           ns="/trust2_boss", auth_key_file=key)
        boss_node = "/trust2_boss/jason/boss2"
        wait_heard(ros, boss_node, ["/jason/messages"], watch=[boss])
        gate = rospy.Publisher("/trust2_boss/jason/perception", Perception, queue_size=1)
        wait_until(lambda: connected_to(gate, boss_node), "the go-ahead's connection to boss2",
                   watch=[boss])
        gate.publish(Perception(source="test", perception=["go_ahead"]))
        robot.wait_for_line(r"\[robot2\] legit_plan_ran", timeout=30)
        wait_until(lambda: any(m.sender == "boss2" and m.content == "legit" for m in seen),
                   "the test to hear the boss's achieve", timeout=15)
        achieve = [m for m in seen if m.sender == "boss2" and m.content == "legit"]
        assert achieve[0].signature.startswith("hmac-sha256:"), achieve
        # Replaying the boss's signed achieve word for word: dropped (nonce seen).
        pub.publish(achieve[0])
        robot.wait_for_line(r"dropped a replayed achieve message claiming to be from 'boss2'",
                            timeout=15)
        pub.unregister()
        gate.unregister()
    finally:
        sub.unregister()
    out = robot.output()
    assert out.count("legit_plan_ran") == 1, out
    assert "hacked" not in out and "hello ran" not in out, out
    assert robot.alive()


def test_an_unreadable_or_short_key_is_a_clear_error(ros, tmp_path):
    short = tmp_path / "short.key"
    short.write_text("tiny\n")
    for path, reason in ((tmp_path / "missing.key", "cannot read the key file"),
                         (short, "at least 16 are needed")):
        proc: Process = ros.rosrun("rason", "agent", "k", str(tmp_path / "k.asl"),
                                   ns="/trust3", params={"auth_key_file": path})
        (tmp_path / "k.asl").write_text("!g.\n+!g <- .print(hi).\n")
        assert proc.wait(30) == 2, proc.output()
        assert reason in proc.output(), proc.output()
        # A decomposer checks the agents' presence with the same key: the same clear error.
        proc = ros.rosrun("rason", "echo_decomposer", ns="/trust3",
                          params={"auth_key_file": path})
        assert proc.wait(30) == 2, proc.output()
        assert "~auth_key_file: " in proc.output() and reason in proc.output(), proc.output()


def test_agents_hosted_together_pass_the_same_acceptance_hook(ros, tmp_path):
    """A mas node with `~trusted_senders:=[boss4]`: in-process messages are checked too."""
    (tmp_path / "robot4.asl").write_text(ROBOT)
    (tmp_path / "boss4.asl").write_text(BOSS.format(target="robot4", start="!go."))
    (tmp_path / "mallory4.asl").write_text(BOSS.format(target="robot4", start="!go.").replace(
        "legit", "rogue"))
    (tmp_path / "crew.mas2j").write_text("MAS crew {\n  agents: robot4; mallory4; boss4;\n}\n")
    mas = ros.rosrun("rason", "mas", str(tmp_path / "crew.mas2j"), ns="/trust4",
                     params={"trusted_senders": ["boss4"]})
    mas.wait_for_line(r"\[robot4\] legit_plan_ran", timeout=30)
    mas.wait_for_line(r"dropped tellHow from 'mallory4': not a trusted sender", timeout=15)
    # the sentinel: mallory4's achieve, sent after its tellHow, dropped too
    mas.wait_for_line(r"dropped achieve from 'mallory4': not a trusted sender", timeout=15)
    assert "rogue_plan_ran" not in mas.output(), mas.output()
    assert mas.alive()
