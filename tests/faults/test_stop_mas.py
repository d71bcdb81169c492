"""Stopping is stopping (#37 item 4): an agent that ends, however it ends, cancels its pending
actions, says goodbye and beats no more, so its decomposer stops the robot.

A real agent node runs ``move(60)`` on the echo decomposer (which holds it: ``~delay`` 60 s) and
then ends: by ``.stopMAS`` (the node exits with status 0, as Jason's platform does), by SIGTERM,
or by ``.kill_agent`` of itself (the node stays up for its other agents). The test hears
jason/cancel, jason/event and jason/presence.
"""

from __future__ import annotations

import signal
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest
import rospy
from agent_nodes import start_agent
from jason_msgs.msg import ActionCancel, AgentMessage, Event
from polling import wait_until

from rason.process.harness import Process, RosHarness
from rason.ros.feedback import CancelReason, parse_accepted, parse_feedback
from rason.ros.presence import GOODBYE, PRESENCE

pytestmark = pytest.mark.ros

MOVER = """
    !go.
    +!go <- !!drive; .wait(4000); .print("ending"); {ending}.
    +!drive <- move(60); .print("moved").
    """


@dataclass
class Heard:
    """jason/cancel, jason/event and jason/presence of one namespace, with wall arrival times."""

    ns: str
    lock: threading.Lock = field(default_factory=threading.Lock)
    cancels: list[ActionCancel] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    beats: list[tuple[float, AgentMessage]] = field(default_factory=list)
    subs: list[rospy.Subscriber] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.subs = [rospy.Subscriber(f"{self.ns}/jason/cancel", ActionCancel, self._add(self.cancels)),
                     rospy.Subscriber(f"{self.ns}/jason/event", Event, self._add(self.events)),
                     rospy.Subscriber(f"{self.ns}/jason/presence", AgentMessage, self._beat)]

    def _add(self, into: list):
        def add(msg) -> None:
            with self.lock:
                into.append(msg)
        return add

    def _beat(self, msg: AgentMessage) -> None:
        if msg.performative == PRESENCE:
            with self.lock:
                self.beats.append((time.monotonic(), msg))

    def accepted(self) -> list[int]:
        with self.lock:
            return [a for a in map(parse_accepted, self.events) if a is not None]

    def results(self) -> list[tuple[int, str]]:
        with self.lock:
            return [(f.action_id, f.result) for f in map(parse_feedback, self.events)
                    if f is not None]

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()


def drive_then_end(ros: RosHarness, tmp_path: Path, ns: str, ending: str,
                   ) -> tuple[Process, Heard, int]:
    """Start the echo decomposer and the agent; wait until move(60) is accepted; let the agent
    end its way (`ending`, its last deed, 4 s after the start); the move's action id."""
    ros.init_rospy()
    heard = Heard(ns)
    ros.rosrun("rason", "echo_decomposer", ns=ns, params={"delay": 60.0})
    ros.wait_for_subscriber(f"{ns}/jason/cancel")
    # the decomposer says "accepted" once, unlatched: our jason/event subscriber must be
    # connected to it before the agent asks (under load it connected after, and missed it)
    wait_until(lambda: heard.subs[1].get_num_connections() > 0,
               "our jason/event subscriber to connect to the decomposer", timeout=20)
    agent = start_agent(ros, tmp_path, "mover", MOVER.format(ending=ending), ns=ns)
    wait_until(lambda: heard.accepted(), "move(60) to be accepted", timeout=20)
    # the cancel and the goodbye come once, unlatched, from the agent's node: our subscribers
    # must be connected to it before it ends (under load presence connected after it ended)
    wait_until(lambda: heard.subs[0].get_num_connections() > 0
               and heard.subs[2].get_num_connections() > 0,
               "our jason/cancel and jason/presence subscribers to connect to the agent",
               timeout=20)
    return agent, heard, heard.accepted()[0]


def assert_stopped(heard: Heard, action_id: int, reason: str) -> None:
    """The move was cancelled with `reason`, answered cancelled, and a goodbye came."""
    wait_until(lambda: (action_id, "cancelled") in heard.results(),
               "the decomposer to answer cancelled", timeout=15)
    with heard.lock:
        cancels = [(c.agent, c.action_id, c.reason) for c in heard.cancels]
    assert ("mover", action_id, reason) in cancels, cancels
    wait_until(lambda: any(m.content == GOODBYE for _, m in heard.beats), "a goodbye", timeout=10)


def assert_goodbye_last(heard: Heard) -> None:
    """The goodbye was the agent's last beat (call it after a sentinel: no beat can follow)."""
    with heard.lock:
        beats = [m.content for _, m in heard.beats if m.sender == "mover"]
    assert beats[-1] == GOODBYE and beats.count(GOODBYE) == 1, beats


def assert_exited_after_goodbye(agent: Process, heard: Heard) -> None:
    """The node exited; the sentinel is our presence subscriber losing its only publisher
    (the node's): every beat the node sent was read before that connection closed."""
    agent.wait(15)
    presence = heard.subs[2]
    wait_until(lambda: presence.get_num_connections() == 0,
               "the exited node's presence connection to close", timeout=15)
    assert_goodbye_last(heard)


def test_stop_mas_cancels_the_move_says_goodbye_and_the_node_exits(ros: RosHarness,
                                                                   tmp_path: Path):
    agent, heard, action_id = drive_then_end(ros, tmp_path, "/stop1", ".stopMAS")
    try:
        assert_stopped(heard, action_id, CancelReason.STOP_MAS)
        assert agent.wait(15) == 0, agent.output()[-2000:]
        assert_exited_after_goodbye(agent, heard)
        assert "mover called .stopMAS: the node stops" in agent.output()
    finally:
        heard.close()


def test_sigterm_cancels_the_move_and_says_goodbye(ros: RosHarness, tmp_path: Path):
    agent, heard, action_id = drive_then_end(ros, tmp_path, "/stop2", ".wait(60000)")
    try:
        agent.signal_group(signal.SIGTERM)
        assert_stopped(heard, action_id, CancelReason.SHUTDOWN)
        assert_exited_after_goodbye(agent, heard)
    finally:
        heard.close()


def test_an_agent_killing_itself_cancels_its_move_and_its_node_stays(ros: RosHarness,
                                                                    tmp_path: Path):
    agent, heard, action_id = drive_then_end(ros, tmp_path, "/stop3",
                                             ".my_name(Me); .kill_agent(Me)")
    try:
        assert_stopped(heard, action_id, CancelReason.DROPPED)
        # The node stays and publishes nothing more on presence, so no sentinel can follow on
        # that topic: a beat is periodic, and its absence takes time to show (ROS time passing
        # for the behaviour under test): more than two presence periods.
        time.sleep(2.5)
        assert_goodbye_last(heard)
        assert agent.alive()          # a node hosts agents: it outlives one of them
    finally:
        heard.close()
