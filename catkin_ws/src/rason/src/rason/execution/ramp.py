"""Speed profile of the motion decomposer: accelerate, cruise, brake to a stop at the goal.

Pure arithmetic (no rospy). The same profile serves linear (m, m/s) and angular (rad, rad/s)
motion: the next speed is the smallest of the cruise speed, the last speed plus the allowed
acceleration, and the speed from which the robot can still brake within the remaining
distance (``sqrt(2 * decel * remaining)``), but never below a creep speed while any distance
remains, so friction near the goal cannot stall the robot before it arrives.
"""

from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class SpeedLimits:
    """Cruise speed, creep speed near the goal, acceleration and braking deceleration."""

    max_speed: float
    min_speed: float
    accel: float
    decel: float

    def __post_init__(self) -> None:
        if not 0.0 < self.min_speed <= self.max_speed or self.accel <= 0 or self.decel <= 0:
            raise ValueError(f"inconsistent speed limits: {self}")


def next_speed(current: float, remaining: float, dt: float, limits: SpeedLimits) -> float:
    """The speed magnitude (>= 0) to command next.

    Args:
        current: magnitude of the last commanded speed.
        remaining: distance (or angle) still to go; <= 0 means stop.
        dt: time since the last command (s), clamped to [0, 0.2] against clock jumps.
    """
    if remaining <= 0.0:
        return 0.0
    dt = min(max(dt, 0.0), 0.2)
    ramp_up = abs(current) + limits.accel * dt
    brake = math.sqrt(2.0 * limits.decel * remaining)
    return max(limits.min_speed, min(limits.max_speed, ramp_up, brake))
