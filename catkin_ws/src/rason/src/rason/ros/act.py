"""``rosrun rason act AGENT 'ACTION(ARGS)'``: perform one action as an agent would.

Publishes a ``jason_msgs/Action`` on ``jason/action`` (latched, so ``rostopic echo`` sees it),
waits for the decomposer's ``action_feedback`` Event on ``jason/event`` and prints it. Exit
status 0 when the feedback is ``OK``, 1 for any other result (printed), 2 when none came.
As an agent does, it gives up early when no node subscribes to ``jason/action`` (within
:data:`GRAPH_WAIT` s of wall time: a question to the master, not to the simulation) and when no
decomposer acknowledges the action within ``--ack-timeout`` (the agents' ``~ack_timeout``: no
decomposer there handles the action); each case is named in the message. Giving up (those,
the timeout, or Ctrl-C) cancels the action on ``jason/cancel``, as an agent does, once: the
action is sent once the cancel's connections to the nodes subscribed to ``jason/cancel`` are
up (at most :data:`CONNECT_WAIT` s), so each of them hears it.
Handy to drive a decomposer by hand, and used by the tests of the harness.
"""

from __future__ import annotations

import argparse
import random
import sys
import threading
import time

import rosgraph
import rospy
from jason_msgs.msg import Action, ActionCancel, Event

from rason.ros.feedback import parse_accepted, parse_feedback, split_action
from rason.ros.node import AgentNodeParams
from rosnode_kit.polling import poll
from rosnode_kit.signals import init_node

#: wall-clock seconds a decomposer starting at the same time has to subscribe to jason/action
GRAPH_WAIT = 2.0
#: wall-clock seconds for the connections to a subscribed decomposer (the action to it, its
#: events to us) and of the cancel to its subscribers before the action is sent anyway
CONNECT_WAIT = 10.0


def subscribers(topic: str) -> list[str]:
    """The nodes subscribed to ``topic`` (a resolved name), as the master knows them."""
    _, subscribed, _ = rosgraph.Master(rospy.get_name()).getSystemState()
    return next((nodes for name, nodes in subscribed if name == topic), [])


def wait_for_subscribers(topic: str, wait: float) -> list[str]:
    """The subscribers of ``topic``, waiting up to ``wait`` wall-clock seconds for the first."""
    return poll(lambda: subscribers(topic), wait, 0.1, stop=rospy.is_shutdown)


def wait_connected(publisher: rospy.Publisher, subscriber: rospy.Subscriber,
                   cancel: rospy.Publisher, wait: float) -> bool:
    """Whether ``publisher`` and ``subscriber`` have a connection and ``cancel`` one to each
    node the master lists as a subscriber of its topic (a cancel is sent once: every node that
    subscribed before now hears it), waiting up to ``wait`` wall-clock seconds."""
    def ready() -> bool:
        return bool(publisher.get_num_connections() and subscriber.get_num_connections()
                    and cancel.get_num_connections() >= len(subscribers(cancel.resolved_name)))
    return poll(ready, wait, 0.02, stop=rospy.is_shutdown)


def main(argv: list[str] | None = None) -> int:
    args_in = rospy.myargv(sys.argv if argv is None else argv)[1:]
    parser = argparse.ArgumentParser(prog="rosrun rason act", description=__doc__.split("\n")[0])
    parser.add_argument("agent", help="agent name put in the Action's agent field")
    parser.add_argument("action", help="the action as Jason text, e.g. 'move(1)' or turn(90)")
    parser.add_argument("--timeout", type=float, default=30.0,
                        help="seconds (ROS time) to wait for the feedback; 0 = do not wait")
    parser.add_argument("--ack-timeout", type=float, default=AgentNodeParams().ack_timeout,
                        help="seconds (ROS time) a decomposer has to acknowledge the action "
                             "(action_accepted), as the agents' ~ack_timeout; 0 = do not "
                             "require it (a decomposer written to the thesis alone)")
    parser.add_argument("--id", type=int, default=None, help="action_id (default: random)")
    args = parser.parse_args(args_in)
    try:
        name, parameters = split_action(args.action)
    except ValueError as err:
        parser.error(str(err))

    init_node("act", anonymous=True)   # Ctrl-C works during its start too
    action_id = args.id if args.id is not None else random.randrange(1, 2**31 - 1)
    done = threading.Event()
    accepted = threading.Event()
    result: list[str] = []

    def on_event(msg: Event) -> None:
        if msg.agent != args.agent:
            return
        if parse_accepted(msg) == action_id:
            accepted.set()
        feedback = parse_feedback(msg)
        if feedback and feedback.action_id == action_id:
            result[:] = [feedback.result, feedback.message]
            accepted.set()
            done.set()

    events = rospy.Subscriber("jason/event", Event, on_event, queue_size=50)
    publisher = rospy.Publisher("jason/action", Action, queue_size=10, latch=True)
    cancel = rospy.Publisher("jason/cancel", ActionCancel, queue_size=10)

    def give_up(reason: str) -> None:
        if args.timeout > 0 and not done.is_set():
            cancel.publish(ActionCancel(agent=args.agent, action_id=action_id, reason=reason))
            done.set()
            time.sleep(0.2)             # let the cancel leave before the node goes

    def send() -> None:
        publisher.publish(Action(agent=args.agent, action_id=action_id, action=name,
                                 parameters=parameters))
        print(f"sent {args.action} as {args.agent} (action_id {action_id})", flush=True)

    rospy.on_shutdown(lambda: give_up("act interrupted"))
    if args.timeout <= 0:
        send()
        rospy.sleep(0.5)
        return 0
    topic = publisher.resolved_name
    if wait_for_subscribers(topic, GRAPH_WAIT):
        # the decomposer answers once, unlatched, and its ack time starts at the sending; our
        # cancel goes once too: send once those connections are up (under load: seconds)
        wait_connected(publisher, events, cancel, CONNECT_WAIT)
        send()
    else:
        give_up(f"act: nothing subscribes to {topic}")
        print(f"no decomposer: nothing subscribes to {topic} (namespace "
              f"{rospy.get_namespace()}); start one there, e.g. rosrun rason motion_decomposer "
              f"__ns:={rospy.get_namespace().rstrip('/') or '/'}", file=sys.stderr)
        return 2
    start = rospy.Time.now()
    deadline = start + rospy.Duration(args.timeout)
    ack_deadline = start + rospy.Duration(args.ack_timeout)
    while not done.is_set() and not rospy.is_shutdown() and rospy.Time.now() < deadline:
        if args.ack_timeout > 0 and not accepted.is_set() and rospy.Time.now() >= ack_deadline:
            give_up(f"act: not acknowledged within {args.ack_timeout:g} s")
            print(f"no decomposer acknowledged {name} within {args.ack_timeout:g} s: the nodes "
                  f"subscribed to {topic} ({', '.join(subscribers(topic))}) do not handle it "
                  f"(or do not acknowledge actions: then use --ack-timeout 0); action cancelled",
                  file=sys.stderr)
            return 2
        done.wait(0.05)
    events.unregister()
    if not result:
        give_up(f"act: no feedback within {args.timeout:g} s")
        print(f"no feedback within {args.timeout} s: action cancelled", file=sys.stderr)
        return 2
    print(f"feedback: {result[0]}" + (f" ({result[1]})" if result[1] else ""), flush=True)
    return 0 if result[0] == "OK" else 1
