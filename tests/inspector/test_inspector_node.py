"""``rosrun rason mind_inspector`` against real agent nodes: discovery, mind states, pushed
events, history bounds, agents leaving, bad requests, the loopback default."""

from __future__ import annotations

import json
import socket
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest
import rospy
from agent_nodes import start_agent
from jason_msgs.msg import AgentMessage
from polling import wait_until
from std_msgs.msg import String

from rason.ros.presence import GOODBYE, MESSAGES_TOPIC, PRESENCE

pytestmark = pytest.mark.ros

ALICE = """
count(0).
!count.
!act.
!greet.
+!count : count(N) & N < 100000 <- -+count(N + 1); .wait(300); !count.
+!act <- .print(moving); move(1); .print(moved).
+!greet <- .send(bob, tell, hello(1)).
-!greet <- .wait(300); !greet.
"""
BOB = """
+hello(X)[source(A)] <- +greeted_by(A).
"""


def _get(url: str, timeout: float = 10.0) -> tuple[int, dict | str]:
    try:
        with urllib.request.urlopen(url, timeout=timeout) as response:
            body = response.read().decode()
            status = response.status
    except urllib.error.HTTPError as err:
        body, status = err.read().decode(), err.code
    try:
        return status, json.loads(body)
    except ValueError:
        return status, body


def _agents(url: str) -> dict[str, dict]:
    status, body = _get(url + "api/agents")
    assert status == 200, body
    return {a["name"]: a for a in body["agents"]}


@pytest.fixture(scope="module")
def graph(ros_session, tmp_path_factory):
    """Two agents in their own namespaces and an inspector keeping 5 states per agent, shared
    by the tests of this module (the one that stops bob comes last)."""
    ros = ros_session
    checkpoint = ros.checkpoint()
    ros.set_param("/use_sim_time", False)
    try:
        yield _start_graph(ros, tmp_path_factory.mktemp("inspector"))
    finally:
        ros.rollback(checkpoint)


def _start_graph(ros, tmp_path: Path):
    inspector = ros.rosrun("rason", "mind_inspector", params={"port": 0, "history": 5})
    url = inspector.wait_for_line(r"mind inspector: (http://127\.0\.0\.1:\d+/)", 120).group(1)
    bob = start_agent(ros, tmp_path, "bob", BOB, ns="/insp_b")
    alice = start_agent(ros, tmp_path, "alice", ALICE, ns="/insp_a", ack_timeout=0,
                        action_timeout=0)
    # one listing for both checks: bob may be ready while alice is not heard yet, and heard
    # (without her topic) by a second listing a moment later
    wait_until(lambda: (agents := _agents(url)) and {"alice", "bob"} <= set(agents) and all(
        a.get("topic") and a.get("last") is not None for a in agents.values()),
        "both agents with their mind_state topics", timeout=150, period=0.3)
    return url, inspector, alice, bob


def test_inspector_shows_each_agents_mind(graph):
    url, inspector, _alice, _bob = graph
    agents = _agents(url)
    assert agents["alice"]["topic"] == "/insp_a/jason/alice/mind_state"
    assert agents["bob"]["namespace"] == "/insp_b/"
    assert any("loopback only" in line for line in inspector.lines())

    def greeted():
        status, entry = _get(url + "api/agents/bob/mind")
        return status == 200 and entry

    bob = wait_until(lambda: (e := greeted()) and any(
        b["text"] == "greeted_by(alice)" for b in e["state"]["mind"]["beliefs"]) and e,
        "bob's belief greeted_by(alice)", timeout=60, period=0.3)
    beliefs = {b["text"]: b for b in bob["state"]["mind"]["beliefs"]}
    assert beliefs["hello(1)"]["sources"] == ["alice"]
    assert beliefs["hello(1)"]["group"] == "hello/1"
    assert [m["content"] for m in bob["state"]["messages_in"]] == ["hello(1)"]
    assert bob["state"]["messages_in"][0]["sender"] == "alice"

    # alice's states come on a topic of their own: the one after her send may not be in yet
    alice = wait_until(lambda: (r := _get(url + "api/agents/alice/mind"))[0] == 200 and any(
        m["receiver"] == "bob" and m["content"] == "hello(1)"
        for m in r[1]["state"]["messages_out"]) and r[1],
        "alice's state with her message to bob", timeout=60, period=0.3)
    state = alice["state"]
    # move(1) has no decomposer (and no ack timeout): it stays pending, with its age
    assert [a["text"] for a in state["actions"]] == ["move(1)"]
    assert 0 <= state["actions"][0]["sent_at"] <= alice["now"]
    waiting = [i for i in state["mind"]["intentions"] if i["suspended"] == "action 1"]
    assert len(waiting) == 1
    means = waiting[0]["means"][0]
    assert means["trigger"].startswith("+!act")
    assert [(s["text"], s["step"]) for s in means["body"]] == [
        (".print(moving)", "done"), ("move(1)", "current"), (".print(moved)", "todo")]
    assert means["where"] == "alice.asl:7"
    counters = [b for b in state["mind"]["beliefs"] if b["group"] == "count/1"]
    assert len(counters) == 1 and counters[0]["sources"] == ["self"]


def test_history_is_bounded_and_steps_back(graph):
    url = graph[0]
    latest = wait_until(lambda: (
        (r := _get(url + "api/agents/alice/mind"))[0] == 200 and r[1]["index"] >= 7 and r[1]),
        "alice's history to pass 7 states", timeout=60, period=0.3)
    assert latest["last"] - latest["first"] == 4          # _history:=5
    older = latest["index"] - 2
    status, entry = _get(url + f"api/agents/alice/mind?index={older}")
    assert status == 200 and entry["index"] == older
    count = [b["text"] for b in entry["state"]["mind"]["beliefs"] if b["group"] == "count/1"]
    newest = [b["text"] for b in latest["state"]["mind"]["beliefs"] if b["group"] == "count/1"]
    assert count != newest                                  # an older state, not the newest
    status, body = _get(url + f"api/agents/alice/mind?index={latest['first'] - 1}")
    assert status == 404 and "not in the history" in body["error"]


def test_changes_are_pushed_as_server_sent_events(graph):
    url = graph[0]
    with urllib.request.urlopen(url + "api/events", timeout=20) as stream:
        assert stream.headers["Content-Type"].startswith("text/event-stream")
        events: list[str] = []
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline and not {"hello", "mind"} <= set(events):
            line = stream.readline().decode()
            if line.startswith("event: "):
                events.append(line[7:].strip())
            elif line.startswith("data: ") and events[-1] == "mind":
                assert json.loads(line[6:])["agent"] in ("alice", "bob")
    assert events[0] == "hello" and "mind" in events, events


def test_bad_requests_get_4xx_and_the_server_goes_on(graph):
    url = graph[0]
    for path, status in [
        ("api/agents/nobody/mind", 404),
        ("api/agents/alice/mind?index=-1", 400),
        ("api/agents/alice/mind?index=abc", 400),
        ("api/agents/alice/mind?index=99999999999999999999999", 400),
        ("api/agents/alice/mind?index=123456789", 404),
        ("api/agents/alice/mind?colour=red", 400),
        ("api/agents/%00bad/mind", 400),
        ("api/camera/nobody.jpg", 404),
        ("api/camera/..%2Fx.jpg", 400),
        ("static/../inspector/main.py", 404),
        ("static/%2e%2e/main.py", 404),
        ("static/nothing.js", 404),
        ("no/such/page", 404),
    ]:
        got, body = _get(url + path)
        assert got == status, (path, got, body)
    request = urllib.request.Request(url + "api/agents", data=b"x", method="POST")
    with pytest.raises(urllib.error.HTTPError) as err:
        urllib.request.urlopen(request, timeout=10)
    assert err.value.code == 405
    host, port = url.split("//")[1].rstrip("/").split(":")
    for raw in (b"NOT HTTP AT ALL\r\n\r\n", b"GET / HTTP/1.1\r\nHost: x\r\nContent-Length: -5\r\n\r\n",
                b"GET /" + b"a" * 20000 + b" HTTP/1.1\r\nHost: x\r\n\r\n"):
        with socket.create_connection((host, int(port)), timeout=10) as sock:
            sock.sendall(raw)
            reply = sock.recv(200)
        assert reply.startswith(b"HTTP/1.") and reply.split()[1][:1] == b"4", (raw[:30], reply)
    status, body = _get(url + "api/agents")
    assert status == 200 and "alice" in {a["name"] for a in body["agents"]}
    status, page = _get(url)
    assert status == 200 and "<title>rason mind inspector</title>" in page


def test_inspector_listens_on_loopback_only_by_default(graph):
    url = graph[0]
    port = int(url.rstrip("/").rsplit(":", 1)[1])
    listening = []
    for line in Path("/proc/net/tcp").read_text().splitlines()[1:]:
        local, state = line.split()[1], line.split()[3]
        address, port_hex = local.split(":")
        if int(port_hex, 16) == port and state == "0A":         # LISTEN
            listening.append(address)
    assert listening == ["0100007F"], listening                 # 127.0.0.1 only


def test_bad_parameters_and_a_taken_port_stop_the_inspector_with_a_clear_error(ros):
    for params, text in (({"port": "abc"}, "~port: expected a number"),
                         ({"port": 70000}, "~port: must be at most 65535"),
                         ({"history": 0}, "~history: must be at least 1")):
        inspector = ros.rosrun("rason", "mind_inspector", params=params,
                               name=f"bad_inspector_{len(ros.processes)}")
        assert inspector.wait(60) == 2
        assert text in inspector.output(), inspector.output()
    with socket.create_server(("127.0.0.1", 0)) as taken:
        port = taken.getsockname()[1]
        inspector = ros.rosrun("rason", "mind_inspector", params={"port": port},
                               name="taken_port_inspector")
        assert inspector.wait(60) == 1
        assert f"cannot listen on 127.0.0.1:{port}" in inspector.output()


def test_an_agent_back_after_lapsing_before_its_first_state_gets_its_topic(graph, ros_session):
    # Under load an agent may miss its beats before its first mind state: the inspector forgets
    # it (nothing to show), and must find its (already subscribed) topic again when it is back.
    url = graph[0]
    ros_session.init_rospy()
    beats = rospy.Publisher(MESSAGES_TOPIC, AgentMessage, queue_size=10)
    topic = "/insp_c/jason/carol/mind_state"
    silent = rospy.Publisher(topic, String, queue_size=1)     # advertised, never published on

    def carol() -> dict:
        beats.publish(AgentMessage(sender="carol", performative=PRESENCE))
        return _agents(url).get("carol", {})

    try:
        wait_until(lambda: carol().get("topic") == topic, "carol with her topic", timeout=60,
                   period=0.3)
        wait_until(lambda: "carol" not in _agents(url),
                   "carol, silent with no state, to be forgotten", timeout=30, period=0.3)
        wait_until(lambda: carol().get("topic") == topic, "carol back with her topic",
                   timeout=30, period=0.3)
    finally:
        beats.publish(AgentMessage(sender="carol", performative=PRESENCE, content=GOODBYE))
        beats.unregister()
        silent.unregister()


def test_an_agent_that_stops_leaves_the_page(graph):
    url, _inspector, _alice, bob = graph
    bob.stop()                          # SIGINT: the node says goodbye
    wait_until(lambda: "bob" not in _agents(url), "bob to leave", timeout=30, period=0.3)
    assert "alice" in _agents(url)
    status, body = _get(url + "api/agents/bob/mind")   # its history is still there
    assert status == 200 and body["present"] is False
