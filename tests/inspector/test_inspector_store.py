"""The inspector's pure parts: the structured mind of rason.asl agents, the store's history."""

from __future__ import annotations

import json
import socket
import threading
from dataclasses import asdict

import pytest

from rason.asl import Agent, AgentArch
from rason.asl.inspection import MindReader, mind_state
from rason.inspector.store import MAX_GONE, MAX_NAME, BadMindState, InspectorStore, Pose, RobotsView
from rason.inspector.web import allowed_hosts, host_name, interface_addresses
from rason.ros.mind_state import MindStatePublisher

PROGRAM = """
value(0).
b(1)[source(x), certain].
r(X) :- value(X).
!start.
+!start <- +a; !g(3); .print(done).
+!g(N) : N > 0 <- .print(N); if (N > 1) { .print(big); act(N) }; !g(N - 1).
+!g(0).
"""


class HeldActions(AgentArch):
    """Actions never finish; the console is kept."""

    def __init__(self) -> None:
        super().__init__()
        self.lines: list[str] = []

    def act(self, agent, action, action_id) -> None:
        pass

    def console(self, agent_name: str, text: str) -> None:
        self.lines.append(text)


def _agent_waiting_for_act() -> Agent:
    agent = Agent("t", PROGRAM, HeldActions())
    for _ in range(50):
        agent.step()
    return agent


def test_mind_state_shows_each_intention_as_a_stack_with_its_position():
    state = mind_state(_agent_waiting_for_act())
    (intention,) = state.intentions
    assert intention.suspended == "action 1"
    top, bottom = intention.means
    assert top.trigger == "+!g(3)[source(self)]" and top.where == "<string>:7"
    assert [(s.text, s.step) for s in top.body] == [
        (".print(N)", "done"), ("if ((N > 1)) { .print(big); act(N) }", "current"),
        ("!g((N-1))", "todo")]
    assert top.doing == "act(N)"                 # inside the if block
    assert top.unifier == {"N": "3"}
    assert [(s.text, s.step) for s in bottom.body] == [
        ("+a", "done"), ("!g(3)", "current"), (".print(done)", "todo")]
    assert state.desires == ["+!start[source(self)]", "+!g(3)[source(self)]"]


def test_mind_state_beliefs_keep_annotations_and_sources_apart():
    state = mind_state(_agent_waiting_for_act())
    beliefs = {b.text: b for b in state.beliefs}
    assert beliefs["b(1)"].group == "b/1"
    assert beliefs["b(1)"].annots == ["certain"] and beliefs["b(1)"].sources == ["x"]
    assert beliefs["a"].sources == ["self"]
    assert state.rules == ["r(X) :- value(X)"]


def test_mind_state_of_a_fresh_agent_has_the_initial_goal_as_an_event():
    state = mind_state(Agent("t", PROGRAM, HeldActions()))
    assert [e.trigger for e in state.events] == ["+!start[source(self)]"]
    assert state.events[0].intention is None and state.intentions == []


def test_publisher_sends_only_when_the_mind_changed():
    agent = Agent("t", PROGRAM, HeldActions())
    sent: list[str] = []
    publisher = MindStatePublisher(agent, lambda: [], sent.append, "/n", "/")
    assert publisher.tick(1.0) and not publisher.tick(2.0)      # nothing changed
    agent.step()
    assert publisher.tick(3.0)
    doc = json.loads(sent[-1])
    assert doc["stamp"] == 3.0 and doc["seq"] == 2 and doc["agent"] == "t"
    assert doc["mind"] == json.loads(json.dumps(asdict(mind_state(agent))))


class _CountedSnapshots(MindReader):
    """A mind reader counting the snapshots it takes."""

    def __init__(self, agent: Agent) -> None:
        super().__init__(agent)
        self.snapshots: list[bool] = []

    def snapshot(self, blocking: bool = True):
        self.snapshots.append(blocking)
        return super().snapshot(blocking)


def test_publisher_takes_no_snapshot_while_nobody_listens():
    agent = Agent("t", PROGRAM, HeldActions())
    sent: list[str] = []
    listening = [False]
    publisher = MindStatePublisher(agent, lambda: [], sent.append, "/n", "/",
                                   listened=lambda: listening[0])
    reader = publisher.reader = _CountedSnapshots(agent)
    snapshots = reader.snapshots
    assert not publisher.tick(1.0) and not publisher.tick(2.0)
    assert sent == [] and snapshots == []
    listening[0] = True                   # an inspector subscribed: the next tick serves it
    assert publisher.tick(3.0) and not publisher.tick(4.0)
    listening[0] = False
    assert not publisher.tick(5.0)
    listening[0] = True                   # the mind did not change: a new listener still gets it
    assert publisher.tick(6.0)
    assert [json.loads(text)["stamp"] for text in sent] == [3.0, 6.0]
    assert len(snapshots) == 3


def test_store_keeps_a_bounded_numbered_history():
    events = []
    store = InspectorStore(history=3, on_change=lambda kind, payload: events.append(kind))
    assert store.agent_heard("a") and not store.agent_heard("a")
    for k in range(5):
        store.add_state("a", json.dumps({"agent": "a", "mind": {"k": k}}), float(k))
    latest = store.mind("a")
    assert (latest["index"], latest["first"], latest["last"]) == (4, 2, 4)
    assert store.mind("a", 2)["state"]["mind"] == {"k": 2}
    assert store.mind("a", 1) is None and store.mind("a", 5) is None
    assert store.mind("nobody") is None
    assert events.count("mind") == 5 and events[0] == "agent"


def test_store_rejects_malformed_states_and_unknown_agents():
    store = InspectorStore()
    store.agent_heard("a")
    for bad in ("null", "[]", '{"agent": "a"}', '{"agent": "a", "mind": "text"}', "{not json"):
        with pytest.raises(BadMindState):
            store.add_state("a", bad, 0.0)
    with pytest.raises(KeyError):
        store.add_state("b", '{"agent": "b", "mind": {}}', 0.0)
    assert store.mind("a") is None


def test_agents_leave_and_come_back():
    store = InspectorStore()
    store.agent_heard("a")
    store.set_topic("a", "/x/jason/a/mind_state")
    assert store.agent_gone("a") and not store.agent_gone("a")
    assert store.agents() == [] and store.without_topic() == []
    assert store.agent_heard("a")
    assert [a["name"] for a in store.agents()] == ["a"]


def _state(name: str, size: int = 0, k: int = 0) -> str:
    return json.dumps({"agent": name, "namespace": "/", "mind": {"k": k, "pad": "x" * size}})


def test_store_pushes_one_agent_at_a_time_never_the_whole_list():
    events: list[tuple[str, dict]] = []
    store = InspectorStore(on_change=lambda kind, payload: events.append((kind, payload)))
    for k in range(100):
        store.agent_heard(f"a{k}")
    store.set_topic("a5", "/jason/a5/mind_state")
    store.agent_gone("a7")
    assert [kind for kind, _ in events] == ["agent"] * 101 + ["gone"]
    assert events[0][1] == {"name": "a0", "present": True, "topic": None, "namespace": None,
                            "first": None, "last": None}
    assert events[100][1]["topic"] == "/jason/a5/mind_state" and events[101][1] == {"name": "a7"}


def test_agents_that_left_are_pruned_and_newcomers_past_max_agents_ignored():
    store = InspectorStore(max_agents=50)
    for k in range(5000):                     # a flood of names, each gone again
        store.agent_heard(f"f{k}")
        store.agent_gone(f"f{k}")
    assert store.memory()["present"] == 0 and len(store._agents) == 0    # none kept a state
    for k in range(100):                      # agents with a mind, then gone: the last 32 kept
        store.agent_heard(f"m{k}")
        store.add_state(f"m{k}", _state(f"m{k}"), 0.0)
        store.agent_gone(f"m{k}")
    assert len(store._agents) == MAX_GONE and store.known("m99") and not store.known("m0")
    assert store.mind("m99")["present"] is False
    for k in range(80):
        store.agent_heard(f"p{k}")
    assert [a["name"] for a in store.agents()][-1] == "p9"          # sorted: p0..p49
    assert len(store.agents()) == 50 and store.refused == 30
    store.agent_gone("p3")
    assert not store.agent_heard("n" * (MAX_NAME + 1)) and store.refused == 30   # never kept
    assert store.agent_heard("late") and not store.agent_heard("later")


def test_history_is_bounded_in_bytes_keeping_each_agents_newest_state():
    store = InspectorStore(history=300, history_bytes=100_000)
    for name in ("quiet", "big"):
        store.agent_heard(name)
    store.add_state("quiet", _state("quiet", 1000), 0.0)
    for k in range(50):
        store.add_state("big", _state("big", 20_000, k), float(k))
    memory = store.memory()
    assert memory["bytes"] <= 100_000
    big = store.mind("big")
    assert big["state"]["mind"]["k"] == 49 and big["last"] - big["first"] + 1 == 4
    assert store.mind("quiet") is not None          # a quiet agent's only state stays
    assert store.mind("big", big["first"] - 1) is None
    with pytest.raises(BadMindState, match="more than half"):
        store.add_state("big", _state("big", 60_000), 0.0)
    for k in range(10):                       # many agents, each one large state: the oldest go
        store.agent_heard(f"n{k}")
        store.add_state(f"n{k}", _state(f"n{k}", 30_000), 0.0)
    assert store.memory()["bytes"] <= 100_000 and store.mind("n9") is not None
    assert store.mind("n0") is None
    assert len(store._arrivals) <= 2 * store._states + 1024


def test_robots_trail_thins_out_small_moves():
    robots = RobotsView()
    for k in range(100):
        robots.pose("r", False, Pose(k * 0.001, 0.0, 0.0, float(k)))     # 10 cm in 1 mm steps
    odom = robots.snapshot()["robots"]["r"]["odom"]
    assert 8 <= len(odom["trail"]) <= 11
    assert odom["first"]["x"] == 0.0 and odom["pose"]["x"] == pytest.approx(0.099)
    assert robots.snapshot()["robots"]["r"]["truth"] is None


def test_a_busy_agent_publishes_its_mind_from_its_own_cycle():
    arch = HeldActions()
    agent = Agent("t", PROGRAM, arch)
    sent: list[str] = []
    scheduled: list = []
    publisher = MindStatePublisher(agent, lambda: [], sent.append, "/n", "/",
                                   schedule=scheduled.append)
    held, release = threading.Event(), threading.Event()

    def cycle_in_progress() -> None:
        with agent.runner.state_lock:           # what a reasoning cycle of the agent's thread holds
            held.set()
            release.wait(10)

    busy = threading.Thread(target=cycle_in_progress)
    busy.start()
    held.wait(10)
    assert publisher.tick(5.0) is False and sent == []      # the timer does not wait
    assert scheduled == [publisher.at_cycle]
    release.set()
    busy.join()
    scheduled[0]()                        # the agent's next cycle takes it
    assert len(sent) == 1 and json.loads(sent[0])["stamp"] == 5.0
    publisher.at_cycle()                  # nothing left to do
    assert len(sent) == 1


def test_a_failing_publication_never_reaches_the_reasoning_cycle():
    agent = Agent("t", PROGRAM, HeldActions())

    def broken(_text: str) -> None:
        raise OSError("link down")

    warnings: list[str] = []
    publisher = MindStatePublisher(agent, lambda: [], broken, "/n", "/",
                                   warn=warnings.append)
    publisher._due = 1.0
    publisher.at_cycle()                  # reported, not raised
    assert publisher._due is None
    assert warnings == ["[t] mind_state not published: OSError: link down"]


def test_host_names_the_inspector_answers():
    assert [host_name(h) for h in ("127.0.0.1:3272", "[::1]:80", "Example.ORG.:8", "::1", "x")] \
        == ["127.0.0.1", "::1", "example.org", "::1", "x"]
    assert allowed_hosts("127.0.0.1") == {"127.0.0.1", "localhost", "::1"}
    assert allowed_hosts("192.0.2.7", ["Robot.lab "]) == {"192.0.2.7", "robot.lab"}
    every = allowed_hosts("0.0.0.0")
    assert {"127.0.0.1", "localhost", socket.gethostname().lower()} <= every
    assert interface_addresses() <= every and "127.0.0.1" in interface_addresses()
    assert "evil.example" not in every
