"""The inspector's pure parts: the structured mind of rason.asl agents, the store's history."""

from __future__ import annotations

import json
import threading
from dataclasses import asdict

import pytest

from rason.asl import Agent, AgentArch
from rason.inspector.store import BadMindState, InspectorStore, Pose, RobotsView
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
    state = _agent_waiting_for_act().mind_state()
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
    state = _agent_waiting_for_act().mind_state()
    beliefs = {b.text: b for b in state.beliefs}
    assert beliefs["b(1)"].group == "b/1"
    assert beliefs["b(1)"].annots == ["certain"] and beliefs["b(1)"].sources == ["x"]
    assert beliefs["a"].sources == ["self"]
    assert state.rules == ["r(X) :- value(X)"]


def test_mind_state_of_a_fresh_agent_has_the_initial_goal_as_an_event():
    state = Agent("t", PROGRAM, HeldActions()).mind_state()
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
    assert doc["mind"] == json.loads(json.dumps(asdict(agent.mind_state())))


class _CountedSnapshots:
    """The agent, counting the snapshots taken of its mind (its compiled class takes no patch)."""

    def __init__(self, agent: Agent) -> None:
        self.agent = agent
        self.snapshots: list[bool] = []

    def mind_state(self, blocking: bool = True):
        self.snapshots.append(blocking)
        return self.agent.mind_state(blocking)

    def __getattr__(self, name: str):
        return getattr(self.agent, name)


def test_publisher_takes_no_snapshot_while_nobody_listens():
    agent = _CountedSnapshots(Agent("t", PROGRAM, HeldActions()))
    sent: list[str] = []
    listening = [False]
    snapshots = agent.snapshots
    publisher = MindStatePublisher(agent, lambda: [], sent.append, "/n", "/",  # type: ignore[arg-type]
                                   listened=lambda: listening[0])
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
        store.add_state("a", {"agent": "a", "mind": {"k": k}}, float(k))
    latest = store.mind("a")
    assert (latest["index"], latest["first"], latest["last"]) == (4, 2, 4)
    assert store.mind("a", 2)["state"]["mind"] == {"k": 2}
    assert store.mind("a", 1) is None and store.mind("a", 5) is None
    assert store.mind("nobody") is None
    assert events.count("mind") == 5 and events[0] == "agents"


def test_store_rejects_malformed_states_and_unknown_agents():
    store = InspectorStore()
    store.agent_heard("a")
    for bad in (None, [], {"agent": "a"}, {"agent": "a", "mind": "text"}):
        with pytest.raises(BadMindState):
            store.add_state("a", bad, 0.0)
    with pytest.raises(KeyError):
        store.add_state("b", {"agent": "b", "mind": {}}, 0.0)
    assert store.mind("a") is None


def test_agents_leave_and_come_back():
    store = InspectorStore()
    store.agent_heard("a")
    store.set_topic("a", "/x/jason/a/mind_state")
    assert store.agent_gone("a") and not store.agent_gone("a")
    assert store.agents() == [] and store.without_topic() == []
    assert store.agent_heard("a")
    assert [a["name"] for a in store.agents()] == ["a"]


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
        with agent._state_lock:           # what a reasoning cycle of the agent's thread holds
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
