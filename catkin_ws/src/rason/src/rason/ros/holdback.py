"""Messages to an agent held until its node listens to us (no rospy here).

Presence is heard one way: node A hears agent ``bob`` once A's subscription reaches bob's node,
but bob hears A only once bob's node has subscribed to A's publisher, a separate connection that
may come later (a node just started, a link just back). A message A sends to bob in between is
lost. :class:`HoldBack` learns which node hosts each agent (from the messages heard from it) and
holds a message for an agent whose node is not yet among our publisher's subscribers, releasing
it, in order, when that node subscribes, or after ``max_hold`` seconds whatever happens (then it
may be lost, as before, and the caller can say so).
"""

from __future__ import annotations

import threading
from collections.abc import Collection
from dataclasses import dataclass
from typing import Generic, TypeVar

M = TypeVar("M")


@dataclass(frozen=True)
class Released(Generic[M]):
    """A held message to publish now; ``late`` when its node had still not subscribed."""

    message: M
    receiver: str
    late: bool


class HoldBack(Generic[M]):
    """Per remote node, the messages waiting for it to subscribe to ours."""

    def __init__(self, max_hold: float) -> None:
        self.max_hold = max_hold
        self._node_of: dict[str, str] = {}                       # agent -> the node hosting it
        self._held: dict[str, list[tuple[float, str, M]]] = {}   # node -> (since, receiver, message)
        self._lock = threading.Lock()

    def heard(self, agent: str, node: str) -> None:
        """A message from ``agent`` came from node ``node`` (called for every message heard:
        the lock is taken only when that is news)."""
        if node and self._node_of.get(agent) != node:
            with self._lock:
                self._node_of[agent] = node

    def submit(self, receiver: str, message: M, now: float,
               subscribers: Collection[str]) -> list[M]:
        """``message`` for ``receiver``: what to publish now, in order (empty: held)."""
        with self._lock:
            node = self._node_of.get(receiver)
            if node is None:
                return [message]           # never heard from it: nothing to wait for
            held = self._held.get(node)
            if node in subscribers:
                if not held:
                    return [message]
                del self._held[node]       # those first, in order
                return [m for _, _, m in held] + [message]
            self._held.setdefault(node, []).append((now, receiver, message))
            return []

    def release(self, now: float, subscribers: Collection[str]) -> list[Released[M]]:
        """The held messages whose node subscribed, or that waited ``max_hold`` seconds."""
        out: list[Released[M]] = []
        with self._lock:
            for node in list(self._held):
                held = self._held[node]
                connected = node in subscribers
                if connected or now - held[0][0] >= self.max_hold or now < held[0][0]:
                    del self._held[node]
                    out.extend(Released(m, receiver, not connected) for _, receiver, m in held)
        return out

    def held(self) -> int:
        """How many messages wait."""
        with self._lock:
            return sum(len(h) for h in self._held.values())
