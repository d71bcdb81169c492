"""The Kobuki base's safety events for the motion decomposer, without rospy.

kobuki_node publishes an event when a bumper is pressed or released
(``mobile_base/events/bumper``, kobuki_msgs/BumperEvent), when a cliff sensor sees the floor
vanish or come back (``.../cliff``, CliffEvent) and when a wheel drops or is raised again
(``.../wheel_drop``, WheelDropEvent). :class:`BaseSafety` keeps which of them are active and
says what a motion may do about them:

* A hazard that begins (a press, a cliff, a drop) stops the running motion at once, whatever
  its direction: the base touched something it was not meant to touch. The motion ends with
  the hazard's name as its result (``bumper``, ``cliff``, ``wheel_drop``) and a message naming
  the bumper, sensor or wheel.
* While a hazard lasts, a new motion that would drive into it is refused with the same result.
  The Kobuki's three bumpers and three cliff sensors all face forward (left, centre, right of
  the front arc), so:

  - a forward ``move`` is refused; a backward ``move`` (a negative distance) is allowed: it
    backs away from the wall or the edge, which is how a robot gets out;
  - a turn toward a pressed side bumper or a side cliff is refused (with the left bumper
    pressed, turning left would scrape further into what it touches); a turn away from it is
    allowed, and so is any turn with only the centre one active (the round base turns in its
    own footprint);
  - a dropped wheel refuses every motion: the robot is lifted or stuck in a hole, and the base
    cuts its motors anyway; put it down (the wheel is raised again) and motions are accepted.

The state comes from the events heard since the node started (kobuki_node publishes them on
change only): a bumper pressed before the decomposer started counts from its next event.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from rason.execution.results import BUMPER, CLIFF, WHEEL_DROP, Verdict

__all__ = ["BUMPER", "CLIFF", "WHEEL_DROP", "BaseSafety", "Hazard", "Side"]


class Side(Enum):
    """Where on the base a bumper, cliff sensor or wheel sits."""

    LEFT = "left"
    CENTRE = "centre"
    RIGHT = "right"


#: kobuki_msgs' numbering: BumperEvent.bumper and CliffEvent.sensor LEFT 0, CENTER 1, RIGHT 2;
#: WheelDropEvent.wheel LEFT 0, RIGHT 1.
SIDES = {BUMPER: (Side.LEFT, Side.CENTRE, Side.RIGHT),
         CLIFF: (Side.LEFT, Side.CENTRE, Side.RIGHT),
         WHEEL_DROP: (Side.LEFT, Side.RIGHT)}
#: What each kind of part is called, and what it does when its hazard begins.
PARTS = {BUMPER: ("bumper", "pressed"), CLIFF: ("cliff sensor", "sees a cliff"),
         WHEEL_DROP: ("wheel", "dropped")}


@dataclass(frozen=True)
class Hazard:
    """One active safety event: a pressed bumper, a cliff under a sensor, a dropped wheel."""

    kind: str          # BUMPER, CLIFF or WHEEL_DROP (the result a motion ends with)
    side: Side

    @classmethod
    def of(cls, kind: str, index: int) -> Hazard:
        """The hazard of kobuki_msgs' part number `index`; ValueError for an unknown one."""
        sides = SIDES.get(kind)
        if sides is None:
            raise ValueError(f"unknown safety event {kind!r}")
        if not 0 <= index < len(sides):
            raise ValueError(f"{kind} event for part {index}: the Kobuki has "
                             f"{len(sides)} (0-{len(sides) - 1})")
        return cls(kind, sides[index])

    @property
    def name(self) -> str:
        """``left bumper``, ``centre cliff sensor``, ``right wheel``."""
        return f"{self.side.value} {PARTS[self.kind][0]}"

    @property
    def what(self) -> str:
        """``left bumper pressed``, ``right cliff sensor sees a cliff``."""
        return f"{self.name} {PARTS[self.kind][1]}"

    def blocks(self, linear: float, angular: float) -> bool:
        """Whether a motion in this direction (signs only: linear > 0 forward, angular > 0
        counter-clockwise, to the left) would drive into this hazard."""
        if self.kind == WHEEL_DROP:
            return bool(linear or angular)
        if linear > 0:
            return True
        if self.side is Side.LEFT:
            return angular > 0
        if self.side is Side.RIGHT:
            return angular < 0
        return False

    def stopped(self, motion: str, doing: str) -> Verdict:
        """The verdict of `motion` (``move(1)``), stopped by this hazard after `doing`."""
        return Verdict(self.kind, f"{self.what}: {motion} stopped after {doing}")

    def way_out(self) -> str:
        """What the robot may still do, for the refusal's message."""
        if self.kind == WHEEL_DROP:
            return "no motion until the wheel is back on the floor"
        turn = {Side.LEFT: "turn right", Side.RIGHT: "turn left",
                Side.CENTRE: "turn"}[self.side]
        return f"back off (a negative move) or {turn}"


class BaseSafety:
    """The active hazards, from the base's events; see the module's documentation."""

    def __init__(self) -> None:
        self.active: dict[tuple[str, Side], Hazard] = {}

    def event(self, kind: str, index: int, on: bool) -> Hazard | None:
        """Take an event (`on`: pressed / cliff / dropped; otherwise released / floor / raised).
        Returns the hazard when one begins (the running motion must stop), else None."""
        hazard = Hazard.of(kind, index)
        key = (hazard.kind, hazard.side)
        if not on:
            self.active.pop(key, None)
            return None
        self.active[key] = hazard
        return hazard

    def refusal(self, motion: str, linear: float, angular: float) -> Verdict | None:
        """The verdict refusing a new motion that would drive into an active hazard, or None.
        `motion` names it in the message (``move(0.5)``)."""
        for hazard in self.active.values():
            if hazard.blocks(linear, angular):
                return Verdict(hazard.kind, f"{hazard.what}: {motion} refused, it would drive "
                                            f"into it ({hazard.way_out()})")
        return None
