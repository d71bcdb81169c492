"""World description: the YAML world file, its defaults and the seeded randomisation.

A world file is a mapping; every key is optional except ``robots``::

    seed: 0                          # randomisation seed (null: no randomisation at all)
    physics: {dt: 0.005}
    floor: {color: [0.45, 0.42, 0.38]}
    room: {size: [10.0, 10.0], wall_height: 2.5, wall_color: [0.82, 0.80, 0.74]}
    lighting: {direction: [0.4, -0.3, 1.0], color: [1, 1, 1], distance: 10.0,
               ambient: 0.6, diffuse: 0.45, specular: 0.05, shadow: false}
    cylinders: {green: [0.10, 0.62, 0.18], orange: [1.0, 0.45, 0.05]}
    camera: {rate: 15, width: 640, height: 480, hfov_deg: 57.0, min_range: 0.5, max_range: 4.5,
             depth_noise: [0.0012, 0.0019, 0.4], quantize_depth: true, color_noise: 3.0,
             edge_dropout: 0.0, exposure_s: 0.0, auto_exposure: false,
             auto_exposure_target: 110, auto_exposure_max_gain: 4.0}
    odometry: {left_radius_scale: 1.0, right_radius_scale: 1.0, separation_scale: 1.0}
    randomize: {pose_cm: 0.0, yaw_deg: 0.0, light_direction_deg: 0.0, light_intensity: 0.0,
                color_jitter: 0.0}
    robots:
      - {name: helper, kind: helper, x: 0.0, y: 0.0, yaw: 0.0}    # yaw in degrees
      - {name: faulty, kind: faulty, x: 0.0, y: -1.5, yaw: 0.0}
    objects:                         # optional distractors (static)
      - {shape: box, size: [0.4, 0.4, 0.6], color: [0.2, 0.3, 0.8], x: 3.0, y: 1.0, yaw: 30}
      - {shape: cylinder, radius: 0.05, height: 0.3, color: [0.9, 0.4, 0.1], x: 2.0, y: -2.0}
    base_events:                     # optional: a cliff sensor or a wheel drop raised at a sim
      - {robot: faulty, at: 5.0, kind: cliff, side: center, duration: 1.0}   # time (seconds)
      - {robot: faulty, at: 8.0, kind: wheel_drop, side: left, duration: 0.5}

Colours are RGB in [0, 1]. ``lighting.shadow`` casts shadows (TinyRenderer's shadow map);
``camera.edge_dropout`` > 0 drops depth at depth edges; ``camera.exposure_s`` > 0 blurs the
colour by the camera's turn over the exposure and ``camera.auto_exposure`` scales it to a mean
luma (:mod:`turtlebot_sim.camera_effects`); all off by default.

:func:`resolve` applies the defaults and the randomisation and returns a plain dict
(picklable, YAML-dumpable) that fully determines the scene: the render worker process rebuilds
the same scene from it.
"""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import yaml

DEFAULTS: dict[str, Any] = {
    "seed": None,
    "physics": {"dt": 1.0 / 200.0},
    "floor": {"color": [0.45, 0.42, 0.38]},
    "room": {"size": [10.0, 10.0], "wall_height": 2.5, "wall_color": [0.82, 0.80, 0.74]},
    "lighting": {"direction": [0.4, -0.3, 1.0], "color": [1.0, 1.0, 1.0], "distance": 10.0,
                 "ambient": 0.6, "diffuse": 0.45, "specular": 0.05, "shadow": False},
    "cylinders": {"green": [0.10, 0.62, 0.18], "orange": [1.0, 0.45, 0.05]},
    "camera": {"rate": 15.0, "width": 640, "height": 480, "hfov_deg": 57.0,
               "min_range": 0.5, "max_range": 4.5, "depth_noise": [0.0012, 0.0019, 0.4],
               "quantize_depth": True, "color_noise": 3.0, "edge_dropout": 0.0,
               "exposure_s": 0.0, "auto_exposure": False, "auto_exposure_target": 110.0,
               "auto_exposure_max_gain": 4.0},
    "odometry": {"left_radius_scale": 1.0, "right_radius_scale": 1.0, "separation_scale": 1.0},
    "randomize": {"pose_cm": 0.0, "yaw_deg": 0.0, "light_direction_deg": 0.0,
                  "light_intensity": 0.0, "color_jitter": 0.0},
    "robots": [],
    "objects": [],
    "base_events": [],
}

ROBOT_KINDS = ("faulty", "helper", "plain")


def load(source: str | Path | dict[str, Any]) -> dict[str, Any]:
    """Read a world: a dict or the path of a YAML world file."""
    if isinstance(source, dict):
        return copy.deepcopy(source)
    path = Path(source)
    with open(path, encoding="utf-8") as f:
        data = yaml.safe_load(f) or {}
    if not isinstance(data, dict):
        raise ValueError(f"{path}: a world file must be a mapping")
    return data


def _merge(defaults: dict[str, Any], given: dict[str, Any]) -> dict[str, Any]:
    out = copy.deepcopy(defaults)
    for key, value in given.items():
        if isinstance(value, dict) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _robot(entry: dict[str, Any]) -> dict[str, Any]:
    if "name" not in entry:
        raise ValueError(f"robot without a name: {entry}")
    kind = entry.get("kind", "plain")
    if kind not in ROBOT_KINDS:
        raise ValueError(f"robot {entry['name']}: kind must be one of {ROBOT_KINDS}")
    return {"name": str(entry["name"]), "kind": kind,
            "x": float(entry.get("x", 0.0)), "y": float(entry.get("y", 0.0)),
            "yaw": float(entry.get("yaw", 0.0)),
            "camera": bool(entry.get("camera", kind == "helper")),
            "cylinders": bool(entry.get("cylinders", kind == "faulty"))}


#: base_events kinds and the sides each can be raised on.
BASE_EVENT_SIDES = {"cliff": ("left", "center", "right"), "wheel_drop": ("left", "right")}


def _base_event(entry: dict[str, Any], robots: list[str]) -> dict[str, Any]:
    """A checked ``base_events`` entry (see the module docstring)."""
    kind, side = str(entry.get("kind")), str(entry.get("side", "center"))
    if entry.get("robot") not in robots:
        raise ValueError(f"base event {entry}: robot must be one of {robots}")
    if kind not in BASE_EVENT_SIDES or side not in BASE_EVENT_SIDES[kind]:
        raise ValueError(f"base event {entry}: kind must be one of {sorted(BASE_EVENT_SIDES)} "
                         f"with a side in {BASE_EVENT_SIDES.get(kind, BASE_EVENT_SIDES)}")
    at, duration = float(entry.get("at", 0.0)), float(entry.get("duration", 1.0))
    if not (at >= 0.0 and duration > 0.0):
        raise ValueError(f"base event {entry}: at must be >= 0 and duration > 0 (seconds)")
    return {"robot": entry["robot"], "kind": kind, "side": side, "at": at, "duration": duration}


def _jitter_color(rng: np.random.Generator, color: list[float], amount: float) -> list[float]:
    jittered = np.clip(np.asarray(color, float) + rng.uniform(-amount, amount, 3), 0.0, 1.0)
    return [float(c) for c in jittered]


def resolve(source: str | Path | dict[str, Any], seed: int | None = None) -> dict[str, Any]:
    """Defaults + world file + randomisation (if a seed is set) -> the concrete scene dict.

    ``seed`` overrides the file's seed. With a seed, the ``randomize`` amounts are applied:
    start poses get uniform jitter of ``pose_cm`` cm and ``yaw_deg`` degrees, the light direction
    turns by up to ``light_direction_deg``, ambient/diffuse scale by up to ±``light_intensity``
    (relative) and every colour (floor, walls, cylinders, objects) moves by up to
    ±``color_jitter`` per RGB channel. The same seed always gives the same scene.
    """
    cfg = _merge(DEFAULTS, load(source))
    if seed is not None:
        cfg["seed"] = int(seed)
    cfg["robots"] = [_robot(r) for r in cfg["robots"]]
    names = [r["name"] for r in cfg["robots"]]
    if len(set(names)) != len(names):
        raise ValueError(f"robot names must be unique: {names}")
    cfg["base_events"] = [_base_event(e, names) for e in cfg["base_events"]]
    if cfg["seed"] is None:
        return cfg
    rng = np.random.default_rng(cfg["seed"])
    rnd = cfg["randomize"]
    for robot in cfg["robots"]:
        robot["x"] += float(rng.uniform(-1, 1)) * rnd["pose_cm"] / 100.0
        robot["y"] += float(rng.uniform(-1, 1)) * rnd["pose_cm"] / 100.0
        robot["yaw"] += float(rng.uniform(-1, 1)) * rnd["yaw_deg"]
    light = cfg["lighting"]
    if rnd["light_direction_deg"]:
        light["direction"] = _turn_direction(rng, light["direction"], rnd["light_direction_deg"])
    for key in ("ambient", "diffuse"):
        light[key] = float(light[key] * (1.0 + rng.uniform(-1, 1) * rnd["light_intensity"]))
    jitter = rnd["color_jitter"]
    if jitter:
        cfg["floor"]["color"] = _jitter_color(rng, cfg["floor"]["color"], jitter)
        cfg["room"]["wall_color"] = _jitter_color(rng, cfg["room"]["wall_color"], jitter)
        for key in ("green", "orange"):
            cfg["cylinders"][key] = _jitter_color(rng, cfg["cylinders"][key], jitter)
        for obj in cfg["objects"]:
            if "color" in obj:
                obj["color"] = _jitter_color(rng, obj["color"], jitter)
    return cfg


def _turn_direction(rng: np.random.Generator, direction: list[float],
                    max_deg: float) -> list[float]:
    """The direction turned by a random angle up to ``max_deg`` about a random axis."""
    d = np.asarray(direction, float)
    d /= np.linalg.norm(d)
    axis = np.cross(d, rng.normal(size=3))
    axis /= np.linalg.norm(axis)
    angle = math.radians(rng.uniform(0, max_deg))
    turned = d * math.cos(angle) + np.cross(axis, d) * math.sin(angle)
    return [float(c) for c in turned]
