"""The Kobuki base (TurtleBot 2): geometry, drive limits, wheel-encoder odometry, pybullet body.

Frames: the robot's body frame is ``base_footprint``: origin on the floor under the wheel axle
centre, x forward, y left, z up. All lengths in metres, angles in radians unless named ``_deg``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import pybullet as p

from turtlebot_model.kobuki import (
    BODY_BOTTOM,
    BODY_RADIUS,
    BODY_TOP,
    CASTER_RADIUS,
    WHEEL_RADIUS,
    WHEEL_SEPARATION,
    WHEEL_WIDTH,
)

# -- Kobuki geometry and limits not in the shared model (Yujin's data sheet) ----------------------
CASTER_X = 0.115
BASE_MASS = 2.35
STACK_MASS = 1.2          # plates, poles (TurtleBot 2 hardware)
KINECT_MASS = 0.5
WHEEL_MASS = 0.12
TICKS_PER_REV = 2578.33   # kobuki encoder ticks per wheel revolution
MAX_V = 0.7               # m/s
MAX_W = math.pi           # rad/s (180 deg/s)
ACCEL_V = 1.0             # m/s^2
ACCEL_W = 4.0             # rad/s^2
WHEEL_MAX_TORQUE = 1.5    # N m (motor + gearbox stall torque, generous)

# -- TurtleBot 2 stack and the payloads (decided geometry, see README) -------------------------
PLATE_RADIUS = 0.16
PLATE_HEIGHTS = (0.135, 0.265, 0.40)   # plate tops; the top plate is at z = 0.40
PLATE_THICKNESS = 0.008
CYLINDER_Y = 0.1135                    # green at +y (left), orange at -y (right): 22.7 cm apart
CYLINDER_RADIUS = 0.03
GREEN_HEIGHT, ORANGE_HEIGHT = 0.10, 0.20   # tops at 0.50 and 0.60
KINECT_OPTICAL = (0.135, 0.0, 0.45)     # optical centre in base_footprint, looking along +x
KINECT_BOX = (0.06, 0.28, 0.04)         # size x, y, z of the visual housing
BODY_COLOR = (0.16, 0.16, 0.17, 1.0)
PLATE_COLOR = (0.05, 0.05, 0.05, 1.0)
POLE_COLOR = (0.30, 0.30, 0.31, 1.0)
KINECT_COLOR = (0.08, 0.08, 0.08, 1.0)


def clamp(value: float, low: float, high: float) -> float:
    return max(low, min(high, value))


def wheel_speeds(v: float, w: float) -> tuple[float, float]:
    """Twist (m/s, rad/s) -> (left, right) wheel angular speeds (rad/s), wheel speed limited.

    When a wheel would exceed ``MAX_V`` both are scaled down so the curvature is kept.
    """
    left = v - w * WHEEL_SEPARATION / 2.0
    right = v + w * WHEEL_SEPARATION / 2.0
    peak = max(abs(left), abs(right))
    if peak > MAX_V:
        left, right = left * MAX_V / peak, right * MAX_V / peak
    return left / WHEEL_RADIUS, right / WHEEL_RADIUS


@dataclass
class DriveController:
    """Turns the commanded Twist into wheel speed targets with speed and acceleration limits."""

    cmd_v: float = 0.0
    cmd_w: float = 0.0
    v: float = 0.0
    w: float = 0.0

    def command(self, v: float, w: float) -> None:
        """Set the commanded Twist; clamped to ±MAX_V and ±MAX_W."""
        self.cmd_v = clamp(float(v), -MAX_V, MAX_V)
        self.cmd_w = clamp(float(w), -MAX_W, MAX_W)

    def update(self, dt: float) -> tuple[float, float]:
        """Advance the ramp by ``dt``; return the (left, right) wheel speed targets in rad/s."""
        self.v += clamp(self.cmd_v - self.v, -ACCEL_V * dt, ACCEL_V * dt)
        self.w += clamp(self.cmd_w - self.w, -ACCEL_W * dt, ACCEL_W * dt)
        return wheel_speeds(self.v, self.w)

    def reset(self) -> None:
        self.cmd_v = self.cmd_w = self.v = self.w = 0.0


@dataclass
class WheelOdometry:
    """Dead reckoning from quantised wheel encoders, as kobuki_node does (no gyro).

    The odometry frame is the robot's pose when the odometry was (re)started: (0, 0, 0).
    ``*_scale`` model a calibration error (the odometry's assumed wheel radii and separation
    are the true ones times these factors).
    """

    left_radius_scale: float = 1.0
    right_radius_scale: float = 1.0
    separation_scale: float = 1.0
    x: float = 0.0
    y: float = 0.0
    yaw: float = 0.0
    v: float = 0.0
    w: float = 0.0
    _ticks: tuple[int, int] | None = field(default=None, repr=False)

    @staticmethod
    def ticks(angle: float) -> int:
        """Encoder count of a wheel turned by ``angle`` radians."""
        return math.floor(angle / (2.0 * math.pi) * TICKS_PER_REV)

    def reset(self) -> None:
        self.x = self.y = self.yaw = self.v = self.w = 0.0
        self._ticks = None

    def update(self, left_angle: float, right_angle: float, dt: float) -> None:
        """Integrate the wheels' motion since the last call (angles in rad, unwrapped)."""
        ticks = (self.ticks(left_angle), self.ticks(right_angle))
        if self._ticks is None:
            self._ticks = ticks
            return
        per_tick = 2.0 * math.pi / TICKS_PER_REV
        d_left = (ticks[0] - self._ticks[0]) * per_tick * WHEEL_RADIUS * self.left_radius_scale
        d_right = (ticks[1] - self._ticks[1]) * per_tick * WHEEL_RADIUS * self.right_radius_scale
        self._ticks = ticks
        distance = (d_left + d_right) / 2.0
        turn = (d_right - d_left) / (WHEEL_SEPARATION * self.separation_scale)
        mid = self.yaw + turn / 2.0
        self.x += distance * math.cos(mid)
        self.y += distance * math.sin(mid)
        self.yaw = math.atan2(math.sin(self.yaw + turn), math.cos(self.yaw + turn))
        if dt > 0:
            self.v, self.w = distance / dt, turn / dt


@dataclass
class RobotBody:
    """Handles of one robot's pybullet multibody."""

    body: int
    left_joint: int
    right_joint: int
    camera: bool
    cylinders: bool


def _visual(client: int, shape: int, color: tuple[float, ...], **kw: object) -> int:
    return p.createVisualShape(shape, rgbaColor=list(color), physicsClientId=client, **kw)


def build_robot(client: int, position: tuple[float, float], yaw: float, *, camera: bool,
                cylinders: bool, green: tuple[float, ...] = (0.1, 0.62, 0.18, 1.0),
                orange: tuple[float, ...] = (1.0, 0.45, 0.05, 1.0)) -> RobotBody:
    """Create a TurtleBot 2 (Kobuki + plates) at ``position`` (x, y) with heading ``yaw`` (rad).

    The base link holds the body disc and the two low-friction caster spheres; the wheels are
    revolute links (axis +y) driven by velocity motors. Plates, poles, coloured cylinders and
    the Kinect are fixed links (the payloads have no collision shapes).
    """
    c = client
    body_h = BODY_TOP - BODY_BOTTOM
    base_col = p.createCollisionShapeArray(
        [p.GEOM_CYLINDER, p.GEOM_SPHERE, p.GEOM_SPHERE],
        radii=[BODY_RADIUS, CASTER_RADIUS, CASTER_RADIUS], lengths=[body_h, 0, 0],
        collisionFramePositions=[[0, 0, BODY_BOTTOM + body_h / 2],
                                 [CASTER_X, 0, CASTER_RADIUS], [-CASTER_X, 0, CASTER_RADIUS]],
        physicsClientId=c)
    base_vis = _visual(c, p.GEOM_CYLINDER, BODY_COLOR, radius=BODY_RADIUS, length=body_h,
                       visualFramePosition=[0, 0, BODY_BOTTOM + body_h / 2])
    wheel_rot = p.getQuaternionFromEuler([math.pi / 2, 0, 0])
    wheel_col = p.createCollisionShape(p.GEOM_CYLINDER, radius=WHEEL_RADIUS, height=WHEEL_WIDTH,
                                       collisionFrameOrientation=wheel_rot, physicsClientId=c)
    wheel_vis = _visual(c, p.GEOM_CYLINDER, PLATE_COLOR, radius=WHEEL_RADIUS, length=WHEEL_WIDTH,
                        visualFrameOrientation=wheel_rot)

    # The stack: three plates and four poles, one link of one colour per part kind.
    stack_z = (PLATE_HEIGHTS[-1] + BODY_TOP) / 2
    plate_vis = p.createVisualShapeArray(
        [p.GEOM_CYLINDER] * 3, radii=[PLATE_RADIUS] * 3, lengths=[PLATE_THICKNESS] * 3,
        visualFramePositions=[[0, 0, h - PLATE_THICKNESS / 2 - stack_z] for h in PLATE_HEIGHTS],
        physicsClientId=c)
    pole_xy = [(0.09, 0.09), (0.09, -0.09), (-0.09, 0.09), (-0.09, -0.09)]
    pole_len = PLATE_HEIGHTS[-1] - BODY_TOP
    pole_vis = p.createVisualShapeArray(
        [p.GEOM_CYLINDER] * 4, radii=[0.006] * 4, lengths=[pole_len] * 4,
        visualFramePositions=[[x, y, BODY_TOP + pole_len / 2 - stack_z] for x, y in pole_xy],
        physicsClientId=c)
    stack_col = p.createCollisionShape(p.GEOM_CYLINDER, radius=PLATE_RADIUS,
                                       height=PLATE_HEIGHTS[-1] - BODY_TOP,
                                       collisionFramePosition=[0, 0, 0], physicsClientId=c)

    masses = [WHEEL_MASS, WHEEL_MASS, STACK_MASS, 0.001]
    cols = [wheel_col, wheel_col, stack_col, -1]
    vis = [wheel_vis, wheel_vis, plate_vis, pole_vis]
    pos = [[0, WHEEL_SEPARATION / 2, WHEEL_RADIUS], [0, -WHEEL_SEPARATION / 2, WHEEL_RADIUS],
           [0, 0, stack_z], [0, 0, stack_z]]
    types = [p.JOINT_REVOLUTE, p.JOINT_REVOLUTE, p.JOINT_FIXED, p.JOINT_FIXED]
    colors: list[tuple[float, ...]] = [PLATE_COLOR, PLATE_COLOR, PLATE_COLOR, POLE_COLOR]
    if cylinders:
        top = PLATE_HEIGHTS[-1]
        for y, height, color in ((CYLINDER_Y, GREEN_HEIGHT, green),
                                 (-CYLINDER_Y, ORANGE_HEIGHT, orange)):
            masses.append(0.001)
            cols.append(-1)
            vis.append(_visual(c, p.GEOM_CYLINDER, color, radius=CYLINDER_RADIUS, length=height))
            pos.append([0, y, top + height / 2])
            types.append(p.JOINT_FIXED)
            colors.append(tuple(color))
    if camera:
        ox, _, oz = KINECT_OPTICAL
        masses.append(0.001)
        cols.append(-1)
        vis.append(p.createVisualShapeArray(
            [p.GEOM_BOX, p.GEOM_BOX],
            halfExtents=[[s / 2 for s in KINECT_BOX], [0.02, 0.03, (oz - PLATE_HEIGHTS[-1]) / 2]],
            visualFramePositions=[[ox - KINECT_BOX[0] / 2 - 0.002, 0, oz],
                                  [ox - KINECT_BOX[0] / 2, 0, (oz + PLATE_HEIGHTS[-1]) / 2]],
            physicsClientId=c))
        pos.append([0, 0, 0])
        types.append(p.JOINT_FIXED)
        colors.append(KINECT_COLOR)
    n = len(masses)
    body = p.createMultiBody(
        baseMass=BASE_MASS, baseCollisionShapeIndex=base_col, baseVisualShapeIndex=base_vis,
        basePosition=[position[0], position[1], 0.0],
        baseOrientation=p.getQuaternionFromEuler([0, 0, yaw]),
        linkMasses=masses, linkCollisionShapeIndices=cols, linkVisualShapeIndices=vis,
        linkPositions=pos, linkOrientations=[[0, 0, 0, 1]] * n,
        linkInertialFramePositions=[[0, 0, 0]] * n, linkInertialFrameOrientations=[[0, 0, 0, 1]] * n,
        linkParentIndices=[0] * n, linkJointTypes=types,
        linkJointAxis=[[0, 1, 0]] * 2 + [[0, 0, 1]] * (n - 2), physicsClientId=c)
    for link, color in enumerate(colors):
        p.changeVisualShape(body, link, rgbaColor=list(color), physicsClientId=c)
    p.changeVisualShape(body, -1, rgbaColor=list(BODY_COLOR), physicsClientId=c)
    # Casters (the base's contacts with the floor) slide freely; the wheels grip.
    p.changeDynamics(body, -1, lateralFriction=0.0, spinningFriction=0.0, rollingFriction=0.0,
                     restitution=0.0, physicsClientId=c)
    for wheel in (0, 1):
        p.changeDynamics(body, wheel, lateralFriction=1.2, spinningFriction=0.001,
                         rollingFriction=0.0, restitution=0.0, jointDamping=0.0,
                         physicsClientId=c)
    p.setJointMotorControlArray(body, [0, 1], p.VELOCITY_CONTROL, targetVelocities=[0, 0],
                                forces=[WHEEL_MAX_TORQUE] * 2, physicsClientId=c)
    return RobotBody(body=body, left_joint=0, right_joint=1, camera=camera, cylinders=cylinders)
