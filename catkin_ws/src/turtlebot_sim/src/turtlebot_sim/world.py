"""The simulated world: TurtleBot 2 robots on a floor in a room, stepped by pybullet (DIRECT).

No ROS here; the ROS node (:mod:`turtlebot_sim.node`) wraps this. Typical use::

    world = World.from_yaml("my_lab.yaml")
    world.set_cmd_vel("faulty", 0.2, 0.0)
    while world.time < 5.0:
        world.step()
    x, y, yaw = world.pose("faulty")              # ground truth (world frame)
    ox, oy, oyaw, v, w = world.odometry("faulty")  # wheel encoders (odom frame)
    rgb, xyz = world.render_kinect("helper")
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pybullet as p

from turtlebot_sim import config as worldcfg
from turtlebot_sim import kinect, kobuki, room

#: A robot's base state for re-posing a copy of the scene: position (x, y, z) and quaternion.
BaseState = tuple[tuple[float, float, float], tuple[float, float, float, float]]
#: A contact counts when the bodies are closer than this (m; pybullet reports touching as <= 0).
CONTACT_DISTANCE = 0.001


@dataclass(frozen=True)
class WheelState:
    """The two wheel joints: angles (rad, unwrapped) and rates (rad/s)."""

    left_angle: float
    right_angle: float
    left_rate: float
    right_rate: float


class Robot:
    """One robot: its pybullet body, drive controller, wheel odometry and wheel faults."""

    def __init__(self, name: str, kind: str, body: kobuki.RobotBody,
                 odometry: kobuki.WheelOdometry):
        self.name = name
        self.kind = kind
        self.body = body
        self.drive = kobuki.DriveController()
        self.odometry = odometry
        #: Multipliers of the wheel speed targets (0 = a blocked wheel), for tests and faults.
        self.wheel_scale = (1.0, 1.0)


class World:
    """A pybullet scene built from a resolved world config (see :mod:`turtlebot_sim.config`).

    Args:
        cfg: a resolved config (from :func:`turtlebot_sim.config.resolve`).
        render_only: build the same scene for rendering only (the render worker); no stepping.
    """

    def __init__(self, cfg: dict[str, Any], render_only: bool = False):
        self.config = cfg
        self.render_only = render_only
        self.dt = float(cfg["physics"]["dt"])
        self.time = 0.0
        self.steps = 0
        self.client = p.connect(p.DIRECT)
        c = self.client
        p.setGravity(0, 0, -9.81, physicsClientId=c)
        p.setPhysicsEngineParameter(fixedTimeStep=self.dt, numSubSteps=0, numSolverIterations=50,
                                    physicsClientId=c)
        self._build_room()
        self.robots: dict[str, Robot] = {}
        green = (*cfg["cylinders"]["green"], 1.0)
        orange = (*cfg["cylinders"]["orange"], 1.0)
        odo = cfg["odometry"]
        for r in cfg["robots"]:
            body = kobuki.build_robot(c, (r["x"], r["y"]), math.radians(r["yaw"]),
                                      camera=r["camera"], cylinders=r["cylinders"],
                                      green=green, orange=orange)
            odometry = kobuki.WheelOdometry(left_radius_scale=odo["left_radius_scale"],
                                            right_radius_scale=odo["right_radius_scale"],
                                            separation_scale=odo["separation_scale"])
            self.robots[r["name"]] = Robot(r["name"], r["kind"], body, odometry)
        cam = cfg["camera"]
        self.intrinsics = kinect.Intrinsics(int(cam["width"]), int(cam["height"]),
                                            float(cam["hfov_deg"]))
        self.noise = kinect.NoiseModel.from_config(cam)
        self._projection = self.intrinsics.projection_matrix()
        intr = self.intrinsics
        self._ray_x = (np.arange(intr.width, dtype=np.float32) - intr.cx) / intr.fx
        self._ray_y = (np.arange(intr.height, dtype=np.float32) - intr.cy) / intr.fy
        seed = cfg["seed"] if cfg["seed"] is not None else 0
        self._render_rng = np.random.default_rng([int(seed), 1])
        #: Last raw render per camera robot, keyed by the scene's (rounded) robot poses: a
        #: still scene is not rendered again (only the sensor noise is drawn anew).
        self._raw_cache: dict[str, tuple[tuple, np.ndarray, np.ndarray]] = {}
        self.renders = 0          # TinyRenderer calls made (cache misses)
        if not render_only:
            self._settle()

    @classmethod
    def from_yaml(cls, source: str | Path | dict[str, Any], seed: int | None = None,
                  **kwargs: Any) -> World:
        """Build a world from a YAML file (path or name in ``worlds/``) or a dict."""
        return cls(worldcfg.resolve(source, seed), **kwargs)

    # -- scene --------------------------------------------------------------------------------
    def _build_room(self) -> None:
        """Floor and walls (collision bodies; visuals drawn by TinyRenderer or ray casting)."""
        c, cfg = self.client, self.config
        sx, sy = cfg["room"]["size"]
        height, light = float(cfg["room"]["wall_height"]), cfg["lighting"]
        # A body without a visual shape is drawn from its collision shape: give the collision
        # bodies a speck of a visual far below the floor instead.
        hidden = p.createVisualShape(p.GEOM_SPHERE, radius=1e-3, visualFramePosition=[0, 0, -50],
                                     physicsClientId=c)
        self.floor = p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE, physicsClientId=c),
                                       hidden, physicsClientId=c)
        p.changeDynamics(self.floor, -1, lateralFriction=1.0, restitution=0.0,
                         physicsClientId=c)
        visuals = [p.createMultiBody(0, -1, p.createVisualShape(
            p.GEOM_BOX, halfExtents=[sx / 2, sy / 2, 0.005], visualFramePosition=[0, 0, -0.005],
            rgbaColor=[*cfg["floor"]["color"], 1.0], physicsClientId=c), physicsClientId=c)]
        color, t = [*cfg["room"]["wall_color"], 1.0], 0.05
        for (x, y), (hx, hy) in (((sx / 2 + t, 0), (t, sy / 2 + 2 * t)),
                                 ((-sx / 2 - t, 0), (t, sy / 2 + 2 * t)),
                                 ((0, sy / 2 + t), (sx / 2, t)),
                                 ((0, -sy / 2 - t), (sx / 2, t))):
            half = [hx, hy, height / 2]
            p.createMultiBody(0, p.createCollisionShape(p.GEOM_BOX, halfExtents=half,
                                                        physicsClientId=c),
                              hidden, basePosition=[x, y, height / 2], physicsClientId=c)
            visuals.append(p.createMultiBody(
                0, -1, p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=color,
                                           physicsClientId=c),
                basePosition=[x, y, height / 2], physicsClientId=c))
        self.room: room.Room | None = None
        if cfg["camera"].get("analytic_room", True) and not light["shadow"]:
            colors = room.calibrate(c, (sx, sy), height, light)
            for body in visuals:
                p.removeBody(body, physicsClientId=c)
            self.room = room.Room((sx, sy), height, colors)
        for obj in cfg["objects"]:
            self._add_object(obj)

    def _add_object(self, obj: dict[str, Any]) -> None:
        c = self.client
        color = [*obj.get("color", [0.5, 0.5, 0.5]), 1.0]
        if obj.get("shape", "box") == "box":
            half = [s / 2 for s in obj.get("size", [0.3, 0.3, 0.3])]
            col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=c)
            vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=color,
                                      physicsClientId=c)
            z = half[2]
        else:
            radius, height = float(obj.get("radius", 0.05)), float(obj.get("height", 0.3))
            col = p.createCollisionShape(p.GEOM_CYLINDER, radius=radius, height=height,
                                         physicsClientId=c)
            vis = p.createVisualShape(p.GEOM_CYLINDER, radius=radius, length=height,
                                      rgbaColor=color, physicsClientId=c)
            z = height / 2
        z += float(obj.get("z", 0.0))
        quat = p.getQuaternionFromEuler([0, 0, math.radians(float(obj.get("yaw", 0.0)))])
        p.createMultiBody(0, col, vis, basePosition=[obj["x"], obj["y"], z],
                          baseOrientation=quat, physicsClientId=c)

    def _settle(self, seconds: float = 0.3) -> None:
        """Let the robots sag onto their contacts, then restart clock and odometry."""
        for _ in range(round(seconds / self.dt)):
            p.stepSimulation(physicsClientId=self.client)
        for robot in self.robots.values():
            robot.odometry.reset()
            self._update_odometry(robot, 0.0)

    # -- queries and commands -------------------------------------------------------------------
    @property
    def names(self) -> list[str]:
        return list(self.robots)

    @property
    def cameras(self) -> list[str]:
        """Names of the robots that carry a Kinect."""
        return [n for n, r in self.robots.items() if r.body.camera]

    def _robot(self, name: str) -> Robot:
        try:
            return self.robots[name]
        except KeyError:
            raise KeyError(f"no robot {name!r}; robots: {self.names}") from None

    def set_cmd_vel(self, robot: str, v: float, w: float) -> None:
        """Command a Twist (m/s forward, rad/s counter-clockwise); limits apply."""
        self._robot(robot).drive.command(v, w)

    def set_wheel_fault(self, robot: str, left: float = 1.0, right: float = 1.0) -> None:
        """Scale the wheels' speed targets (0 = blocked wheel, 1 = healthy)."""
        self._robot(robot).wheel_scale = (float(left), float(right))

    def pose(self, robot: str) -> tuple[float, float, float]:
        """Ground truth (x, y, yaw) of ``base_footprint`` in the world frame (m, m, rad)."""
        pos, quat = p.getBasePositionAndOrientation(self._robot(robot).body.body,
                                                    physicsClientId=self.client)
        return pos[0], pos[1], p.getEulerFromQuaternion(quat)[2]

    def velocity(self, robot: str) -> tuple[float, float]:
        """Ground truth (forward speed m/s, yaw rate rad/s)."""
        body = self._robot(robot).body.body
        lin, ang = p.getBaseVelocity(body, physicsClientId=self.client)
        yaw = self.pose(robot)[2]
        return lin[0] * math.cos(yaw) + lin[1] * math.sin(yaw), ang[2]

    def set_pose(self, robot: str, x: float, y: float, yaw: float) -> None:
        """Teleport a robot (yaw in rad), at rest. Its odometry is not changed (as on a robot
        carried by hand); use :meth:`reset_odometry` to restart it."""
        r = self._robot(robot)
        p.resetBasePositionAndOrientation(r.body.body, [x, y, 0.0],
                                          p.getQuaternionFromEuler([0, 0, yaw]),
                                          physicsClientId=self.client)
        p.resetBaseVelocity(r.body.body, [0, 0, 0], [0, 0, 0], physicsClientId=self.client)
        r.drive.reset()

    def odometry(self, robot: str) -> tuple[float, float, float, float, float]:
        """Wheel-encoder odometry (x, y, yaw, v, w) in the odom frame (the start pose)."""
        o = self._robot(robot).odometry
        return o.x, o.y, o.yaw, o.v, o.w

    def wheels(self, robot: str) -> WheelState:
        """The wheels' joint angles (rad, unwrapped) and rates (rad/s)."""
        r = self._robot(robot)
        left, right = p.getJointStates(r.body.body, [r.body.left_joint, r.body.right_joint],
                                       physicsClientId=self.client)
        return WheelState(left[0], right[0], left[1], right[1])

    def contact_bearings(self, robot: str) -> list[float]:
        """Bearings (rad in ``base_footprint``, CCW from ahead) of the points where the robot's
        body touches anything but the floor: a wall, another robot, an object."""
        r = self._robot(robot)
        x, y, yaw = self.pose(robot)
        bearings = []
        for contact in p.getContactPoints(bodyA=r.body.body, physicsClientId=self.client):
            other, on_robot, distance = contact[2], contact[5], contact[8]
            if other in (self.floor, r.body.body) or distance > CONTACT_DISTANCE:
                continue
            bearings.append(math.atan2(on_robot[1] - y, on_robot[0] - x) - yaw)
        return bearings

    def reset_odometry(self, robot: str) -> None:
        """Restart a robot's odometry at (0, 0, 0) from its current wheel angles."""
        r = self._robot(robot)
        r.odometry.reset()
        self._update_odometry(r, 0.0)

    # -- stepping -----------------------------------------------------------------------------
    def step(self) -> None:
        """Advance the world by one physics step of ``dt`` seconds."""
        c = self.client
        for robot in self.robots.values():
            left, right = robot.drive.update(self.dt)
            p.setJointMotorControlArray(
                robot.body.body, [robot.body.left_joint, robot.body.right_joint],
                p.VELOCITY_CONTROL,
                targetVelocities=[left * robot.wheel_scale[0], right * robot.wheel_scale[1]],
                forces=[kobuki.WHEEL_MAX_TORQUE] * 2, physicsClientId=c)
        p.stepSimulation(physicsClientId=c)
        self.steps += 1
        self.time = self.steps * self.dt
        for robot in self.robots.values():
            self._update_odometry(robot, self.dt)

    def _update_odometry(self, robot: Robot, dt: float) -> None:
        states = p.getJointStates(robot.body.body, [robot.body.left_joint, robot.body.right_joint],
                                  physicsClientId=self.client)
        robot.odometry.update(states[0][0], states[1][0], dt)

    # -- rendering ------------------------------------------------------------------------------
    def base_states(self) -> dict[str, BaseState]:
        """Every robot's full base pose, to re-pose a render-only copy of this world."""
        return {name: p.getBasePositionAndOrientation(r.body.body, physicsClientId=self.client)
                for name, r in self.robots.items()}

    def apply_base_states(self, states: dict[str, BaseState]) -> None:
        """Put the robots at the given base poses (used by the render worker)."""
        for name, (pos, quat) in states.items():
            p.resetBasePositionAndOrientation(self._robot(name).body.body, pos, quat,
                                              physicsClientId=self.client)

    def camera_pose(self, robot: str) -> tuple[np.ndarray, np.ndarray]:
        """World position of the Kinect's optical centre and the mount's rotation (x forward)."""
        pos, quat = p.getBasePositionAndOrientation(self._robot(robot).body.body,
                                                    physicsClientId=self.client)
        rot = np.asarray(p.getMatrixFromQuaternion(quat), dtype=float).reshape(3, 3)
        return np.asarray(pos) + rot @ np.asarray(kobuki.KINECT_OPTICAL), rot

    def render_kinect(self, robot: str, rng: np.random.Generator | None = None,
                      ) -> tuple[np.ndarray, np.ndarray]:
        """Render the robot's Kinect: (rgb HxWx3 uint8, xyz HxWx3 float32 optical frame, NaN).

        The noise comes from ``rng`` (default: the world's own seeded stream).
        """
        if not self._robot(robot).body.camera:
            raise ValueError(f"robot {robot!r} has no camera")
        return kinect.sense(*self.render_raw(robot), self.intrinsics, self.noise,
                            rng or self._render_rng)

    def _scene_key(self) -> tuple:
        """The robots' poses rounded to 0.1 mm and 1e-5 (quaternion): equal = same picture."""
        return tuple((tuple(round(v, 4) for v in pos), tuple(round(v, 5) for v in quat))
                     for pos, quat in self.base_states().values())

    def render_raw(self, robot: str) -> tuple[np.ndarray, np.ndarray]:
        """The ideal Kinect picture: (rgb HxWx3 uint8, z HxW float32 optical depth, inf = none).

        TinyRenderer draws robots and objects, ray casting the room (see
        :mod:`turtlebot_sim.room`). Reuses the previous picture when no robot moved since.
        """
        key = self._scene_key()
        cached = self._raw_cache.get(robot)
        if cached is not None and cached[0] == key:
            return cached[1], cached[2]
        position, rotation = self.camera_pose(robot)
        light = self.config["lighting"]
        intr = self.intrinsics
        _, _, rgba, depth, _ = p.getCameraImage(
            intr.width, intr.height, kinect.view_matrix(position, rotation), self._projection,
            lightDirection=list(light["direction"]), lightColor=list(light["color"]),
            lightDistance=float(light["distance"]), shadow=int(bool(light["shadow"])),
            lightAmbientCoeff=float(light["ambient"]),
            lightDiffuseCoeff=float(light["diffuse"]),
            lightSpecularCoeff=float(light["specular"]),
            renderer=p.ER_TINY_RENDERER, flags=p.ER_NO_SEGMENTATION_MASK,
            physicsClientId=self.client)
        rgb = np.asarray(rgba, dtype=np.uint8).reshape(intr.height, intr.width, 4)[:, :, :3].copy()
        z = kinect.linear_depth(np.asarray(depth, dtype=np.float32).reshape(intr.height,
                                                                            intr.width))
        if self.room is not None:
            self.room.fill(rgb, z, position, rotation, self._ray_x, self._ray_y)
        self._raw_cache[robot] = (key, rgb, z)
        self.renders += 1
        return rgb, z

    def close(self) -> None:
        """Disconnect from pybullet."""
        if self.client >= 0:
            p.disconnect(physicsClientId=self.client)
            self.client = -1

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
