"""Seeded random layouts of the case study: where a user might put the two robots in a room.

Faulty stands 0.8-4 m from Helper at any bearing, both robots at any heading, inside the room:
Helper keeps ``HELPER_WALL_MARGIN`` from the walls (it may back up to get Faulty into a good
range), Faulty's own test path (1 m forward and back, the case study's goal) stays inside the
room and clear of Helper, as a user would place a robot about to drive 1 m.
Angles in degrees; world frame x forward, y left, yaw counter-clockwise (the world file's).
"""

from __future__ import annotations

import copy
import math
import random
from dataclasses import asdict, dataclass
from pathlib import Path

import yaml

from rason_diagnosis.paths import world_colours
from turtlebot_model.geometry import wrap_deg

MIN_DISTANCE, MAX_DISTANCE = 0.8, 4.0
HELPER_WALL_MARGIN = 1.3     # m: Helper may back up by up to 0.9 m
FAULTY_WALL_MARGIN = 0.5     # m: Faulty's body and its 1 m path stay this far from the walls
FAULTY_PATH = 1.2            # m: Faulty's forward path checked (its 1 m goal plus overshoot)
PATH_CLEARANCE = 0.6         # m: Helper's centre from Faulty's path (two robot radii + margin)


@dataclass(frozen=True)
class Layout:
    """One placement: the world poses and what Helper will see of Faulty."""

    seed: int
    helper_x: float
    helper_y: float
    helper_yaw: float
    faulty_x: float
    faulty_y: float
    faulty_yaw: float
    distance: float          # m, centre to centre
    bearing: float           # deg, Faulty seen from Helper's start heading, + = right (clockwise)
    relative_heading: float  # deg, Faulty's heading minus the line of sight Helper -> Faulty,
    #                          clockwise: -90 = its left flank toward Helper (the thesis' view)

    def robots(self) -> list[dict]:
        return [{"name": "helper", "kind": "helper", "x": round(self.helper_x, 3),
                 "y": round(self.helper_y, 3), "yaw": round(self.helper_yaw, 1)},
                {"name": "faulty", "kind": "faulty", "x": round(self.faulty_x, 3),
                 "y": round(self.faulty_y, 3), "yaw": round(self.faulty_yaw, 1)}]


def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> float:
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(px - (ax + t * dx), py - (ay + t * dy))


def random_layout(seed: int, room: tuple[float, float] = (10.0, 10.0)) -> Layout:
    """The layout of a seed (the same seed always gives the same layout)."""
    rng = random.Random(seed)
    half_x, half_y = room[0] / 2.0, room[1] / 2.0
    while True:
        hx = rng.uniform(-half_x + HELPER_WALL_MARGIN, half_x - HELPER_WALL_MARGIN)
        hy = rng.uniform(-half_y + HELPER_WALL_MARGIN, half_y - HELPER_WALL_MARGIN)
        hyaw = rng.uniform(-180.0, 180.0)
        distance = rng.uniform(MIN_DISTANCE, MAX_DISTANCE)
        bearing = rng.uniform(-180.0, 180.0)               # clockwise from Helper's heading
        direction = math.radians(hyaw - bearing)           # world angle of Helper -> Faulty
        fx, fy = hx + distance * math.cos(direction), hy + distance * math.sin(direction)
        fyaw = rng.uniform(-180.0, 180.0)
        ex = fx + FAULTY_PATH * math.cos(math.radians(fyaw))
        ey = fy + FAULTY_PATH * math.sin(math.radians(fyaw))
        inside = all(abs(x) <= half_x - FAULTY_WALL_MARGIN for x in (fx, ex)) and \
            all(abs(y) <= half_y - FAULTY_WALL_MARGIN for y in (fy, ey))
        if inside and _segment_distance(hx, hy, fx, fy, ex, ey) >= PATH_CLEARANCE:
            line_of_sight = math.degrees(direction)
            return Layout(seed, hx, hy, hyaw, fx, fy, fyaw, distance, wrap_deg(bearing),
                          wrap_deg(-(fyaw - line_of_sight)))


def write_world(layout: Layout, base: Path, out: Path) -> Path:
    """``base`` (a world file) with the layout's robot poses, written to ``out`` (a colours file
    the world names is kept, by its absolute path)."""
    world = yaml.safe_load(base.read_text())
    world = copy.deepcopy(world)
    world["robots"] = layout.robots()
    colours = world_colours(base)
    if colours is not None:
        world["vision"]["colours"] = str(colours)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(f"# random layout, seed {layout.seed}: {asdict(layout)}\n"
                   + yaml.safe_dump(world, sort_keys=False))
    return out
