"""RosAgArch: the agent architecture that plugs a rason.asl agent into ROS (thesis 5.2).

The agent's environment is ROS: actions go out as ``jason_msgs/Action`` and come back as
``action_feedback`` Events; percepts come from the node's perception table; messages to other
agents travel on the global ``/jason/messages`` topic. Time is ROS time, so ``/clock`` works.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import TYPE_CHECKING

import rospy

from rason.asl import AgentArch, Clock, Message, UnknownReceiver
from rason.ros.feedback import Feedback
from rason.ros.perceptions import PerceptionFilter, PerceptionTable, parse_percept

if TYPE_CHECKING:
    from rason.asl import Agent
    from rason.ros.node import RasonNode


class RosClock(Clock):
    """ROS time (``rospy.get_time``): wall time, or the simulator's ``/clock`` with use_sim_time."""

    def now(self) -> float:
        return rospy.get_time()

    def now_ns(self) -> int:
        return rospy.get_rostime().to_nsec()

    def wait(self, event: threading.Event, deadline: float | None) -> None:
        if deadline is None:
            event.wait()
            return
        # Simulated time may run faster or slower than real time: re-check it often.
        while not event.is_set():
            remaining = deadline - self.now()
            if remaining <= 0:
                return
            event.wait(min(remaining, 0.02))


@dataclass
class PendingAction:
    """An action published and not yet answered."""

    action_id: int
    text: str
    sent_at: float
    accepted_at: float | None = None


class RosAgArch(AgentArch):
    """Architecture of one agent hosted by a :class:`RasonNode`."""

    def __init__(self, node: RasonNode, name: str,
                 perception_filter: PerceptionFilter | None = None):
        super().__init__(RosClock())
        self.node = node
        self.name = name
        self.agent: Agent | None = None
        self.perceptions: PerceptionTable = PerceptionTable(
            parse=parse_percept, warn=lambda text: rospy.logwarn("[%s] %s", name, text),
            mode=node.perception_mode, filter=perception_filter or PerceptionFilter(),
            now=rospy.get_time)
        self.pending: dict[int, PendingAction] = {}
        self._lock = threading.Lock()

    # -- AgentArch --------------------------------------------------------------------------------
    def perceive(self):
        return self.perceptions.percepts()

    def act(self, agent: Agent, action, action_id: int) -> None:
        with self._lock:
            self.pending[action_id] = PendingAction(action_id, str(action), self.clock.now())
        self.node.publish_action(self.name, action_id, action)

    def send(self, agent: Agent, message: Message) -> None:
        if self.node.deliver_local(message):
            return
        if not self.node.directory.knows(message.receiver, self.clock.now()):
            raise UnknownReceiver(f"no agent named '{message.receiver}' is known on the network "
                               f"(known: {', '.join(self.agent_names())})")
        self.node.publish_message(message)

    def broadcast(self, agent: Agent, message: Message) -> None:
        message.receiver = ""
        self.node.deliver_local(message)
        self.node.publish_message(message)

    def agent_names(self) -> list[str]:
        return self.node.directory.names(self.clock.now())

    def console(self, agent_name: str, text: str) -> None:
        self.node.console(agent_name, text)

    # -- from the node -------------------------------------------------------------------------------
    def on_perception(self, source: str, perceptions: list[str]) -> None:
        if self.perceptions.update(source, perceptions) and self.agent is not None:
            self.agent.wake()

    def on_accepted(self, action_id: int) -> None:
        with self._lock:
            pending = self.pending.get(action_id)
            if pending is not None and pending.accepted_at is None:
                pending.accepted_at = self.clock.now()

    def on_feedback(self, feedback: Feedback) -> None:
        with self._lock:
            pending = self.pending.pop(feedback.action_id, None)
        if pending is None or self.agent is None:
            return  # not ours, or already failed by a timeout
        if feedback.ok:
            self.agent.action_feedback(feedback.action_id, True)
        else:
            self.agent.action_feedback(feedback.action_id, False, feedback.result,
                                       feedback.message or f"{pending.text} failed: {feedback.result}")

    def check_timeouts(self, now: float, ack_timeout: float, action_timeout: float) -> None:
        """Fail actions no decomposer acknowledged, and accepted ones that never finished."""
        failed: list[tuple[PendingAction, str, str]] = []
        with self._lock:
            for pending in list(self.pending.values()):
                if pending.accepted_at is None and ack_timeout > 0 \
                        and now - pending.sent_at > ack_timeout:
                    failed.append((pending, "no_decomposer",
                                   f"no decomposer acknowledged {pending.text} within "
                                   f"{ack_timeout:g} s"))
                elif action_timeout > 0 and now - (pending.accepted_at or pending.sent_at) \
                        > action_timeout:
                    failed.append((pending, "action_timeout",
                                   f"{pending.text} did not finish within {action_timeout:g} s"))
            for pending, _, _ in failed:
                del self.pending[pending.action_id]
        for pending, reason, text in failed:
            rospy.logwarn("[%s] %s", self.name, text)
            if self.agent is not None:
                self.agent.action_feedback(pending.action_id, False, reason, text)

    def pending_texts(self) -> list[str]:
        with self._lock:
            return [f"{p.action_id}: {p.text}" + ("" if p.accepted_at is not None
                                                   else " (not yet accepted)")
                    for p in self.pending.values()]
