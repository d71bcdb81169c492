"""Loud miswiring: warn by name when a needed input stays silent while the robot is evidently up.

A node wired to the wrong name hears nothing and, without this, says nothing either (the fault
injector subscribed to ``mobile_base/odom`` under the stock driver names, where the driver
publishes ``odom``). :class:`InputWatch` notices when an input has been silent for ``after``
seconds while another topic of the same type in the node's namespace has a publisher other than
the node itself, and says which: the input is then miswired, not merely waiting for a robot.

:func:`watch_input` runs one in a ``rospy.Timer`` (ROS time) and logs the warning (again every
``repeat`` seconds while the silence lasts); :class:`InputWatch` alone has no ROS in it.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import rosgraph
import rospy

#: Seconds of silence before the watch looks for evidence that the robot is up.
SILENCE = 3.0
#: Seconds between repeated warnings while the silence lasts.
REPEAT = 30.0


@dataclass(frozen=True)
class Publication:
    """One topic on the master: its name, type and the nodes that publish it."""

    topic: str
    msg_type: str
    publishers: tuple[str, ...]


@dataclass
class InputWatch:
    """The silence of one subscribed ``topic`` (a resolved name) of type ``msg_type``."""

    topic: str
    msg_type: str
    node: str                  # the watching node's name (its own publications are no evidence)
    namespace: str             # evidence is looked for under this namespace
    started: float             # when the watch started (s)
    hint: str = ""             # how to wire it right, appended to the warning
    after: float = SILENCE
    repeat: float = REPEAT
    last_heard: float | None = None
    warned_at: float | None = field(default=None, repr=False)

    def heard(self, now: float) -> None:
        """A message arrived on the input."""
        self.last_heard = now
        self.warned_at = None

    def evidence(self, publications: Iterable[Publication]) -> list[Publication]:
        """Other topics of the input's type in the namespace that someone else publishes."""
        return [pub for pub in publications
                if pub.topic != self.topic and pub.msg_type == self.msg_type
                and pub.topic.startswith(self.namespace)
                and any(node != self.node for node in pub.publishers)]

    @property
    def silent_since(self) -> float:
        return self.last_heard if self.last_heard is not None else self.started

    def due(self, now: float) -> bool:
        """Silent long enough, and not warned about lately: worth asking the master."""
        return (now - self.silent_since >= self.after
                and (self.warned_at is None or now - self.warned_at >= self.repeat))

    def check(self, now: float, publications: Iterable[Publication]) -> str | None:
        """The warning due at ``now``, or None."""
        if not self.due(now):
            return None
        silent_since = self.silent_since
        others = self.evidence(publications)
        if not others:
            return None
        self.warned_at = now
        named = ", ".join(f"{pub.topic} (published by {', '.join(pub.publishers)})"
                          for pub in others)
        text = (f"{self.node}: nothing on {self.topic} ({self.msg_type}) for "
                f"{now - silent_since:.1f} s while {named} flows: is this input wired to the "
                f"right name?")
        return f"{text} {self.hint}".strip()


def publications() -> list[Publication]:
    """Every published topic on the master, with its type and publishers."""
    master = rosgraph.Master(rospy.get_name())
    types = dict(master.getTopicTypes())
    published, _, _ = master.getSystemState()
    return [Publication(topic, types.get(topic, ""), tuple(nodes))
            for topic, nodes in published]


def watch_input(topic: str, msg_class: Any, hint: str = "",
                after: float = SILENCE) -> InputWatch:
    """Start watching the input ``topic`` (as the node names it; remaps apply) of ``msg_class``;
    call ``.heard(rospy.get_time())`` from its callback (``msg_class``: a generated message
    class, e.g. nav_msgs.msg.Odometry). Checks once a second (ROS time) and
    logs a warning naming the input."""
    watch = InputWatch(topic=rospy.resolve_name(topic), msg_type=msg_class._type,
                       node=rospy.get_name(), namespace=rospy.get_namespace(),
                       started=rospy.get_time(), hint=hint, after=after)

    def check(_event: object) -> None:
        now = rospy.get_time()
        if not watch.due(now):
            return
        try:
            warning = watch.check(now, publications())
        except (OSError, rosgraph.MasterException):
            return                       # the master is away: nothing to compare with
        if warning:
            rospy.logwarn(warning)

    rospy.Timer(rospy.Duration(1.0), check)
    return watch
