"""Comparing detections with the bags' ground truth (shared by the vision tests)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

from turtlebot_model.geometry import wrap_deg

#: The repository's committed bags (tests run from the source tree).
BAGS = Path(__file__).resolve().parents[2] / "bags"
#: The committed bags: the heading sweep and the special cases (the ROS test plays the latter).
SWEEP_BAG = BAGS / "vision_sweep.bag"
CASES_BAG = BAGS / "vision_cases.bag"
#: The cases as a Kinect driver gives them (Bayer + 16UC1 depth + camera_info) and compressed.
KINECT_BAG = BAGS / "vision_cases_kinect.bag"
COMPRESSED_BAG = BAGS / "vision_cases_compressed.bag"
ANGLE_TOL, DEPTH_TOL, YAW_TOL = 1.0, 0.03, 8.0
LITERAL = re.compile(r"^robot\((\w+),(-?\d+\.\d),(-?\d+\.\d\d),(-?\d+\.\d)\)$")
PARTIAL = re.compile(r"^robot_partial\((\w+),(-?\d+\.\d),(-?\d+\.\d\d),(green|orange)\)$")


def errors(angle: float, depth: float, yaw: float, truth: dict[str, Any]) -> tuple[float, ...]:
    """Absolute angle, depth and yaw errors against a ground-truth record."""
    return (abs(angle - truth["angle"]), abs(depth - truth["depth"]),
            abs(wrap_deg(yaw - truth["yaw"])))


def check(found: tuple[float, float, float] | None, truth: dict[str, Any],
          slack: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> str | None:
    """None when a detection (angle, depth, yaw) or its absence agrees with the truth."""
    expect = truth["expect"]
    if found is None:
        return "missed" if expect == "robot" else None
    if expect == "none":
        return "false positive"
    both_visible = truth["green_px"] > 0 and truth["orange_px"] > 0
    if not both_visible:
        return None
    errs = errors(*found, truth)
    tols = (ANGLE_TOL + slack[0], DEPTH_TOL + slack[1], YAW_TOL + slack[2])
    if any(e > t for e, t in zip(errs, tols, strict=True)):
        return f"errors {tuple(round(e, 3) for e in errs)} beyond {tols}"
    return None
