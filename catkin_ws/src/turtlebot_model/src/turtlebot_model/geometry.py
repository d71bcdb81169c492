"""Planar angles: yaw from a quaternion, wrapping, and wrap-safe differences."""

from __future__ import annotations

import math


def yaw_from_quaternion(x: float, y: float, z: float, w: float) -> float:
    """The heading (rotation about z) of a quaternion, in radians, in (-pi, pi]."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


def wrap_rad(angle: float) -> float:
    """An angle in radians wrapped into (-pi, pi], as :func:`wrap_deg` (one convention)."""
    wrapped = math.fmod(angle, 2.0 * math.pi)
    if wrapped <= -math.pi:
        wrapped += 2.0 * math.pi
    elif wrapped > math.pi:
        wrapped -= 2.0 * math.pi
    return wrapped


def wrap_deg(angle: float) -> float:
    """An angle in degrees wrapped into (-180, 180]."""
    wrapped = math.fmod(angle, 360.0)
    if wrapped <= -180.0:
        wrapped += 360.0
    elif wrapped > 180.0:
        wrapped -= 360.0
    return wrapped


def angle_diff_deg(a: float, b: float) -> float:
    """``a - b`` in degrees, wrapped into (-180, 180]: the shortest turn from ``b`` to ``a``."""
    return wrap_deg(a - b)
