"""Agents as ROS nodes: real roscore, real `rosrun rason agent` processes, real decomposers."""

from __future__ import annotations

import os
import re

import pytest
from agent_nodes import start_agent, write_agent
from polling import wait_until

from rason.process.procstat import sched_slice

pytestmark = pytest.mark.ros


def test_action_ok_resumes_and_a_reason_reaches_the_failure_plan(ros, tmp_path):
    ros.rosrun("rason", "echo_decomposer", ns="/b1")
    ros.wait_for_subscriber("/b1/jason/action")
    agent = start_agent(ros, tmp_path, "faulty", """
        !go.
        +!go <- .wait(500); move(1); .print("moved ok"); move(2, no_progress); .print("never").
        -!go[error(R), error_msg(M)] <- .print("failed: ", R, " / ", M).
        """, ns="/b1")
    agent.wait_for_line(r"\[faulty\] moved ok", timeout=20)
    match = agent.wait_for_line(r"\[faulty\] failed: (\w+)", timeout=20)
    assert match.group(1) == "no_progress"
    assert "never" not in agent.output()


def test_an_action_no_decomposer_handles_fails_with_no_decomposer(ros, tmp_path):
    ros.rosrun("rason", "echo_decomposer", ns="/b2")       # handles move only
    agent = start_agent(ros, tmp_path, "pilot", """
        !go.
        +!go <- .wait(300); fly(3); .print("flew").
        -!go[error(R)] <- .print("failed: ", R).
        """, ns="/b2", ack_timeout=1.0)
    match = agent.wait_for_line(r"\[pilot\] failed: (\w+)", timeout=20)
    assert match.group(1) == "no_decomposer"


def test_events_for_another_agent_are_ignored(ros, tmp_path):
    import rospy
    from jason_msgs.msg import Action, Event

    ros.init_rospy()
    actions: list[Action] = []
    rospy.Subscriber("/b3/jason/action", Action, actions.append)
    events = rospy.Publisher("/b3/jason/event", Event, queue_size=10)
    agent = start_agent(ros, tmp_path, "worker", """
        !go.
        +!go <- .wait(800); lift(2); .print("lifted").
        -!go[error(R)] <- .print("failed: ", R).
        """, ns="/b3", ack_timeout=0)
    ros.wait_for_subscriber("/b3/jason/event")
    wait_until(lambda: actions, "the lift action", watch=[agent])
    action_id = str(actions[0].action_id)
    assert (actions[0].agent, actions[0].action, list(actions[0].parameters)) == \
        ("worker", "lift", ["2"])
    events.publish(Event(agent="someone_else", event_type="action_feedback",
                         parameters=["OK", action_id]))
    # the sentinel: the worker's own feedback, after the other one on the same topic, fails the
    # action; had the other agent's OK been taken, the action would have ended "lifted" first
    events.publish(Event(agent="worker", event_type="action_feedback",
                         parameters=["jammed", action_id]))
    match = agent.wait_for_line(r"\[worker\] (lifted|failed: \w+)", timeout=60)
    assert match.group(1) == "failed: jammed", agent.output()


def test_malformed_perception_does_not_stop_the_agent(ros, tmp_path):
    import rospy
    from jason_msgs.msg import Perception

    ros.init_rospy()
    pub = rospy.Publisher("/b4/jason/perception", Perception, queue_size=10, latch=True)
    agent = start_agent(ros, tmp_path, "seer", """
        +ok(X)[source(percept)] <- .print("ok ", X).
        -ok(X) <- .print("lost ", X).
        """, ns="/b4")
    ros.wait_for_subscriber("/b4/jason/perception")
    pub.publish(Perception(source="test_cam", perception=["robot(faulty,1", "ok(1)"]))
    agent.wait_for_line(r"\[seer\] ok 1", timeout=60)
    agent.wait_for_line(r"malformed perception.*robot\(faulty,1", timeout=5)
    pub.publish(Perception(source="test_cam", perception=["ok(2)"]))
    agent.wait_for_line(r"\[seer\] lost 1", timeout=10)
    agent.wait_for_line(r"\[seer\] ok 2", timeout=10)
    assert agent.alive()


ALICE = """
    !start.
    +!start : .all_names(L) & .member(bob, L)
       <- .send(bob, tell, hello(alice));
          .send(bob, askOne, value(X), value(V));
          .print("bob says ", V);
          .send(bob, achieve, greet);
          !watch.
    +!start <- .wait(200); !start.
    +!watch <- .all_names(L); .print("names ", L); .wait(500); !watch.
    """
BOB = """
    value(42).
    +hello(X)[source(S)] <- .print("hello from ", S).
    +!greet[source(S)] <- .print("greeted by ", S).
    """


def test_two_agents_in_two_processes_talk_and_forget_each_other(ros, tmp_path):
    bob = start_agent(ros, tmp_path, "bob", BOB, ns="/r2", presence_period=0.5,
                      presence_timeout=2.0)
    alice = start_agent(ros, tmp_path, "alice", ALICE, ns="/r1", presence_period=0.5,
                        presence_timeout=2.0)
    assert alice.wait_for_line(r"\[alice\] bob says (\d+)", timeout=30).group(1) == "42"
    bob.wait_for_line(r"\[bob\] hello from alice", timeout=60)
    bob.wait_for_line(r"\[bob\] greeted by alice", timeout=10)
    # in the order of Jason's map of agents, as Jason 3.3 prints it for these two names
    alice.wait_for_line(r"\[alice\] names \[bob,alice\]", timeout=10)

    mind = ros.check_output(["rosservice", "call", "/r2/jason/bob/mind"])
    assert "value(42)" in mind and "hello(alice)" in mind

    mark = len(alice.lines())
    bob.stop()
    alice.wait_for_line(r"\[alice\] names \[alice\]$", timeout=15, start=mark)


def _thread_nices(pid: int) -> dict[str, int]:
    """The nice value of each thread of process `pid`, by thread id."""
    return {tid: os.getpriority(os.PRIO_PROCESS, int(tid)) for tid in os.listdir(f"/proc/{pid}/task")}


def test_the_threads_reading_the_fleets_messages_run_at_a_lower_priority(ros, tmp_path):
    bob = start_agent(ros, tmp_path, "bob", BOB, ns="/r2")                  # ~receive_nice 5
    alice = start_agent(ros, tmp_path, "alice", ALICE, ns="/r1", receive_nice=0)
    assert alice.wait_for_line(r"\[alice\] bob says (\d+)", timeout=30).group(1) == "42"
    bob.wait_for_line(r"\[bob\] greeted by alice", timeout=10)   # each has heard the other
    base = os.getpriority(os.PRIO_PROCESS, 0)
    bob_threads = _thread_nices(bob.pid)
    bob_nices = list(bob_threads.values())
    # the reader of alice's node's messages (and of any other publisher of /jason/messages)
    # is niced; the agent's thread, rospy's and those reading the robot's own topics are not
    assert set(bob_nices) == {base, min(base + 5, 19)}, bob_nices
    assert bob_nices.count(base) > bob_nices.count(min(base + 5, 19))
    assert set(_thread_nices(alice.pid).values()) == {base}
    # the niced readers, and only they, ask for a 0.2 ms slice (~receive_slice's default)
    niced = {tid for tid, nice in bob_threads.items() if nice != base}
    slices = {tid: sched_slice(f"/proc/{bob.pid}/task/{tid}/sched") for tid in bob_threads}
    assert niced and {slices[t] for t in niced} == {200_000}, slices
    assert 200_000 not in {v for t, v in slices.items() if t not in niced}, slices


def test_send_to_an_unknown_agent_fails_with_a_clear_reason(ros, tmp_path):
    agent = start_agent(ros, tmp_path, "lonely", """
        !start.
        +!start <- .wait(300); .send(nobody, tell, hi); .print("sent").
        -!start[error_msg(M)] <- .print("failed: ", M).
        """, ns="/b5")
    match = agent.wait_for_line(r"\[lonely\] failed: (.*)", timeout=15)
    assert "nobody" in match.group(1)
    assert "sent" not in agent.output()


def test_syntax_error_is_reported_with_file_line_col(ros, tmp_path):
    path = write_agent(tmp_path, "broken", "!start.\n+!start <- .print(\"x\"\n")
    proc = ros.rosrun("rason", "agent", "broken", str(path), ns="/b6")
    assert proc.wait(30) != 0
    assert f"{path}:" in proc.output()


def test_a_non_utf8_source_is_a_file_error_with_status_2(ros, tmp_path):
    path = tmp_path / "latin1.asl"
    path.write_bytes(b'!start.\n+!start <- .print("caf\xe9").\n')
    proc = ros.rosrun("rason", "agent", "latin1", str(path), ns="/b7")
    assert proc.wait(30) == 2
    assert f"{path}:2:23: not UTF-8 text" in proc.output()
    assert "Traceback" not in proc.output()


def test_a_non_utf8_project_is_a_file_error_with_status_2(ros, tmp_path):
    project = tmp_path / "latin1.mas2j"
    project.write_bytes(b"MAS caf\xe9 {\n  agents: bob;\n}\n")
    proc = ros.rosrun("rason", "mas", str(project), ns="/b8")
    assert proc.wait(30) == 2
    assert f"{project}: not UTF-8 text" in proc.output()
    assert "Traceback" not in proc.output()


def test_mas_hosts_every_agent_of_a_project_in_one_node(ros, tmp_path):
    write_agent(tmp_path, "bob", BOB)
    write_agent(tmp_path, "carol", """
        !start.
        +!start : .all_names(L) & .member(bob, L) <- .send(bob, tell, hello(carol)).
        +!start <- .wait(100); !start.
        """)
    project = tmp_path / "pair.mas2j"
    project.write_text("MAS pair {\n  agents: bob; carol;\n}\n")
    mas = ros.rosrun("rason", "mas", str(project), ns="/m1")
    mas.wait_for_line(r"\[bob\] hello from carol", timeout=20)
    assert "/m1/jason/bob/mind" in ros.services()
    assert "/m1/jason/carol/mind" in ros.services()


def test_a_node_that_subscribes_late_hears_who_is_there_at_once(ros, tmp_path):
    """An agent greets each new subscriber of /jason/messages with its presence, so a node
    joining the graph learns it at once, not one `presence_period` (here 60 s) later."""
    start_agent(ros, tmp_path, "greeter", "!idle.\n+!idle <- .wait(60000).\n", ns="/b8",
                presence_period=60.0, presence_timeout=200.0)
    listener = ros.run(["rostopic", "echo", "/jason/messages"], label="late listener")
    listener.wait_for_line(r"sender: \"?greeter\"?", timeout=20)

    def greeters_first() -> str | None:
        """greeter's first whole message (rostopic echo ends each one with "---")."""
        whole = listener.output().split("\n---")[:-1]
        return next((m for m in whole if re.search(r'sender: "?greeter"?', m)), None)
    wait_until(lambda: greeters_first() is not None, "greeter's whole first message", timeout=10)
    first = greeters_first()
    assert first is not None and re.search(r'performative: "?presence"?', first), first


def test_an_action_waits_until_its_decomposer_can_answer(ros, tmp_path):
    """A decomposer that already hears jason/action but whose jason/event the agent's node is
    not yet connected to would have its acknowledgement lost (-> no_decomposer): the node holds
    the action until both ways are up, then sends it once."""
    import rospy
    from jason_msgs.msg import Action, Event

    ros.init_rospy()
    actions: list[Action] = []
    rospy.Subscriber("/b9/jason/action", Action, actions.append)
    agent = start_agent(ros, tmp_path, "eager", """
        !go.
        +!go <- move(1); .print("moved").
        -!go[error(R)] <- .print("failed: ", R).
        """, ns="/b9", ack_timeout=20.0)
    ros.wait_for_subscriber("/b9/jason/action")
    # No sentinel can follow on jason/action: the node holds everything until it hears the
    # decomposer's jason/event, so 1.5 s of ROS time is given to a wrong send to show.
    rospy.sleep(1.5)
    assert actions == [], "sent before its decomposer could answer"
    events = rospy.Publisher("/b9/jason/event", Event, queue_size=10)
    wait_until(lambda: actions, "the move action", watch=[agent])
    assert len(actions) == 1, agent.output()
    action_id = str(actions[0].action_id)
    events.publish(Event(agent="eager", event_type="action_accepted", parameters=[action_id]))
    events.publish(Event(agent="eager", event_type="action_feedback",
                         parameters=["OK", action_id, "done"]))
    agent.wait_for_line(r"\[eager\] moved", timeout=20)
    assert len(actions) == 1


def test_an_action_held_for_its_connections_gets_its_full_ack_timeout(ros, tmp_path):
    """#39: an action held back while its decomposer's connections are made one after the
    other (a loaded machine) fails only when no connection came for ``~ack_timeout``, and once
    sent it gets ``~ack_timeout`` from its publication (before, the time it was held counted
    against the decomposer: here its answer came 5 s after the action was issued, 2.5 s after
    it was sent, and it failed no_decomposer)."""
    import rospy
    from jason_msgs.msg import Action, Event

    ros.init_rospy()
    agent = start_agent(ros, tmp_path, "eager", """
        !go.
        +!go <- move(1); .print("moved").
        -!go[error(R)] <- .print("failed: ", R).
        """, ns="/b39", ack_timeout=4.0)
    # the decomposer's two connections 2.5 s apart, its answer 2.5 s after the action
    actions: list[Action] = []
    rospy.Subscriber("/b39/jason/action", Action, actions.append)
    rospy.sleep(2.5)
    assert actions == [], "sent before its decomposer could answer"
    events = rospy.Publisher("/b39/jason/event", Event, queue_size=10)
    wait_until(lambda: actions, "the move action", watch=[agent])
    rospy.sleep(2.5)
    action_id = str(actions[0].action_id)
    events.publish(Event(agent="eager", event_type="action_accepted", parameters=[action_id]))
    events.publish(Event(agent="eager", event_type="action_feedback",
                         parameters=["OK", action_id, "done"]))
    agent.wait_for_line(r"\[eager\] (moved|failed: \w+)", timeout=20)
    assert "[eager] moved" in agent.output(), agent.output()[-2000:]


def test_an_agent_with_verbose_zero_prints_bare_text_and_its_warnings(ros, tmp_path):
    write_agent(tmp_path, "quiet", """
        !start.
        +!start <- .println(bare_text); .log(info, hidden); !missing.
        """)
    project = tmp_path / "quiet.mas2j"
    project.write_text("MAS quiet {\n  agents: quiet [verbose=0];\n}\n")
    mas = ros.rosrun("rason", "mas", str(project), ns="/v0")
    mas.wait_for_line(r"^bare_text$", timeout=20)
    mas.wait_for_line(r"\[quiet\] Found a goal for which there is no relevant plan", timeout=20)
    assert "hidden" not in mas.output()
