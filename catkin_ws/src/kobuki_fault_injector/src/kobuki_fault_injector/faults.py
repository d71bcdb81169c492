"""The fault maths of the Kobuki fault injector (thesis 6.3), without rospy.

Faults (one active at a time; a new one replaces the old one):

* ``left_actuator`` / ``right_actuator`` - a weak wheel. For a command that moves the base
  forward or backward (``linear.x != 0``) the thesis' case table applies (eqs. 6.2 and 6.3)::

      angular.z = +x   if left_actuator and x > 0, or right_actuator and x < 0
      angular.z = -x   if right_actuator and x > 0, or left_actuator and x < 0
      linear.x  = x / 2

  (``x`` is the commanded ``linear.x``; the commanded ``angular.z`` is replaced). Going forward
  the robot makes a smooth turn toward the faulty wheel: left fault -> +z, it curves left.
  Backward, the table turns the *heading* toward the faulty side too (left fault -> +z), which
  moves the base away from it (a weak physical wheel would curve it toward the faulty side,
  with the opposite z); we keep the thesis' table as written.

  Eq. 6.2 does not fit a pure rotation (``linear.x == 0``, ``angular.z != 0``): taken literally
  it sets ``angular.z = +-0``, so a robot with one weak wheel could not turn at all. Our model
  for that case works at wheel level: the commanded (v, w) is turned into wheel speeds
  (separation 0.230 m), the faulty wheel delivers only :data:`ROTATION_WHEEL_GAIN`
  (half) of its speed, and the wheel speeds are turned back into (v, w). A turn then runs at
  3/4 of the commanded rate while the centre drifts slowly along the healthy wheel's
  direction of travel (``|v| = |w| * L / 8``), so ``turn(deg)`` still completes by odometry, only
  slower; what gives an actuator fault away is the straight ``move``.
* ``both_actuators`` - all six velocity components are zeroed: the robot cannot move.
* ``odometry`` - a frozen encoder: odometry is held at the last value seen before the fault
  (if none was seen yet, at the first one that arrives). :class:`OdometryFreezer` keeps it;
  the node republishes its pose and twist with the live header stamp, so the topic stays
  alive while its values no longer change.
* ``cancel`` - clears the active fault; commands and odometry pass unchanged again.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field, replace
from typing import Generic, TypeVar

from turtlebot_model.kobuki import WHEEL_SEPARATION

LEFT_ACTUATOR = "left_actuator"
RIGHT_ACTUATOR = "right_actuator"
BOTH_ACTUATORS = "both_actuators"
ODOMETRY = "odometry"
CANCEL = "cancel"

#: The faults that can be injected, in the thesis' order.
FAULTS: tuple[str, ...] = (LEFT_ACTUATOR, RIGHT_ACTUATOR, BOTH_ACTUATORS, ODOMETRY)
#: Every name the service accepts.
VALID_REQUESTS: tuple[str, ...] = (*FAULTS, CANCEL)
#: What the status topic says when no fault is active.
NO_FAULT = "none"
#: The longest fault name a request may carry (the valid ones are far shorter): a longer one
#: is refused without being echoed in the reply or the log.
MAX_REQUEST_NAME = 64

#: Fraction of its commanded speed the faulty wheel delivers during a pure rotation.
ROTATION_WHEEL_GAIN = 0.5
#: |linear.x| below this (m/s) counts as "no forward/backward motion".
LINEAR_EPSILON = 1e-9


@dataclass(frozen=True)
class Velocity:
    """The six components of a ``geometry_msgs/Twist`` (linear x, y, z; angular x, y, z)."""

    linear_x: float = 0.0
    linear_y: float = 0.0
    linear_z: float = 0.0
    angular_x: float = 0.0
    angular_y: float = 0.0
    angular_z: float = 0.0


def wheel_speeds(v: float, w: float, separation: float = WHEEL_SEPARATION) -> tuple[float, float]:
    """(left, right) wheel rim speeds (m/s) of a differential drive moving at (v, w)."""
    half = w * separation / 2.0
    return v - half, v + half


def body_velocity(left: float, right: float,
                  separation: float = WHEEL_SEPARATION) -> tuple[float, float]:
    """(v, w) of a differential drive whose wheels move at (left, right) m/s."""
    return (left + right) / 2.0, (right - left) / separation


def actuator_fault(fault: str, cmd: Velocity) -> Velocity:
    """The command a base with a faulty `fault` actuator (left/right) actually executes.

    Forward/backward commands follow eqs. 6.2/6.3; pure rotations the wheel-level model
    (module docstring). Components other than linear.x and angular.z pass unchanged.
    """
    if fault not in (LEFT_ACTUATOR, RIGHT_ACTUATOR):
        raise ValueError(f"not an actuator fault: {fault!r}")
    x = cmd.linear_x
    if abs(x) > LINEAR_EPSILON:
        turn_left = (fault == LEFT_ACTUATOR) == (x > 0)      # eq. 6.2's first case
        z = x if turn_left else -x
        return replace(cmd, linear_x=x / 2.0, angular_z=z)   # eq. 6.3
    left, right = wheel_speeds(x, cmd.angular_z)
    if fault == LEFT_ACTUATOR:
        left *= ROTATION_WHEEL_GAIN
    else:
        right *= ROTATION_WHEEL_GAIN
    v, w = body_velocity(left, right)
    return replace(cmd, linear_x=v, angular_z=w)


def apply_fault(fault: str | None, cmd: Velocity) -> Velocity:
    """The velocity command forwarded to the base while `fault` (or None) is active."""
    if fault in (LEFT_ACTUATOR, RIGHT_ACTUATOR):
        return actuator_fault(fault, cmd)
    if fault == BOTH_ACTUATORS:
        return Velocity()
    return cmd


T = TypeVar("T")


class OdometryFreezer(Generic[T]):
    """Holds the odometry message to publish while the encoder fault is active.

    Feed every incoming message to :meth:`filter`; it returns the message itself while the
    encoders are healthy and the one frozen at :meth:`freeze` time while they are not.
    Generic over the message type, so it is tested without ROS.
    """

    def __init__(self) -> None:
        self.last: T | None = None
        self.frozen: T | None = None
        self.active = False

    def freeze(self) -> None:
        """Start the fault: hold the last message seen (or the next one, if none yet)."""
        self.active = True
        self.frozen = self.last

    def release(self) -> None:
        """End the fault: pass messages through again."""
        self.active = False
        self.frozen = None

    def filter(self, msg: T) -> T:
        """The message to publish in place of `msg`."""
        if not self.active:
            self.last = msg
            return msg
        if self.frozen is None:
            self.frozen = msg
        return self.frozen


@dataclass
class FaultState:
    """The active fault and the service's answers; the node only translates messages.

    Args:
        on_change: called with the new active fault (None = no fault) whenever it changes.
    """

    active: str | None = None
    on_change: Callable[[str | None], None] | None = None
    odometry: OdometryFreezer = field(default_factory=OdometryFreezer)

    @property
    def status(self) -> str:
        """The active fault's name, or ``none``."""
        return self.active or NO_FAULT

    def request(self, name: str) -> str:
        """Handle a service request `name`; return the service's ``return_message``.

        An unknown name changes nothing and lists the valid ones; one longer than
        MAX_REQUEST_NAME is not echoed back.
        """
        name = name.strip()
        if len(name) > MAX_REQUEST_NAME:
            return (f"error: fault name too long ({len(name):,} characters, at most "
                    f"{MAX_REQUEST_NAME}); valid faults: {', '.join(VALID_REQUESTS)} "
                    f"(active fault unchanged: {self.status})")
        if name not in VALID_REQUESTS:
            return (f"error: unknown fault '{name}'; valid faults: {', '.join(VALID_REQUESTS)} "
                    f"(active fault unchanged: {self.status})")
        previous = self.active
        new = None if name == CANCEL else name
        if new == ODOMETRY and previous != ODOMETRY:
            self.odometry.freeze()
        elif new != ODOMETRY and previous == ODOMETRY:
            self.odometry.release()
        self.active = new
        if new != previous and self.on_change is not None:
            self.on_change(new)
        if new is None:
            return f"fault cancelled (was: {previous or NO_FAULT})"
        suffix = f" (replaces {previous})" if previous and previous != new else ""
        return f"fault '{new}' injected{suffix}"

    def command(self, cmd: Velocity) -> Velocity:
        """The velocity command to forward to the base."""
        return apply_fault(self.active, cmd)

    def odom(self, msg: T) -> T:
        """The odometry message to forward to the robot's consumers."""
        return self.odometry.filter(msg)
