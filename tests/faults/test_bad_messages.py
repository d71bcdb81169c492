"""Every callback survives any message (#14 item 2): the agent node, a decomposer and the
fault injector are sent malformed, empty, huge and non-finite messages on every topic they
subscribe, and still do their job afterwards (real nodes, real roscore)."""

from __future__ import annotations

import math
import threading
from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, start_agent
from geometry_msgs.msg import Twist
from jason_msgs.msg import Action, ActionCancel, AgentMessage, Event, Perception
from nav_msgs.msg import Odometry
from polling import wait_until

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

NAN, INF = math.nan, math.inf
HUGE = "x" * 200_000


def connected(*endpoints: rospy.Publisher | rospy.Subscriber, timeout: float = 10.0) -> None:
    wait_until(lambda: all(e.get_num_connections() for e in endpoints),
               f"connections of {[e.resolved_name for e in endpoints]}", timeout)


def test_agent_node_survives_bad_events_perceptions_and_messages(ros: RosHarness,
                                                                 tmp_path: Path):
    ros.init_rospy()
    ns = "/badmsg1"
    ros.rosrun("rason", "echo_decomposer", ns=ns, params={"actions": ["move"]})
    agent = start_agent(ros, tmp_path, "sturdy", """
        +ok(X)[source(percept)] <- .print("ok ", X); move(X); .print("moved ", X).
        +!hello[source(S)] <- .print("hello from ", S).
        """, ns=ns)
    events = rospy.Publisher(f"{ns}/jason/event", Event, queue_size=100)
    percepts = rospy.Publisher(f"{ns}/jason/perception", Perception, queue_size=100)
    messages = rospy.Publisher("/jason/messages", AgentMessage, queue_size=100)
    connected(events, percepts)
    # /jason/messages is global: any other node's subscriber would count; sturdy's own
    wait_until(lambda: connected_to(messages, f"{ns}/jason/sturdy"),
               "the connection to sturdy's node", timeout=10)
    for params in ([], ["OK"], ["", ""], ["OK", "nan"], ["OK", "99999999999999999999"],
                   [HUGE, "1"], ["1"] * 10_000, ["\x00\xff", "-1"]):
        for kind in ("action_feedback", "action_accepted", "", HUGE):
            events.publish(Event(agent="sturdy", event_type=kind, parameters=params))
    for perception in ([""], ["robot(faulty,"], [HUGE], ["ok(nan)", "ok(Infinity)"],
                       ["p(" * 5000], [f"n({i})" for i in range(20_000)], ["\x00"]):
        percepts.publish(Perception(source="fuzz", perception=perception))
    for content in ("", "(((", HUGE, "hello(", "[1,2|", "\x00", "f(" * 5000):
        for performative in ("tell", "achieve", "askOne", "tellHow", "presence", "", HUGE):
            messages.publish(AgentMessage(sender="fuzzer", receiver="sturdy",
                                          performative=performative, content=content))
    # still perceives, acts through the decomposer, and talks: a good perception and a good
    # message, sent on the same publishers after the bad ones, are the sentinels (handled after
    # them), so no sleep is needed before asking whether the node survived
    percepts.publish(Perception(source="fuzz", perception=["ok(3)"]))
    agent.wait_for_line(r"\[sturdy\] moved 3", timeout=30)
    messages.publish(AgentMessage(sender="friend", receiver="sturdy", performative="achieve",
                                  content="hello", reply_with="m1"))
    agent.wait_for_line(r"\[sturdy\] hello from friend", timeout=15)
    assert agent.alive(), agent.output()[-3000:]
    assert "Traceback" not in agent.output()


def test_decomposer_survives_bad_actions_cancels_odometry(ros: RosHarness):
    ros.init_rospy()
    ns = "/badmsg2"
    node = ros.rosrun("rason", "motion_decomposer", ns=ns)
    ros.wait_for_subscriber(f"{ns}/jason/cancel", watch=[node])
    got: list[Event] = []
    lock = threading.Lock()

    def on_event(msg: Event) -> None:
        with lock:
            got.append(msg)

    sub = rospy.Subscriber(f"{ns}/jason/event", Event, on_event, queue_size=1000)
    actions = rospy.Publisher(f"{ns}/jason/action", Action, queue_size=1000)
    cancels = rospy.Publisher(f"{ns}/jason/cancel", ActionCancel, queue_size=100)
    odom = rospy.Publisher(f"{ns}/odom", Odometry, queue_size=100)
    connected(sub, actions, cancels, odom)
    bad_odom = Odometry()
    bad_odom.pose.pose.position.x = NAN
    bad_odom.pose.pose.orientation.w = INF
    for _ in range(20):
        odom.publish(bad_odom)
    for i, params in enumerate(([], ["1", "2"], [HUGE], ["1"] * 10_000, ["\x00"], ["nan"],
                                ["1e400"], ["0x10"], ["-0"])):
        actions.publish(Action(agent="fuzz", action_id=i, action="move", parameters=params))
    for action_id in (-1, 0, 2**31 - 1, -2**31):
        cancels.publish(ActionCancel(agent=HUGE, action_id=action_id, reason=HUGE))
    def feedback_results() -> list[str]:
        with lock:
            return [e.parameters[0] for e in got if e.event_type == "action_feedback"]

    wait_until(lambda: feedback_results().count("bad_parameters") >= 7,
               "bad_parameters for the malformed actions", timeout=30, watch=[node])
    # a good odometry stream and a good action still work: move(0) ends OK at once. Odometry
    # and actions come on different topics, so the action may be handled before the good pose:
    # until that pose is, move(0) may end otherwise; each try sends both again.
    good = Odometry()
    good.pose.pose.orientation.w = 1.0
    ids = iter(range(100, 200))

    def move_0_ok() -> bool:
        odom.publish(good)
        action_id = next(ids)
        actions.publish(Action(agent="fuzz", action_id=action_id, action="move",
                               parameters=["0"]))

        def feedback() -> list[Event]:
            with lock:
                return [e for e in got if e.event_type == "action_feedback"
                        and e.parameters[1] == str(action_id)]

        done = wait_until(feedback, f"feedback for action {action_id}", timeout=10, watch=[node])
        return done[0].parameters[0] == "OK"

    wait_until(move_0_ok, "move(0) ending OK after a good pose", timeout=30, watch=[node])
    assert "rejected (ValueError: odometry pose is not finite" in node.output()
    sub.unregister()


def test_fault_injector_stops_on_non_finite_commands(ros: RosHarness):
    ros.init_rospy()
    ns = "/badmsg3"
    node = ros.rosrun("kobuki_fault_injector", "fault_injector", ns=ns)
    ros.wait_for_subscriber(f"{ns}/cmd_vel", watch=[node])
    out: list[Twist] = []
    sub = rospy.Subscriber(f"{ns}/mobile_base/commands/velocity", Twist, out.append,
                           queue_size=100)
    cmd = rospy.Publisher(f"{ns}/cmd_vel", Twist, queue_size=100)
    odom = rospy.Publisher(f"{ns}/mobile_base/odom", Odometry, queue_size=100)
    passed: list[Odometry] = []
    odom_out = rospy.Subscriber(f"{ns}/odom", Odometry, passed.append, queue_size=100)
    connected(sub, cmd, odom, odom_out)
    bad = Twist()
    bad.linear.x = NAN
    bad.angular.z = INF
    cmd.publish(bad)
    bad_odom = Odometry()
    bad_odom.pose.pose.position.x = NAN
    odom.publish(bad_odom)
    # the sentinel: the non-finite odometry came out the other side, so it was handled
    wait_until(lambda: passed, f"odometry on {ns}/odom", timeout=10, watch=[node])
    good = Twist()
    good.linear.x = 0.2
    cmd.publish(good)
    wait_until(lambda: len(out) >= 2, "the stop and the good command", timeout=10, watch=[node])
    odom_out.unregister()
    assert [(t.linear.x, t.angular.z) for t in out[:2]] == [(0.0, 0.0), (0.2, 0.0)]
    assert "non-finite velocity command" in node.output()
    sub.unregister()
