"""Test scenes for the detector, rendered by the simulator, with their ground truth.

A :class:`Scenario` places Faulty relative to Helper's Kinect (horizontal range, bearing and
heading in the camera frame, see :mod:`rason_vision.geometry`), plus optional distractor
objects, lighting and cylinder-colour changes. :func:`render` builds the simulator world
(``turtlebot_sim.world.World``), renders Helper's Kinect and returns the frame with its ground
truth, a JSON-able dict:

``case``, ``seed``, ``faulty`` (in the scene at all), ``angle``/``depth``/``yaw``/``heading``
(what a perfect detector would publish; null without Faulty), ``distance`` (horizontal range
of Faulty's centre), ``green_px``/``orange_px`` (pixels of each cylinder in view, occlusion
included, from an exact ray cast of the cylinders), ``green_cols``/``orange_cols`` (image
columns they span), and ``expect``: ``robot`` (both cylinders clearly visible: at least 40 px
and 5 columns each, colours normal: must be detected), ``none`` (no robot can be seen: must not be
reported) or ``any`` (partly visible or deliberately off-colour: either answer is acceptable;
accuracy is still scored when a detection is made and both cylinders show).
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from rason_vision.geometry import CYLINDER_OFFSET, cylinder_axes_in_camera, relative_from_axes
from rason_vision_tools.synthetic import Cylinder, Scene
from turtlebot_sim.camera_effects import CameraEffects
from turtlebot_sim.world import World

#: Kinect optical centre in Helper's base frame (m), as built by turtlebot_sim.
CAMERA_OFFSET = (0.135, 0.0, 0.45)
#: Visible pixels each cylinder needs for a frame to count as "both clearly visible".
CLEAR_PX = 40
#: ... and image columns it must span (a thinner sliver does not survive the opening).
CLEAR_COLUMNS = 5
FOV_HALF_DEG = 28.5

GREEN_LIKE = [0.12, 0.60, 0.20]
ORANGE_LIKE = [0.95, 0.42, 0.08]


@dataclass
class Distractor:
    """A static object placed by range and bearing from Helper's camera."""
    shape: str
    distance: float
    bearing: float
    color: list[float]
    radius: float = 0.05
    height: float = 0.3
    size: tuple[float, float, float] = (0.3, 0.3, 0.5)
    yaw: float = 0.0


@dataclass
class Scenario:
    """One frame to render: Faulty relative to Helper's camera, and the scene around it."""
    case: str
    distance: float = 1.5
    bearing: float = 0.0
    heading: float = -90.0
    faulty: bool = True
    helper: tuple[float, float, float] = (0.0, 0.0, 0.0)
    distractors: list[Distractor] = field(default_factory=list)
    cylinder_colors: dict[str, list[float]] = field(default_factory=dict)
    lighting: dict[str, Any] = field(default_factory=dict)
    seed: int = 0
    expect: str | None = None
    #: Faulty's world pose (x, y, yaw deg); when set it replaces distance/bearing/heading.
    faulty_pose: tuple[float, float, float] | None = None

    def faulty_world_pose(self) -> tuple[float, float, float]:
        """Faulty's world pose (x, y, yaw in rad)."""
        if self.faulty_pose is not None:
            x, y, yaw = self.faulty_pose
            return x, y, math.radians(yaw)
        fx, fy, _, _ = _world_xy(self.helper, self.distance, self.bearing)
        return fx, fy, math.radians(self.helper[2] - self.heading)


def _world_xy(helper: tuple[float, float, float], distance: float,
              bearing: float) -> tuple[float, float, float, float]:
    """World (x, y) at ``distance``/``bearing`` from the camera; also camera x, y."""
    hx, hy, hyaw = helper[0], helper[1], math.radians(helper[2])
    cx = hx + CAMERA_OFFSET[0] * math.cos(hyaw)
    cy = hy + CAMERA_OFFSET[0] * math.sin(hyaw)
    direction = hyaw - math.radians(bearing)
    return cx + distance * math.cos(direction), cy + distance * math.sin(direction), cx, cy


#: The sections of a world file that :func:`world_config` takes over (its light and camera).
WORLD_OVERLAY_KEYS = ("lighting", "camera", "floor", "room")


def world_config(s: Scenario, overlay: dict[str, Any] | None = None) -> dict[str, Any]:
    """The turtlebot_sim world dict of a scenario (poses are set again after building); the
    :data:`WORLD_OVERLAY_KEYS` sections of `overlay` (a world file's dict) replace its own."""
    robots = [{"name": "helper", "kind": "helper", "x": s.helper[0], "y": s.helper[1],
               "yaw": s.helper[2]}]
    if s.faulty:
        fx, fy, fyaw = s.faulty_world_pose()
        robots.append({"name": "faulty", "kind": "faulty", "x": fx, "y": fy,
                       "yaw": math.degrees(fyaw)})
    objects = []
    for d in s.distractors:
        ox, oy, _, _ = _world_xy(s.helper, d.distance, d.bearing)
        obj: dict[str, Any] = {"shape": d.shape, "color": list(d.color), "x": ox, "y": oy,
                               "yaw": d.yaw}
        if d.shape == "box":
            obj["size"] = list(d.size)
        else:
            obj.update(radius=d.radius, height=d.height)
        objects.append(obj)
    cfg: dict[str, Any] = {"seed": s.seed, "robots": robots, "objects": objects,
                           "randomize": {"pose_cm": 0.0, "yaw_deg": 0.0,
                                         "light_direction_deg": 25.0, "light_intensity": 0.15,
                                         "color_jitter": 0.03}}
    if s.cylinder_colors:
        cfg["cylinders"] = dict(s.cylinder_colors)
    if s.lighting:
        cfg["lighting"] = dict(s.lighting)
    for key in WORLD_OVERLAY_KEYS:
        if overlay and key in overlay:
            cfg[key] = {**cfg.get(key, {}), **overlay[key]}
    return cfg


def _label_scene(cam: tuple[float, float, float], faulty: tuple[float, float, float] | None,
                 s: Scenario) -> Scene:
    """The cylinders of a scene in the camera frame, for exact visibility counts."""
    scene = Scene(camera_height=CAMERA_OFFSET[2])
    if faulty is not None:
        green, orange = cylinder_axes_in_camera(*cam, *faulty)
        scene.add_faulty(green, orange)
        scene.cylinders[0] = replace(scene.cylinders[0], radius=0.16)
    for d in s.distractors:
        b = math.radians(d.bearing)
        radius = d.radius if d.shape != "box" else math.hypot(d.size[0], d.size[1]) / 2
        height = d.height if d.shape != "box" else d.size[2]
        scene.cylinders.append(Cylinder(d.distance * math.sin(b), d.distance * math.cos(b),
                                        radius, 0.0, height, (0, 0, 0)))
    return scene


def _expectation(s: Scenario, truth: dict[str, Any]) -> str:
    if s.expect:
        return s.expect
    if not s.faulty or truth["green_px"] == 0 or truth["orange_px"] == 0:
        return "none"
    clear = all(truth[f"{c}_px"] >= CLEAR_PX and truth[f"{c}_cols"] >= CLEAR_COLUMNS
                for c in ("green", "orange"))
    return "robot" if clear and not s.cylinder_colors else "any"


def render(s: Scenario, overlay: dict[str, Any] | None = None
           ) -> tuple[np.ndarray, np.ndarray, dict[str, Any]]:
    """Render a scenario with the simulator, in the light and camera of `overlay` (a world
    file's dict, see :func:`world_config`): (rgb, xyz, ground truth dict). The camera's
    effects apply (a still camera: auto exposure, no motion blur)."""
    with World.from_yaml(world_config(s, overlay)) as world:
        hx, hy, hyaw = s.helper[0], s.helper[1], math.radians(s.helper[2])
        world.set_pose("helper", hx, hy, hyaw)
        faulty_pose = None
        if s.faulty:
            world.set_pose("faulty", *s.faulty_world_pose())
            faulty_pose = world.pose("faulty")
        position, rotation = world.camera_pose("helper")
        cam = (float(position[0]), float(position[1]),
               math.atan2(rotation[1, 0], rotation[0, 0]))
        rgb, xyz = world.render_kinect("helper", rng=np.random.default_rng([s.seed, 7]))
        effects = CameraEffects.from_config(world.config["camera"])
        if effects.active:
            rgb = effects.apply(rgb, 0.0, world.intrinsics.fx)
    seen = _label_scene(cam, faulty_pose, s).visibility()
    truth: dict[str, Any] = {"case": s.case, "seed": s.seed, "faulty": s.faulty,
                             "green_px": seen[1][0] if s.faulty else 0,
                             "orange_px": seen[2][0] if s.faulty else 0,
                             "green_cols": seen[1][1] if s.faulty else 0,
                             "orange_cols": seen[2][1] if s.faulty else 0,
                             "angle": None, "depth": None, "yaw": None, "heading": None,
                             "distance": None}
    if faulty_pose is not None:
        rel = relative_from_axes(*cylinder_axes_in_camera(*cam, *faulty_pose))
        truth.update(angle=rel.angle, depth=rel.depth, yaw=rel.yaw, heading=rel.heading,
                     distance=rel.depth / math.cos(math.radians(rel.angle)))
    truth["expect"] = _expectation(s, truth)
    return rgb, xyz, truth


# -- scenario sets -------------------------------------------------------------------------------

def _distractors(rng: np.random.Generator, s: Scenario, count: int) -> list[Distractor]:
    """Similar-coloured objects in view that neither hide Faulty nor pair up by accident."""
    kinds = [("cylinder", ORANGE_LIKE, 0.05, 0.3), ("box", GREEN_LIKE, 0.0, 0.5),
             ("cylinder", GREEN_LIKE, 0.03, 0.6), ("box", ORANGE_LIKE, 0.0, 0.4),
             ("cylinder", ORANGE_LIKE, 0.03, 0.55)]
    placed: list[tuple[float, float]] = []
    fb = math.radians(s.bearing)
    faulty_xz = (s.distance * math.sin(fb), s.distance * math.cos(fb)) if s.faulty else None
    out: list[Distractor] = []
    for _ in range(200):
        if len(out) >= count:
            break
        shape, color, radius, height = kinds[int(rng.integers(len(kinds)))]
        dist, bearing = float(rng.uniform(1.0, 4.0)), float(rng.uniform(-26, 26))
        b = math.radians(bearing)
        xz = (dist * math.sin(b), dist * math.cos(b))
        if any(math.dist(xz, other) < 0.6 for other in placed):
            continue
        if faulty_xz is not None:
            if math.dist(xz, faulty_xz) < 0.7:
                continue
            # not between the camera and Faulty
            sep = abs(bearing - s.bearing)
            if dist < s.distance + 0.4 and sep < math.degrees(math.atan2(0.45, dist)) + 4:
                continue
        placed.append(xz)
        size = (0.25, 0.25, height) if shape == "box" else (0.3, 0.3, 0.5)
        out.append(Distractor(shape, dist, bearing, color, radius or 0.05, height, size,
                              float(rng.uniform(0, 90))))
    return out


def _in_view_bearing(rng: np.random.Generator, distance: float, margin_m: float = 0.16) -> float:
    """A bearing that keeps Faulty's cylinders inside the image."""
    limit = FOV_HALF_DEG - math.degrees(math.atan2(margin_m, distance)) - 0.5
    return float(rng.uniform(-limit, limit))


def random_scenarios(seed: int, count: int) -> Iterator[Scenario]:
    """A seeded mix: headings all round in 15 deg steps over distances 0.8-3.5 m and bearings
    across the view (light direction, intensity and colours jittered), plus dim (some with
    shadows) and bright light, flank views, distractors, failure cases (one cylinder
    off-colour, as if shadowed; partly out of frame) and frames without Faulty."""
    rng = np.random.default_rng(seed)
    for i in range(count):
        kind = i % 10
        helper = (float(rng.uniform(-1, 1)), float(rng.uniform(-1, 1)),
                  float(rng.uniform(-180, 180)))
        distance = float(rng.uniform(0.8, 3.5))
        heading = float((i * 15) % 360 - 180 + rng.uniform(-2, 2))
        s = Scenario("sweep", distance, _in_view_bearing(rng, distance), heading,
                     helper=helper, seed=seed * 100003 + i)
        if kind == 1:
            s.case = "dim_light" if i % 20 == 1 else "bright_light"
            s.lighting = ({"ambient": float(rng.uniform(0.15, 0.35)),
                           "diffuse": float(rng.uniform(0.2, 0.35)), "shadow": bool(i % 40 == 1)}
                          if i % 20 == 1 else
                          {"ambient": float(rng.uniform(0.8, 0.95)),
                           "diffuse": float(rng.uniform(0.5, 0.7))})
        elif kind == 3:
            s.case, s.heading = "flank", float(rng.choice([-90.0, 90.0]) + rng.uniform(-6, 6))
        elif kind == 5:
            s.case = "distractors"
            s.distractors = _distractors(rng, s, int(rng.integers(2, 5)))
        elif kind == 7:
            s.case = "partly_out"
            side = float(rng.choice([-1.0, 1.0]))
            s.bearing = side * (FOV_HALF_DEG - math.degrees(math.atan2(0.05, distance)))
        elif kind == 9 and i % 20 == 9:
            s.case, s.faulty = "no_robot", False
            s.distractors = _distractors(rng, s, int(rng.integers(2, 5)))
        elif kind == 9:
            s.case = "off_colour"
            s.cylinder_colors = {"orange": [0.45, 0.38, 0.33]} if i % 40 == 19 else \
                {"green": [0.30, 0.36, 0.32]}
        yield s


def committed_sweep() -> list[Scenario]:
    """``bags/vision_sweep.bag``: Faulty's heading all round in 15 deg steps (24 frames) over
    distances 0.8-3.5 m and bearings across the view; flank views at +-90 (the right flank
    is the self-occlusion case); five frames with similar-coloured distractors."""
    distances = [0.8, 1.2, 1.5, 2.0, 2.5, 3.0, 3.5]
    bearings = [-22.0, -14.0, -5.0, 0.0, 7.0, 15.0, 22.0]
    rng = np.random.default_rng(2015)
    out = []
    for i, heading in enumerate(range(-180, 180, 15)):
        s = Scenario("sweep", distances[i % 7], bearings[(i * 3) % 7], float(heading),
                     helper=(0.0, 0.0, float((i * 37) % 360 - 180)), seed=1000 + i)
        if heading in (-90, 90):
            s.case, s.bearing = "flank", 0.0
        if i % 5 == 2:
            s.case = "distractors"
            s.distractors = _distractors(rng, s, 3)
        out.append(s)
    return out


def committed_cases() -> list[Scenario]:
    """``bags/vision_cases.bag`` (7 frames): the case study's start (Faulty 1.5 m on Helper's
    right, Helper turned right by 85 and 90 deg: Faulty's left flank), one cylinder out of
    colour range, one cut by the image border, the right flank (green hidden), distractors
    alone and an empty room."""
    rng = np.random.default_rng(2016)
    out = [Scenario("case_study", helper=(0.0, 0.0, -85.0), faulty_pose=(0.0, -1.5, 0.0),
                    seed=1200),
           Scenario("case_study", helper=(0.0, 0.0, -90.0), faulty_pose=(0.0, -1.5, 0.0),
                    seed=1201),
           Scenario("off_colour", 1.8, 6.0, -60.0, helper=(0.5, 0.5, 45.0), seed=1202,
                    cylinder_colors={"orange": [0.45, 0.38, 0.33]}),
           Scenario("partly_out", 1.3, 26.0, -20.0, helper=(-0.5, 0.3, 120.0), seed=1203),
           Scenario("self_occlusion", 2.2, -8.0, 82.0, helper=(0.3, 0.0, 10.0), seed=1204)]
    none = Scenario("no_robot", faulty=False, helper=(0.2, -0.4, -30.0), seed=1205)
    none.distractors = _distractors(rng, none, 4)
    out.append(none)
    out.append(Scenario("no_robot", faulty=False, helper=(-1.0, 1.0, 160.0), seed=1206))
    return out


__all__ = ["CYLINDER_OFFSET", "Distractor", "Scenario", "committed_cases", "committed_sweep",
           "random_scenarios", "render", "world_config"]
