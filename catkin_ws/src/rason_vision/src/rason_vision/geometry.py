"""Angles, the yaw sign convention, and the Faulty robot's marker layout (no ROS, no OpenCV).

Frames
------
Everything the detector measures is in Helper's Kinect *optical* frame: x right, y down,
z forward. Only the horizontal plane (x, z) matters for the perception; seen from above, an
angle measured from the optical axis (+z) towards +x is **clockwise** ("to the right").

Conventions of the perception ``robot(Name, Angle, Depth, Yaw)``
----------------------------------------------------------------
* ``Angle`` (deg): bearing of Faulty's centre (the midpoint of the two cylinder axes),
  ``atan2(x, z)``; negative = left of the observer, positive = right (thesis 6.2). It is the
  exact pinhole angle ``atan((u - cx0) / fx)`` of the column ``u`` the midpoint projects to.
* ``Depth`` (m): mean of the two cylinder axes' depths along the optical axis (their ``z``),
  i.e. the thesis' ``(c1 + c2) / 2`` with each centroid taken on the cylinder axis.
* ``Yaw`` (deg): ``wrap(heading + Angle)``, where ``heading`` is the direction Faulty faces,
  measured in the same rotational sense as ``Angle`` (clockwise seen from above, towards the
  image's right) from the optical axis: 0 = facing straight away from Helper's camera,
  +90 = facing the image's right, -90 = facing the image's left, 180 = facing the camera.

Why ``heading + Angle`` and not ``heading - Angle`` (the "heading relative to the line of
sight")? Faulty's diagnosis rule is ``Yaw1 - (Yaw + (Deg1 - Deg))``: a straight move must
leave it at 0 and a curve to Faulty's right (clockwise, a right-actuator fault) must make it
positive. Over a move, ``heading`` changes by the turn ``dH`` and ``Angle`` by ``dA``; the rule
then reads ``dYaw - dA``. With ``Yaw = heading + Angle`` that is exactly ``dH``: 0 when going
straight, > 0 when curving right, < 0 when curving left. ``heading - Angle`` would give
``dH - 2 dA`` (a straight move across the view would look like a turn), and ``Angle -
heading`` gives ``-dH`` (right and left swapped). So the rule fixes the convention; for a
robot on the optical axis (Angle 0) yaw is simply its heading as seen by the camera.
In the case study (Helper looking at Faulty's left flank) yaw is about -90.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from turtlebot_model.geometry import wrap_deg

#: Distance between the two cylinder axes on Faulty (m), thesis 6.2.
CYLINDER_SPACING = 0.227
#: Cylinder radius (m).
CYLINDER_RADIUS = 0.03
#: Lateral offset of each cylinder axis from Faulty's centre, robot frame y (m): green +, orange -.
CYLINDER_OFFSET = CYLINDER_SPACING / 2.0
#: Kinect horizontal field of view (deg) and the thesis' half-angle.
KINECT_HFOV_DEG = 57.0
THESIS_HALF_FOV_DEG = 28.5


def bearing_deg(x: float, z: float) -> float:
    """Bearing of an optical-frame point in the horizontal plane (deg, + = right)."""
    return math.degrees(math.atan2(x, z))


def heading_from_pair_deg(green_xz: tuple[float, float], orange_xz: tuple[float, float]) -> float:
    """Faulty's heading in the camera's horizontal plane (deg, clockwise from +z).

    Green sits on Faulty's left, orange on its right, so ``green - orange`` points to Faulty's
    left; its forward direction is that vector turned 90 deg clockwise (to the right).
    """
    lx = green_xz[0] - orange_xz[0]
    lz = green_xz[1] - orange_xz[1]
    return wrap_deg(math.degrees(math.atan2(lx, lz)) + 90.0)


def yaw_deg(heading: float, angle: float) -> float:
    """The published yaw: ``wrap(heading + angle)`` (see the module docstring)."""
    return wrap_deg(heading + angle)


def thesis_angle_deg(u: float, width: int) -> float:
    """The thesis' linear angle ``(u - w/2) / (w/2) * 28.5`` for image column ``u``."""
    half = width / 2.0
    return (u - half) / half * THESIS_HALF_FOV_DEG


@dataclass(frozen=True)
class Intrinsics:
    """Pinhole intrinsics of a camera (pixel-index coordinates). The defaults are the
    simulator's Kinect (57 deg wide); the node takes the real ones from camera_info."""

    width: int = 640
    height: int = 480
    fx: float = 589.4
    fy: float = 589.4
    cx: float = 319.5
    cy: float = 239.5

    @classmethod
    def from_fov(cls, width: int = 640, height: int = 480,
                 hfov_deg: float = KINECT_HFOV_DEG) -> Intrinsics:
        """Square pixels, principal point at the image centre, focal length from the FOV."""
        f = (width / 2.0) / math.tan(math.radians(hfov_deg / 2.0))
        return cls(width, height, f, f, (width - 1) / 2.0, (height - 1) / 2.0)

    def pinhole_angle_deg(self, u: float) -> float:
        """Exact horizontal angle of image column ``u``: ``atan((u - cx) / fx)``."""
        return math.degrees(math.atan((u - self.cx) / self.fx))


#: A real Kinect v1 at VGA as openni / freenect describe it by default (their camera_info).
KINECT_VGA = Intrinsics(640, 480, 525.0, 525.0, 319.5, 239.5)


@dataclass(frozen=True)
class Relative:
    """Faulty as seen from Helper's camera: what the perception reports."""

    angle: float
    depth: float
    yaw: float
    heading: float

    def literal(self, name: str = "faulty") -> str:
        """The Jason literal, e.g. ``robot(faulty,-3.2,1.52,-88.0)``."""
        return format_literal(name, self.angle, self.depth, self.yaw)


def format_literal(name: str, angle: float, depth: float, yaw: float) -> str:
    """``robot(name,Angle,Depth,Yaw)``: degrees with 1 decimal, metres with 2."""
    def clean(value: float, digits: int) -> str:
        text = f"{value:.{digits}f}"
        return "0." + "0" * digits if text.strip("-0.") == "" else text
    return f"robot({name},{clean(angle, 1)},{clean(depth, 2)},{clean(yaw, 1)})"


def format_partial_literal(name: str, angle: float, depth: float, colour: str) -> str:
    """``robot_partial(name,Angle,Depth,Colour)``: one cylinder seen, Faulty's yaw unknown."""
    text = format_literal(name, angle, depth, 0.0)
    return "robot_partial" + text[len("robot"):text.rindex(",")] + f",{colour})"


def relative_from_axes(green_xz: tuple[float, float],
                       orange_xz: tuple[float, float]) -> Relative:
    """Angle, depth, yaw and heading from the two cylinder axes (optical frame x, z)."""
    mx = (green_xz[0] + orange_xz[0]) / 2.0
    mz = (green_xz[1] + orange_xz[1]) / 2.0
    angle = bearing_deg(mx, mz)
    heading = heading_from_pair_deg(green_xz, orange_xz)
    return Relative(angle=angle, depth=mz, yaw=yaw_deg(heading, angle), heading=heading)


def cylinder_axes_in_camera(cam_x: float, cam_y: float, cam_yaw: float, faulty_x: float,
                            faulty_y: float, faulty_yaw: float,
                            offset: float = CYLINDER_OFFSET
                            ) -> tuple[tuple[float, float], tuple[float, float]]:
    """Green and orange axes in the camera's (x, z) from planar world poses.

    World frame: x forward, y left, yaw counter-clockwise (REP 103), radians. The camera sits
    at ``(cam_x, cam_y)`` looking along ``cam_yaw``; its optical x is the world's "right".
    """
    out = []
    for side in (+1.0, -1.0):
        wx = faulty_x - side * offset * math.sin(faulty_yaw)
        wy = faulty_y + side * offset * math.cos(faulty_yaw)
        dx, dy = wx - cam_x, wy - cam_y
        forward = dx * math.cos(cam_yaw) + dy * math.sin(cam_yaw)
        left = -dx * math.sin(cam_yaw) + dy * math.cos(cam_yaw)
        out.append((-left, forward))
    return out[0], out[1]
