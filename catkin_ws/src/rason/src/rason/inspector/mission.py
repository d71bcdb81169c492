"""The mission an agent's beliefs describe (agents/mission/faulty.asl's Knowledge), for the
inspector's mission view; pure, no ROS.

An agent has a mission when it believes ``waypoint(I, X, Y)`` (world frame, m). Its other
beliefs say how far it is: ``reached(I, By)``, ``delegated(H)`` (the remaining waypoints were
offered to H), ``accept(Ws)[source(H)]`` (H took them), ``diagnosis(D)``, ``recovery(S)``,
``gaveUp(Why)`` and ``missionDone``. Each waypoint is then reached by someone, assigned to the
robot that has it now (the agent itself, or H once delegated), or nobody's (given up).
Waypoints with a coordinate that is not finite are left out, and beyond MAX_WAYPOINTS the
highest indices.
"""

from __future__ import annotations

import math
import re
from dataclasses import asdict, dataclass, field

NUMBER = r"(-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?)"
WAYPOINT = re.compile(rf"^waypoint\((\d+),{NUMBER},{NUMBER}\)$")
REACHED = re.compile(r"^reached\((\d+),(\w+)\)$")
ONE_ARGUMENT = re.compile(r"^(diagnosis|recovery|delegated|gaveUp)\((.*)\)$")
#: waypoints shown per mission at most (the lowest indices): the page stays small whatever an
#: agent believes
MAX_WAYPOINTS = 256


@dataclass
class WaypointState:
    """One waypoint: where, who reached it (None: not yet), who has it now (None: reached, or
    nobody since the mission was given up) and whether it is the one being driven to."""

    index: int
    x: float
    y: float
    reached_by: str | None = None
    assigned_to: str | None = None
    current: bool = False


@dataclass
class MissionState:
    """What an agent's beliefs say of its mission."""

    agent: str
    waypoints: list[WaypointState] = field(default_factory=list)
    diagnosis: str | None = None
    recovery: str | None = None
    delegated_to: str | None = None
    accepted: bool = False             # the robot delegated to accepted the offer
    gave_up: str | None = None
    done: bool = False

    def to_dict(self) -> dict:
        return asdict(self)


def mission_of(agent: str, beliefs: list[dict]) -> MissionState | None:
    """The mission in an agent's beliefs (a mind state's ``mind.beliefs``: ``text`` and
    ``sources`` each), or None when it believes no ``waypoint/3``."""
    state = MissionState(agent)
    points: dict[int, WaypointState] = {}
    reached: dict[int, str] = {}
    accepted_by: set[str] = set()
    for belief in beliefs:
        text = str(belief.get("text", "")).replace(" ", "")
        if m := WAYPOINT.match(text):
            index, x, y = int(m.group(1)), float(m.group(2)), float(m.group(3))
            if math.isfinite(x) and math.isfinite(y):      # JSON has no inf
                points[index] = WaypointState(index, x, y)
        elif m := REACHED.match(text):
            reached[int(m.group(1))] = m.group(2)
        elif text.startswith("accept("):
            accepted_by.update(str(s) for s in belief.get("sources", []))
        elif text == "missionDone":
            state.done = True
        elif m := ONE_ARGUMENT.match(text):
            name, value = m.groups()
            if name == "delegated":
                state.delegated_to = value
            elif name == "gaveUp":
                state.gave_up = value
            else:
                setattr(state, name, value)
    if not points:
        return None
    state.accepted = state.delegated_to is not None and state.delegated_to in accepted_by
    holder = None if state.gave_up is not None else state.delegated_to or agent
    for index in sorted(points)[:MAX_WAYPOINTS]:
        point = points[index]
        point.reached_by = reached.get(index)
        point.assigned_to = holder if point.reached_by is None else None
        state.waypoints.append(point)
    if holder is not None:
        pending = [p for p in state.waypoints if p.reached_by is None]
        if pending:
            pending[0].current = True
    return state
