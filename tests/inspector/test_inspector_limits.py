"""The mind inspector stays small and private (#37 item 3), against a real inspector node.

This test process plays the graph: presence beats under a flood of names (each then gone),
an agent whose mind state is large, and HTTP requests naming other hosts (DNS rebinding).
"""

from __future__ import annotations

import http.client
import json
import socket
import threading
import time
from collections.abc import Iterator

import pytest
import rospy
from jason_msgs.msg import AgentMessage
from polling import wait_until
from std_msgs.msg import String

from rason.inspector.web import interface_addresses
from rason.process.harness import Process, RosHarness
from rason.ros.presence import GOODBYE, PRESENCE

pytestmark = pytest.mark.ros

STATE_BYTES = 60_000
HISTORY_BYTES = 200_000


def _request(url: str, path: str, host: str | None = None) -> tuple[int, dict]:
    address = url.split("//")[1].rstrip("/")
    name, port = address.rsplit(":", 1)
    conn = http.client.HTTPConnection(name, int(port), timeout=20)
    try:
        conn.putrequest("GET", path, skip_host=True)
        conn.putheader("Host", host if host is not None else address)
        conn.endheaders()
        reply = conn.getresponse()
        return reply.status, json.loads(reply.read() or b"null")
    finally:
        conn.close()


def _start(ros: RosHarness, name: str, **params: object) -> tuple[Process, str]:
    inspector = ros.rosrun("rason", "mind_inspector", name=name, params={"port": 0, **params})
    url = inspector.wait_for_line(r"mind inspector: (http://127\.0\.0\.1:\d+/)", 120).group(1)
    return inspector, url


class Beats:
    """Presence beats of one agent every 0.3 s, from a thread of this process."""

    def __init__(self, pub: rospy.Publisher, name: str) -> None:
        self.pub, self.name = pub, name
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self) -> None:
        while not self.stop.wait(0.3):
            self.pub.publish(AgentMessage(sender=self.name, performative=PRESENCE))

    def close(self) -> None:
        self.stop.set()
        self.thread.join(5)


@pytest.fixture
def graph(ros: RosHarness) -> Iterator[tuple[rospy.Publisher, Process, str]]:
    ros.init_rospy()
    inspector, url = _start(ros, "limits_inspector", history_bytes=HISTORY_BYTES, max_agents=200)
    pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=1000)
    ros.wait_for_subscriber("/jason/messages")
    try:
        yield pub, inspector, url
    finally:
        pub.unregister()


def test_a_flood_of_names_is_pruned_and_bounded(graph):
    pub, inspector, url = graph
    beats = Beats(pub, "steady")
    try:
        wait_until(lambda: "steady" in {
            a["name"] for a in _request(url, "/api/agents")[1]["agents"]}, "steady listed",
            timeout=60, period=0.3)
        for k in range(3000):             # new names, each saying goodbye
            pub.publish(AgentMessage(sender=f"flood_{k}", performative=PRESENCE))
            pub.publish(AgentMessage(sender=f"flood_{k}", performative=PRESENCE,
                                     content=GOODBYE))
            if k % 100 == 0:
                time.sleep(0.01)          # the flood's pace
        pub.publish(AgentMessage(sender="n" * 1_000_000, performative=PRESENCE))   # not kept
        for k in range(1000):             # new names that go silent (presence timeout)
            pub.publish(AgentMessage(sender=f"silent_{k}", performative=PRESENCE))
            if k % 100 == 0:
                time.sleep(0.01)          # the flood's pace
        seen = wait_until(lambda: (
            names := {a["name"] for a in _request(url, "/api/agents")[1]["agents"]})
            and any(n.startswith("silent_") for n in names) and names,
            "the silent flood to be listed", timeout=60, period=0.3)
        assert len(seen) <= 200                      # ~max_agents
        wait_until(lambda: {
            a["name"] for a in _request(url, "/api/agents")[1]["agents"]} == {"steady"},
            "the silent names to expire", timeout=30, period=0.3)
        status, body = _request(url, "/api/agents/flood_5/mind")
        assert status == 404 and "no agent named" in body["error"]      # pruned, not kept
        assert any("~max_agents" in line for line in inspector.lines())
        assert inspector.alive()
    finally:
        beats.close()


def test_mind_history_is_bounded_in_bytes(graph):
    pub, inspector, url = graph
    mind = rospy.Publisher("/lim/jason/big/mind_state", String, queue_size=20, latch=True)
    beats = Beats(pub, "big")

    def publish_state(k: int) -> None:
        mind.publish(String(json.dumps({"agent": "big", "namespace": "/lim/", "mind": {
            "beliefs": [{"text": f'big({k},"{"x" * STATE_BYTES}")'}]}})))

    def state_kept(k: int) -> dict:
        return wait_until(lambda: (r := _request(url, "/api/agents/big/mind"))[0] == 200
                          and r[1]["index"] == k and r[1], f"state {k}", timeout=60, period=0.05)
    try:
        wait_until(lambda: any(
            a["name"] == "big" and a["topic"] for a in _request(url, "/api/agents")[1]["agents"]),
            "big's mind_state topic found", timeout=60, period=0.3)
        for k in range(12):               # each state kept before the next is sent
            publish_state(k)
            latest = state_kept(k)
        assert latest["state"]["mind"]["beliefs"][0]["text"].startswith("big(11,")
        kept = latest["last"] - latest["first"] + 1
        assert kept == HISTORY_BYTES // (STATE_BYTES + 100), latest["first"]    # 3 of 12
        status, body = _request(url, f"/api/agents/big/mind?index={latest['first'] - 1}")
        assert status == 404 and "not in the history" in body["error"]
        # a state larger than half the byte bound is refused (the inspector says so); the
        # history stays as it was: the next state sent after it is number 12
        mind.publish(String(json.dumps({"agent": "big", "mind": {"b": "y" * HISTORY_BYTES}})))
        wait_until(lambda: any("mind_state of big ignored" in line and "more than half" in line
                               for line in inspector.lines()),
                   "the inspector's warning of the oversized state", timeout=60, watch=[inspector])
        publish_state(12)
        latest = state_kept(12)
        assert latest["state"]["mind"]["beliefs"][0]["text"].startswith("big(12,")
    finally:
        beats.close()
        mind.unregister()


def test_only_requests_naming_the_inspectors_address_are_answered(ros):
    _inspector, url = _start(ros, "host_inspector", allowed_hosts="[inspector.lan]")
    port = url.rstrip("/").rsplit(":", 1)[1]
    for host in (f"127.0.0.1:{port}", "127.0.0.1", f"localhost:{port}", "LOCALHOST.",
                 "inspector.lan", f"Inspector.LAN:{port}"):
        status, body = _request(url, "/api/agents", host)
        assert status == 200 and "agents" in body, (host, status, body)
    for host in (f"evil.example:{port}", "127.0.0.1.evil.example", "", f"10.0.0.1:{port}",
                 "inspector.lan.evil.example"):
        for path in ("/", "/api/agents", "/api/events", "/static/app.js"):
            status, body = _request(url, path, host)
            assert status == 403, (host, path, status)
        assert "not this inspector's address" in body["error"]


def test_on_every_interface_the_machines_own_addresses_are_answered(ros):
    _inspector, url = _start(ros, "all_interfaces_inspector", host="0.0.0.0")
    port = url.rstrip("/").rsplit(":", 1)[1]
    own = [*sorted(a for a in interface_addresses() if ":" not in a), socket.gethostname()]
    for host in own:
        status, body = _request(url, "/api/agents", f"{host}:{port}")
        assert status == 200 and "agents" in body, (host, status, body)
    assert _request(url, "/api/agents", f"evil.example:{port}")[0] == 403
