"""A message never runs an internal action it is not allowed to (#37 item 1).

The issue's three attacks, with real roscore and agent nodes: an askOne whose content is an
internal action (``.add_plan`` then a tell that triggers the plan, ``.list_files`` to read the
receiver's files, ``.stopMAS`` to stop its reasoning). Keyed with a trusted sender: a keyed but
untrusted agent (a real node, its messages signed) tries them; open (no key, no trusted
senders): a process on the graph spoofs them. Every one is dropped with a warning, the
receiver keeps reasoning, and an open node says at start-up that it accepts anyone.
"""

from __future__ import annotations

import secrets
from pathlib import Path

import pytest
from agent_nodes import connected_to, key_file, start_agent
from polling import wait_until

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

ROBOT = """
    secret(42).
    +ping[source(S)] <- .print("pong ", S).
    +pwn <- .print("pwned").
    """
#: ms the attacker waits for the answer to each forbidden ask. Its timeout is what the attacker
#: sees, so it stays, but short: the connections are proven first (an allowed ask answered), an
#: answer would come within milliseconds, and what shows that none was sent is the receiver's
#: own "dropped" line for each, asserted below, with the allowed ask after them answered.
FORBIDDEN_ASK_MS = 500
ATTACKER = """
    !go.
    +!go : .all_names(L) & .member({target}, L)
       <- .send({target}, askOne, secret(X), A0, 500);
          !attack(A0).
    +!go <- .wait(200); !go.
    +!attack(timeout) <- !go.         // the ask went before the connections were up: again
    +!attack(_)
       <- .send({target}, askOne, .add_plan({{+pwn <- .print(pwned)}}), A1, {ask_ms});
          .print("answer1 ", A1);
          .send({target}, tell, pwn);
          .send({target}, askOne, .list_files("{folder}", "secret.*", F), A2, {ask_ms});
          .print("answer2 ", A2);
          .send({target}, askOne, .stopMAS, A3, {ask_ms});
          .print("answer3 ", A3);
          .send({target}, askOne, secret(X), A4, 3000);
          .print("answer4 ", A4);
          .send({target}, tell, ping).
    """


def test_a_keyed_untrusted_agent_cannot_run_internal_actions_by_asking(ros: RosHarness,
                                                                       tmp_path: Path):
    key = key_file(tmp_path, "fleet.key")
    (tmp_path / "secret.txt").write_text("the receiver's secret\n")
    robot = start_agent(ros, tmp_path, "robot7", ROBOT.replace("+pwn", "+other"),
                        ns="/ria7", auth_key_file=key, trusted_senders=["boss7"])
    mallory = start_agent(ros, tmp_path, "mallory7",
                          ATTACKER.format(target="robot7", folder=tmp_path,
                                          ask_ms=FORBIDDEN_ASK_MS),
                          ns="/ria7_m", auth_key_file=key)
    mallory.wait_for_line(r"\[mallory7\] answer4 ", timeout=60)
    robot.wait_for_line(r"\[robot7\] pong mallory7", timeout=30)
    out, attacker = robot.output(), mallory.output()
    assert "pwned" not in out, out
    assert "secret.txt" not in attacker, attacker
    for answer in ("answer1", "answer2", "answer3"):
        assert f"{answer} timeout" in attacker, attacker
    # an ask about a belief is still answered (asks are open to every sender)
    assert "answer4 secret(42)" in attacker, attacker
    for ia in (".add_plan", ".list_files", ".stopMAS"):
        assert f"dropped askOne from 'mallory7': its content calls {ia}" in out, out
    assert "accepts any sender" not in out, out
    assert robot.alive()


def test_an_open_node_says_so_and_still_refuses_internal_actions(ros: RosHarness,
                                                               tmp_path: Path):
    import rospy
    from jason_msgs.msg import AgentMessage

    robot = start_agent(ros, tmp_path, "robot8", ROBOT.replace("+pwn", "+other"), ns="/ria8")
    robot.wait_for_line(r"no ~auth_key_file: .*accepts any sender on the ROS graph", timeout=15)
    ros.init_rospy()
    pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10)
    wait_until(lambda: connected_to(pub, "/ria8/jason/robot8"), "a connection to the agent", timeout=10)

    def spoof(performative: str, content: str) -> None:
        pub.publish(AgentMessage(sender="mallory8", receiver="robot8", performative=performative,
                                 content=content, reply_with=secrets.token_hex(4)))

    spoof("askOne", ".add_plan({+pwn <- .print(pwned)})")
    spoof("askOne", "not .stopMAS")            # inside a formula too
    spoof("askOne", ".stopMAS")
    spoof("askAll", ".my_name(N)")
    spoof("tell", "{p :- .stopMAS}")              # a rule that would run it when queried
    spoof("achieve", ".stopMAS")
    spoof("tell", "pwn")
    spoof("tell", "ping")
    robot.wait_for_line(r"\[robot8\] pong mallory8", timeout=15)
    pub.unregister()
    out = robot.output()
    assert "dropped askOne from 'mallory8': its content calls .add_plan" in out, out
    assert "dropped askOne from 'mallory8': its content calls .stopMAS" in out, out
    assert "dropped tell from 'mallory8': its content holds a plan term" in out, out
    assert "dropped achieve from 'mallory8': its content calls .stopMAS" in out, out
    assert "pwned" not in out, out
    assert out.count("accepts any sender") == 1, out
    assert robot.alive()
