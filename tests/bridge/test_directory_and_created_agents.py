"""The directory facilitator across nodes and ``.create_agent``/``.kill_agent`` in an agent
node: real roscore, real ``rosrun rason agent`` processes."""

from __future__ import annotations

import textwrap

import pytest
from agent_nodes import start_agent
from polling import wait_until

pytestmark = pytest.mark.ros


SELLER = """
    !start.
    +!start <- .df_register("sell(book)"); .df_register(repair, "garage"); .print(registered).
    +!stop_selling <- .df_deregister("sell(book)"); .print(deregistered).
    """

BUYER = """
    !find.
    +!find <- .df_subscribe("sell(book)"); !search.
    +!search <- .df_search("sell(book)", L); .df_search(repair, R);
                if (L == []) { .wait(200); !search } else { .print("sellers ", L, " ", R) }.
    +provider(A, S)[source(df)] <- .print("told ", A, " sells ", S).
    """


def test_agents_on_different_nodes_find_each_others_services(ros, tmp_path):
    buyer = start_agent(ros, tmp_path, "buyer", BUYER, ns="/df1", presence_period=0.5,
                        presence_timeout=3.0)
    seller = start_agent(ros, tmp_path, "seller", SELLER, ns="/df2", presence_period=0.5,
                         presence_timeout=3.0)
    seller.wait_for_line(r"\[seller\] registered", timeout=30)
    buyer.wait_for_line(r'\[buyer\] told seller sells sell\(book\)', timeout=30)
    buyer.wait_for_line(r"\[buyer\] sellers \[seller\] \[seller\]", timeout=30)
    # a late subscriber gets the providers present when it subscribes (latched registrations)
    late = start_agent(ros, tmp_path, "late", """
        !s.
        +!s <- .df_subscribe(repair).
        +provider(A, S)[source(df)] <- .print("told ", A, " does ", S).
        """, ns="/df3", presence_period=0.5, presence_timeout=3.0)
    late.wait_for_line(r'\[late\] told seller does repair', timeout=30)
    # a provider that leaves the graph is no longer found once its presence lapses
    seller.stop()
    watcher = start_agent(ros, tmp_path, "watcher", """
        !w.
        +!w <- .df_search(repair, L); .print("repairers ", L); .wait(500); !w.
        """, ns="/df4", presence_period=0.5, presence_timeout=3.0)
    watcher.wait_for_line(r"\[watcher\] repairers \[\]", timeout=30)


def test_create_agent_in_an_agent_node_gets_its_mind_service_and_kill_removes_it(ros, tmp_path):
    (tmp_path / "helper.asl").write_text(textwrap.dedent("""
        +!hello[source(S)] <- .print("hello from ", S); .send(S, tell, ready).
        """))
    boss = start_agent(ros, tmp_path, "boss", """
        !start.
        +!start <- .create_agent(helper, "helper.asl"); .create_agent(N, "helper.asl");
                   .print("created ", N); .send(helper, achieve, hello).
        +ready[source(A)] <- .print("ready ", A); .all_names(L); .print("names ", L).
        +!kill <- .kill_agent(helper); .all_names(L); .print("after kill ", L).
        """, ns="/ca1")
    boss.wait_for_line(r"\[boss\] created agent", timeout=30)
    boss.wait_for_line(r"\[helper\] hello from boss", timeout=30)
    boss.wait_for_line(r"\[boss\] ready helper", timeout=30)
    # (agents of an earlier test may still be heard for a presence timeout: only ours matter)
    names = boss.wait_for_line(r"\[boss\] names \[(.*)\]", timeout=10).group(1).split(",")
    assert {"agent", "boss", "helper"} <= set(names)
    ros.wait_for_service("/ca1/jason/helper/mind", timeout=20)
    mind = ros.check_output(["rosservice", "call", "/ca1/jason/helper/mind"])
    assert 'agent: "helper"' in mind
    # the created agent is reached from another node like any agent
    other = start_agent(ros, tmp_path, "other", """
        !go.
        +!go : .all_names(L) & .member(helper, L) <- .send(helper, achieve, hello).
        +!go <- .wait(200); !go.
        +ready[source(A)] <- .print("ready ", A); .send(boss, achieve, kill).
        """, ns="/ca2")
    other.wait_for_line(r"\[other\] ready helper", timeout=40)
    after = boss.wait_for_line(r"\[boss\] after kill \[(.*)\]", timeout=20).group(1).split(",")
    assert {"agent", "boss", "other"} <= set(after) and "helper" not in after
    wait_until(lambda: "/ca1/jason/helper/mind" not in ros.services(),
               "the killed agent's mind service gone", timeout=20, period=0.2)
    assert "/ca1/jason/agent/mind" in ros.services()
