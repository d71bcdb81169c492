"""``rosrun rason echo_decomposer``: a decomposer for tests that answers what it is asked.

Handles the actions named in ``~actions`` (default ``[move]``) on ``jason/action``, acknowledges
each (``action_accepted``), waits ``~delay`` seconds of ROS time, then answers
``action_feedback [RESULT, action_id, message]``. RESULT is the action's last parameter when it
is an atom (``move(1, no_progress)`` fails with ``no_progress``), else ``~result`` (``OK``).
``~ack:=false`` behaves like a decomposer written to the thesis alone (no acknowledgement).
"""

from __future__ import annotations

import re

import rospy
from jason_msgs.msg import Action, Event

from rason.ros.feedback import ACTION_ACCEPTED, ACTION_FEEDBACK

ATOM = re.compile(r"^[a-z][A-Za-z0-9_]*$")


class EchoDecomposer:
    """Answers handled actions with the result they ask for."""

    def __init__(self) -> None:
        # parameters
        self.actions = set(rospy.get_param("~actions", ["move"]))
        self.result = str(rospy.get_param("~result", "OK"))
        self.delay = float(rospy.get_param("~delay", 0.0))
        self.ack = bool(rospy.get_param("~ack", True))
        # topics
        self.events = rospy.Publisher("jason/event", Event, queue_size=100)
        rospy.Subscriber("jason/action", Action, self.on_action, queue_size=100, tcp_nodelay=True)

    def on_action(self, msg: Action) -> None:
        if msg.action not in self.actions:
            return
        if self.ack:
            self.events.publish(Event(agent=msg.agent, event_type=ACTION_ACCEPTED,
                                      parameters=[str(msg.action_id)]))
        last = msg.parameters[-1] if msg.parameters else ""
        result = last if ATOM.match(last) else self.result
        if self.delay > 0:
            rospy.Timer(rospy.Duration(self.delay), lambda _e: self.answer(msg, result),
                        oneshot=True)
        else:
            self.answer(msg, result)

    def answer(self, msg: Action, result: str) -> None:
        self.events.publish(Event(agent=msg.agent, event_type=ACTION_FEEDBACK, parameters=[
            result, str(msg.action_id), f"echo: {msg.action}({', '.join(msg.parameters)})"]))


def main() -> None:
    rospy.init_node("echo_decomposer")
    EchoDecomposer()
    rospy.spin()
