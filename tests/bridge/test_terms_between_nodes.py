"""Terms cross processes intact: real agent nodes talking through /jason/messages."""

from __future__ import annotations

import sys
import time

import pytest
from agent_nodes import connected_to, start_agent
from polling import wait_until

pytestmark = pytest.mark.ros

# strings with quotes, a backslash and non-ASCII, quoted atoms (one uppercase), negative
# numbers, annotations, a list with a tail, a nested list
INFO = ('info("say \\"hi\\" \\\\ été ☃", \'Robot lost\'(-2.5, \'X\'), [1, -0.001, "a,b" | T], '
        'f(a)[k, source(x)], [[], [~q]])')


def test_an_askone_reply_with_hard_text_arrives_equal(ros, tmp_path):
    teller = start_agent(ros, tmp_path, "teller", f"""
        {INFO}.
        n(20000).
        +!kqml_received(S, askOne, big, M) : n(N)
           <- .findall(v(K, "k\\\\", 'K'), .range(K, 1, N), L); .send(S, tell, L, M).
        """, ns="/t1")
    asker = start_agent(ros, tmp_path, "asker", f"""
        !go.
        +!go : .all_names(L) & .member(teller, L)
           <- .send(teller, askOne, info(A, B, C, D, E), R);
              // the reply's tail variable is renamed apart (as Jason copies messages), so the
              // ground parts are compared by unification: each must arrive exactly as sent
              if (R = {INFO}[source(teller)] & not .ground(T)) {{
                  .print("equal") }} else {{ .print("differs: ", R) }};
              .send(teller, askOne, big, Big);
              .length(Big, N); .nth(19999, Big, Last);
              if (Last == v(20000, "k\\\\", 'K')) {{ .print("big ", N) }} else {{ .print("bad ", Last) }}.
        +!go <- .wait(200); !go.
        """, ns="/t2")
    asker.wait_for_line(r"\[asker\] (equal|differs.*)$", timeout=60)
    assert "[asker] equal" in asker.output(), asker.output()
    asker.wait_for_line(r"\[asker\] (big|bad) ", timeout=180)
    assert "[asker] big 20000" in asker.output(), asker.output()
    assert teller.alive()


def test_messages_with_nan_or_infinity_are_dropped_with_one_warning(ros, tmp_path):
    import rospy
    from jason_msgs.msg import AgentMessage

    ros.init_rospy()
    pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=100)
    agent = start_agent(ros, tmp_path, "guard", """
        +v(X)[source(S)] <- .print("got ", X, " from ", S).
        """, ns="/t3")
    wait_until(lambda: connected_to(pub, "/t3/jason/guard"), "the connection to guard's node")
    for k, content in enumerate(["v(NaN)", "v(Infinity)", "v(-Infinity)", "v(1e999)", "v(f(NaN))"] * 20):
        pub.publish(AgentMessage(sender="probe", receiver="guard", performative="tell",
                                 content=content, reply_with=f"m{k}", in_reply_to=""))
    pub.publish(AgentMessage(sender="probe", receiver="guard", performative="tell",
                             content="v(1.5)", reply_with="ok", in_reply_to=""))
    agent.wait_for_line(r"\[guard\] got 1.5 from probe", timeout=20)
    out = agent.output()
    assert "got NaN" not in out and "got Infinity" not in out and "got -Infinity" not in out
    assert "got f(" not in out and "got X" not in out
    warnings = [line for line in out.splitlines() if "not a finite number" in line]
    assert 1 <= len(warnings) <= 2, warnings    # rate-limited: not one per message
    assert agent.alive()


def test_sets_maps_and_queues_arrive_as_the_same_kind_of_collection(ros, tmp_path):
    # Jason's local infrastructure hands the receiver the collections themselves; between
    # nodes each one travels as text and is made again: same kind, same members, same order
    receiver = start_agent(ros, tmp_path, "keeper", """
        +coll(S, M, Q, P)[source(A)]
           <- .type(S, TS); .type(M, TM); .type(Q, TQ); .type(P, TP);
              .print("kinds ", TS, " ", TM, " ", TQ, " ", TP);
              .print("values ", S, " ", M, " ", Q, " ", P);
              .set.add(S, c); .map.get(M, k, V); .queue.head(P, H); .length(Q, N);
              .print("use ", S, " ", V, " ", H, " ", N).
        +nested(L)[source(A)] <- L = [S, f(M)]; .type(S, T1); .type(M, T2); .print("nested ", T1, " ", T2).
        """, ns="/c1")
    start_agent(ros, tmp_path, "maker", """
        !go.
        +!go : .all_names(L) & .member(keeper, L)
           <- .set.create(S); .set.add(S, b); .set.add(S, a);
              .map.create(M); .map.put(M, k, v(1)); .map.put(M, "z", [1,2]);
              .queue.create(Q); .queue.add(Q, z); .queue.add(Q, a);
              .queue.create(P, priority); .queue.add(P, z); .queue.add(P, a); .queue.add(P, m);
              .queue.add(P, b);
              .send(keeper, tell, coll(S, M, Q, P)); .send(keeper, tell, nested([S, f(M)])).
        +!go <- .wait(200); !go.
        """, ns="/c2")
    receiver.wait_for_line(r"\[keeper\] nested ", timeout=60)
    receiver.wait_for_line(r"\[keeper\] use ", timeout=30)
    out = receiver.output()
    assert "[keeper] kinds set map queue queue" in out, out
    assert '[keeper] values {a,b} {"z"->[1,2],k->v(1)} [z, a] [a, b, m, z]' in out, out
    assert "[keeper] use {a,b,c} v(1) a 2" in out, out
    assert "[keeper] nested set map" in out, out


# A node that announces agent "bob" on /jason/messages and subscribes to the topic only once the
# file argv[1] exists (as a node just started, or a link just back, can hear late: the two
# directions of a connection come up separately); then it prints every message for bob.
LATE_LISTENER = """
import os
import sys
import time
import rospy
from jason_msgs.msg import AgentMessage

rospy.init_node("bob_node")
pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10)

def beat():
    pub.publish(AgentMessage(sender="bob", performative="presence", stamp=rospy.Time.now()))

while not os.path.exists(sys.argv[1]):     # beats at the presence pace until told to listen
    beat()
    time.sleep(0.2)
rospy.Subscriber("/jason/messages", AgentMessage,
                 lambda m: m.receiver == "bob" and print("bob got", m.performative, m.content,
                                                         flush=True))
print("subscribed", flush=True)
while not rospy.is_shutdown():             # the presence pace
    beat()
    time.sleep(0.2)
"""


def test_a_message_to_an_agent_heard_before_it_listens_waits_for_it(ros, tmp_path):
    """alice hears bob (bob's node publishes to her) before bob's node subscribes to hers: the
    messages she sends meanwhile wait for that subscription, then arrive in order."""
    script, listen = tmp_path / "late_listener.py", tmp_path / "listen"
    script.write_text(LATE_LISTENER)
    bob = ros.run([sys.executable, str(script), str(listen)], label="bob_node")
    alice = start_agent(ros, tmp_path, "alice", """
        !greet.
        +!greet : .all_names(L) & .member(bob, L)
           <- .send(bob, tell, hi(1)); .send(bob, tell, hi(2)); .print("sent").
        +!greet <- .wait(50); !greet.
        """, ns="/h1")
    alice.wait_for_line(r"\[alice\] sent", timeout=30)
    time.sleep(0.5)          # published now, they would be lost: bob's node does not listen yet
    listen.touch()
    bob.wait_for_line(r"subscribed", timeout=30)
    bob.wait_for_line(r"bob got tell hi\(2\)", timeout=30)
    got = [line for line in bob.lines() if line.startswith("bob got")]
    assert got == ["bob got tell hi(1)", "bob got tell hi(2)"]


def test_a_plan_with_statements_and_forks_arrives_whole_and_runs(ros, tmp_path):
    # plan terms travel as rason's source text (Jason's printed form, with `.if_then_else`
    # and blocks of several deeds as arguments, does not read back); the asker prints the
    # answer as Jason prints it and runs it
    start_agent(ros, tmp_path, "teller", """
        +!g(X) <- if (X > 1) { .print(big); .print(X) } else { .print(small) };
                  for (.member(Y, [a, b])) { .print(Y) }; {.print(p); !q} |&| (!q ||| !q).
        """, ns="/t5")
    asker = start_agent(ros, tmp_path, "asker", """
        !go.
        +!go : .all_names(L) & .member(teller, L)
           <- .send(teller, askHow, {+!g(_)}, Plans); .print("got ", Plans);
              .add_plan(Plans); !g(2); .print("ran").
        +!go <- .wait(200); !go.
        +!q <- .print(q).
        """, ns="/t6")
    asker.wait_for_line(r"\[asker\] ran$", timeout=60)
    lines = [ln.split("] ", 1)[1] for ln in asker.output().splitlines() if ln.startswith("[asker] ")]
    got = next(ln for ln in lines if ln.startswith("got "))
    assert ".if_then_else((_" in got and ",.print(big); .print(_" in got, got
    assert ".foreach(.member(_" in got and ".fork(and,.print(p); !q,.fork(or,!q,!q))" in got, got
    ran = lines[lines.index(got) + 1:]
    assert ran[:4] == ["big", "2", "a", "b"] and ran[-1] == "ran", ran
    assert "p" in ran and "q" in ran, ran
