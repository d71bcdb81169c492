"""The agent's mind as a latched topic, for the mind inspector (``jason/NAME/mind_state``).

Each hosted agent gets a :class:`MindStatePublisher`. A timer of the node (ROS time, at most
``~mind_state_rate`` Hz) asks every publisher to :meth:`~MindStatePublisher.tick`: it takes a
snapshot of the mind (:class:`rason.asl.inspection.MindReader`), adds the pending actions with the ROS
time they were sent and the last messages in and out, and publishes it as JSON in a
``std_msgs/String`` only when something changed. The topic is latched, so an inspector started
later gets the current state at once.

Snapshots are taken only while the topic has a subscriber (an inspector, ``rostopic echo``):
the first one gets the current mind at the next tick, within ``1/~mind_state_rate`` s.

The timer never waits for a busy agent: when a reasoning cycle holds the agent, the snapshot is
left to the agent's own thread, which takes it at the start of its next cycle
(:meth:`~MindStatePublisher.at_cycle`, scheduled through ``RosAgArch.at_next_cycle``). So the
reasoning thread and the timer never queue on the agent's lock, and a cycle with no snapshot
due pays one attribute test.

The JSON document (``MIND_STATE_VERSION``): ``agent``, ``node``, ``namespace``, ``stamp`` (ROS
seconds of the snapshot), ``seq`` (counts publications), ``mind`` (beliefs, rules, events,
desires, intentions: see :mod:`rason.asl.inspection`), ``actions`` (id, text, sent_at,
accepted_at), ``messages_in`` and ``messages_out`` (time, sender, receiver, performative,
content), oldest first.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import rospy
from std_msgs.msg import String

from rason.asl import Message, term_str
from rason.asl.inspection import MindReader, to_json
from rosnode_kit.guard import WARNINGS

if TYPE_CHECKING:
    from rason.asl import Agent
    from rason.asl.inspection import MindState
    from rason.ros.arch import PendingAction

MIND_STATE_VERSION = 1
MESSAGES_KEPT = 10


def mind_state_topic(base_ns: str, agent: str) -> str:
    """The topic of `agent`'s mind under the robot namespace `base_ns` ("/", "/helper/")."""
    return f"{base_ns.rstrip('/')}/jason/{agent}/mind_state"


@dataclass
class MessageView:
    """A message an agent received or sent, with the ROS time it passed the node."""

    time: float
    sender: str
    receiver: str
    performative: str
    content: str

    @classmethod
    def of(cls, noted: NotedMessage) -> MessageView:
        message = noted.message
        return cls(time=noted.time, sender=message.sender, receiver=message.receiver or "",
                   performative=message.performative, content=term_str(message.content))


@dataclass(frozen=True)
class NotedMessage:
    """A message as noted when it passed the node: written out only for a snapshot."""

    time: float
    message: Message


class LatchedTopic:
    """A latched std_msgs/String topic: publish a text; does anyone subscribe?
    (``on_subscribe`` is called when a subscriber connects.)"""

    def __init__(self, topic: str, on_subscribe: Callable[[], None] | None = None) -> None:
        listener = _SubscribeListener(on_subscribe) if on_subscribe is not None else None
        self._publisher = rospy.Publisher(topic, String, queue_size=1, latch=True,
                                          subscriber_listener=listener)

    def publish(self, text: str) -> None:
        self._publisher.publish(String(data=text))

    def listened(self) -> bool:
        return self._publisher.get_num_connections() > 0


class _SubscribeListener(rospy.SubscribeListener):
    """Calls a function when a subscriber connects."""

    def __init__(self, on_subscribe: Callable[[], None]) -> None:
        super().__init__()
        self._on_subscribe = on_subscribe

    def peer_subscribe(self, topic_name: str, topic_publish: Any, peer_publish: Any) -> None:
        self._on_subscribe()


class MindStatePublisher:
    """Publishes one agent's mind on change (see the module's docstring).

    `pending_actions` gives the agent's actions waiting for feedback (RosAgArch.pending_actions),
    `publish` sends the JSON text (LatchedTopic.publish), `node` names the hosting node,
    `schedule` has a function called by the agent's thread at its next cycle (sets
    ``RosAgArch.at_next_cycle``), `warn` reports a publication that failed (default: the node's
    rate-limited warnings), `listened` tells whether anyone subscribes (LatchedTopic.listened;
    default: always): nobody listening, no snapshot is taken.
    """

    def __init__(self, agent: Agent, pending_actions: Callable[[], list[PendingAction]],
                 publish: Callable[[str], None], node: str, namespace: str,
                 schedule: Callable[[Callable[[], None]], None] | None = None,
                 warn: Callable[[str], object] | None = None,
                 listened: Callable[[], bool] | None = None) -> None:
        self.agent = agent
        #: takes the snapshots, keeping what the last one formatted
        self.reader = MindReader(agent)
        self.listened = listened or (lambda: True)
        self.schedule = schedule or (lambda fn: None)
        self.warn = warn or (lambda text: WARNINGS.warn("mind_state", text))
        self.pending_actions = pending_actions
        self.publish = publish
        self.node = node
        self.namespace = namespace
        self.messages_in: deque[NotedMessage] = deque(maxlen=MESSAGES_KEPT)
        self.messages_out: deque[NotedMessage] = deque(maxlen=MESSAGES_KEPT)
        self._lock = threading.Lock()
        self._publishing = threading.Lock()
        self._last = ""
        self._due: float | None = None      # ROS time of a tick left to the agent's thread
        self.seq = 0

    def note_message(self, message: Message, outgoing: bool, now: float) -> None:
        """Remember a message the agent received (or sent) at ROS time `now` (cheap: it is
        written out only when a snapshot is taken)."""
        noted = NotedMessage(now, message)
        with self._lock:
            (self.messages_out if outgoing else self.messages_in).append(noted)

    def document(self, mind: MindState) -> dict:
        """The mind as records for :func:`to_json`, without stamp and seq (they always change)."""
        actions = [{"id": p.action_id, "text": p.text, "sent_at": p.sent_at,
                    "accepted_at": p.accepted_at} for p in self.pending_actions()]
        with self._lock:
            noted_in, noted_out = list(self.messages_in), list(self.messages_out)
        messages_in = [MessageView.of(noted) for noted in noted_in]
        messages_out = [MessageView.of(noted) for noted in noted_out]
        return {"version": MIND_STATE_VERSION, "agent": self.agent.name,
                "node": self.node, "namespace": self.namespace, "mind": mind,
                "actions": actions, "messages_in": messages_in, "messages_out": messages_out}

    def tick(self, now: float) -> bool:
        """The timer: publish the mind if it changed; True if published. A busy agent's mind is
        published by its own thread at its next cycle instead (:meth:`at_cycle`). While nobody
        subscribes no snapshot is taken (an agent in a fleet of agents would spend more on its
        snapshots than on its messages); the first subscriber gets one at the next tick."""
        if not self.listened():
            self._last = ""
            return False
        mind = self.reader.snapshot(blocking=False)
        if mind is None:
            self._due = now
            self.schedule(self.at_cycle)
            return False
        return self._publish(mind, now)

    def at_cycle(self) -> None:
        """The agent's thread, at the start of a reasoning cycle: publish if a tick was left."""
        due = self._due
        if due is None:
            return
        self._due = None
        try:
            mind = self.reader.snapshot()
            if mind is not None:
                self._publish(mind, due)
        except Exception as err:  # never into the reasoning cycle: it would drop an intention
            self.warn(f"[{self.agent.name}] mind_state not published: {type(err).__name__}: {err}")

    def _publish(self, mind: MindState, now: float) -> bool:
        body = to_json(self.document(mind))
        with self._publishing:
            if body == self._last:
                return False
            self._last = body
            self.seq += 1
            # stamp and seq go first, outside what is compared
            self.publish(f'{{"stamp":{now!r},"seq":{self.seq},{body[1:]}')
            return True
