"""Which agents are around (thesis 5.6 future work: no fixed addresses), without rospy.

Every agent announces itself periodically on the global message topic. A :class:`Directory`
remembers when each name was last heard and forgets it after a timeout, so ``.all_names`` and
``.broadcast`` reach the agents seen recently, a new agent is found without restarting anyone,
and one that stops (or whose link breaks) disappears.
"""

from __future__ import annotations

import threading
from collections.abc import Iterable

#: The global topic of agent messages and presence announcements (jason_msgs/AgentMessage).
MESSAGES_TOPIC = "/jason/messages"
#: The relative topic (``<robot ns>/jason/presence``) where an agent node repeats its agents'
#: presence beats and goodbyes, every period, for the decomposers of its own robot: they supervise
#: the agents that act on them without hearing every message of a fleet on MESSAGES_TOPIC.
PRESENCE_TOPIC = "jason/presence"
#: The global latched topic where each node publishes its agents' directory-facilitator
#: registrations (jason_msgs/AgentMessage, performative DF_PERFORMATIVE).
DIRECTORY_TOPIC = "/jason/directory"
DF_PERFORMATIVE = "df"
#: Performative of a presence announcement; its content is "" (still here), HELLO (a newcomer:
#: everyone announce yourselves) or GOODBYE (leaving now).
PRESENCE = "presence"
HELLO = "hello"
GOODBYE = "goodbye"


class Directory:
    """Agent names with the time (seconds, any clock) each was last heard from."""

    def __init__(self, timeout: float, local: Iterable[str] = ()):
        self.timeout = timeout
        self._local = set(local)
        self._last_seen: dict[str, float] = {}
        self._lock = threading.Lock()

    def add_local(self, name: str) -> None:
        """An agent hosted in this process: always known."""
        with self._lock:
            self._local.add(name)

    def remove_local(self, name: str) -> None:
        """An agent of this process left it."""
        with self._lock:
            self._local.discard(name)

    def heard(self, name: str, now: float) -> bool:
        """Record that `name` was heard at `now`; True if it was not known before."""
        with self._lock:
            new = name not in self._local and not self._alive(name, now)
            self._last_seen[name] = max(now, self._last_seen.get(name, now))
            return new

    def forget(self, name: str) -> None:
        """Drop `name` at once (it said goodbye)."""
        with self._lock:
            self._last_seen.pop(name, None)

    def _alive(self, name: str, now: float) -> bool:
        seen = self._last_seen.get(name)
        # A clock that jumped backwards (sim restarted) keeps the entry until heard again.
        return seen is not None and (now - seen <= self.timeout or now < seen)

    def knows(self, name: str, now: float) -> bool:
        with self._lock:
            return name in self._local or self._alive(name, now)

    def names(self, now: float) -> list[str]:
        """Local agents plus the remote ones heard within the timeout, sorted."""
        with self._lock:
            remote = {n for n in self._last_seen if self._alive(n, now)}
            return sorted(self._local | remote)

    def expire(self, now: float) -> list[str]:
        """Forget the remote agents not heard within the timeout; return their names."""
        with self._lock:
            gone = [n for n in self._last_seen if not self._alive(n, now)]
            for name in gone:
                del self._last_seen[name]
            return gone
