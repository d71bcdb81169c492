"""The Kobuki's bumpers from the simulation's contacts, as edge events (no ROS, no pybullet).

A Kobuki has one bumper around the front half of its body, read as three switches. A contact
between the base and an obstacle (a wall, another robot, an object) at bearing ``a`` (radians in
``base_footprint``, counter-clockwise from straight ahead) presses:

* CENTER when ``|a| <= CENTER_HALF_SPAN``,
* LEFT when ``CENTER_HALF_SPAN < a <= BUMPER_HALF_SPAN``,
* RIGHT when ``-BUMPER_HALF_SPAN <= a < -CENTER_HALF_SPAN``,
* nothing behind that (the Kobuki's back has no bumper).

:class:`BumperSwitches` turns the pressed set of each check into PRESSED / RELEASED events, one
per switch that changed, as kobuki_node publishes them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from enum import IntEnum

#: Half the angle the front bumper covers (the Kobuki's bumper wraps the front half).
BUMPER_HALF_SPAN = math.radians(90.0)
#: Half the angle of the centre switch; the left and right switches take the rest.
CENTER_HALF_SPAN = math.radians(30.0)


class Bumper(IntEnum):
    """kobuki_msgs/BumperEvent's ``bumper`` values."""

    LEFT = 0
    CENTER = 1
    RIGHT = 2


class SwitchState(IntEnum):
    """kobuki_msgs/BumperEvent's ``state`` values."""

    RELEASED = 0
    PRESSED = 1


#: kobuki_msgs/SensorState's ``bumper`` bit of each switch.
SENSOR_BITS = {Bumper.RIGHT: 1, Bumper.CENTER: 2, Bumper.LEFT: 4}


def bumper_at(bearing: float) -> Bumper | None:
    """The switch a contact at ``bearing`` (rad, base frame, CCW from ahead) presses, or None."""
    a = math.atan2(math.sin(bearing), math.cos(bearing))
    if abs(a) <= CENTER_HALF_SPAN:
        return Bumper.CENTER
    if abs(a) > BUMPER_HALF_SPAN:
        return None
    return Bumper.LEFT if a > 0 else Bumper.RIGHT


@dataclass(frozen=True)
class BumperChange:
    """One switch that changed state."""

    bumper: Bumper
    state: SwitchState


@dataclass
class BumperSwitches:
    """The three switches of one robot: the pressed set, updated from each check's contacts."""

    pressed: set[Bumper] = field(default_factory=set)

    def update(self, bearings: Iterable[float]) -> list[BumperChange]:
        """Contacts of this check -> the changes (presses first, then releases, by switch)."""
        now = {b for b in map(bumper_at, bearings) if b is not None}
        changes = [BumperChange(b, SwitchState.PRESSED) for b in sorted(now - self.pressed)]
        changes += [BumperChange(b, SwitchState.RELEASED) for b in sorted(self.pressed - now)]
        self.pressed = now
        return changes

    @property
    def bits(self) -> int:
        """The pressed switches as kobuki_msgs/SensorState's ``bumper`` bits."""
        return sum(SENSOR_BITS[b] for b in self.pressed)


class Side(IntEnum):
    """kobuki_msgs/CliffEvent's ``sensor`` values (WheelDropEvent's ``wheel``: LEFT 0, RIGHT 1)."""

    LEFT = 0
    CENTER = 1
    RIGHT = 2


#: kobuki_msgs/SensorState's ``cliff`` and ``wheel_drop`` bits of each side.
CLIFF_BITS = {Side.RIGHT: 1, Side.CENTER: 2, Side.LEFT: 4}
WHEEL_DROP_BITS = {Side.RIGHT: 1, Side.LEFT: 2}
WHEELS = {Side.LEFT: 0, Side.RIGHT: 1}


@dataclass(frozen=True)
class ScriptedEvent:
    """A cliff or wheel drop of the world file's ``base_events``, on (True) or off (False)."""

    robot: str
    kind: str            # "cliff" or "wheel_drop"
    side: Side
    on: bool


@dataclass
class BaseEventScript:
    """The world file's ``base_events`` (resolved entries), as edges in time."""

    entries: list[dict]
    _done: set[tuple[int, bool]] = field(default_factory=set)

    def due(self, t: float) -> list[ScriptedEvent]:
        """The edges reached by time ``t`` (s) and not returned before, in time order."""
        edges = []
        for i, e in enumerate(self.entries):
            for on, when in ((True, e["at"]), (False, e["at"] + e["duration"])):
                if t >= when and (i, on) not in self._done:
                    self._done.add((i, on))
                    edges.append((when, ScriptedEvent(e["robot"], e["kind"],
                                                      Side[e["side"].upper()], on)))
        return [event for _, event in sorted(edges, key=lambda edge: edge[0])]

    def robots(self) -> set[str]:
        return {e["robot"] for e in self.entries}
