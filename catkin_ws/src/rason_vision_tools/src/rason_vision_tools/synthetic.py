"""A tiny ray-cast Kinect for tests: vertical cylinders on a floor, drawn with numpy only.

It knows nothing of the simulator; it renders what the detector needs (Faulty's base, its two
coloured cylinders, distractor cylinders, a floor and a far wall) by exact ray/cylinder
intersection per pixel, with a z-buffer, simple shading and Kinect-like depth noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rason_vision.geometry import CYLINDER_RADIUS, Intrinsics, cylinder_axes_in_camera

GREEN_RGB = (40, 170, 60)
ORANGE_RGB = (240, 120, 20)
BASE_RGB = (60, 60, 60)
FLOOR_RGB = (150, 140, 130)
WALL_RGB = (200, 200, 205)

#: Faulty's layout (heights above the floor, m): top plate, green and orange cylinder tops.
PLATE_HEIGHT = 0.40
GREEN_TOP = 0.50
ORANGE_TOP = 0.60
BASE_RADIUS = 0.177
CAMERA_HEIGHT = 0.45


@dataclass(frozen=True)
class Cylinder:
    """A vertical cylinder in the camera's horizontal plane (axis at optical x, z)."""

    x: float
    z: float
    radius: float
    bottom: float
    top: float
    rgb: tuple[int, int, int]


@dataclass
class Scene:
    """Cylinders seen by a camera ``camera_height`` above a floor, a wall at ``wall_z``."""

    cylinders: list[Cylinder] = field(default_factory=list)
    camera_height: float = CAMERA_HEIGHT
    wall_z: float = 6.0
    depth_noise: float = 0.0015
    intrinsics: Intrinsics = field(default_factory=Intrinsics)

    def add_faulty(self, green_xz: tuple[float, float], orange_xz: tuple[float, float],
                   green_rgb: tuple[int, int, int] = GREEN_RGB,
                   orange_rgb: tuple[int, int, int] = ORANGE_RGB) -> Scene:
        """Faulty's grey base plus its two cylinders standing on the top plate."""
        cx = (green_xz[0] + orange_xz[0]) / 2.0
        cz = (green_xz[1] + orange_xz[1]) / 2.0
        self.cylinders += [
            Cylinder(cx, cz, BASE_RADIUS, 0.0, PLATE_HEIGHT, BASE_RGB),
            Cylinder(*green_xz, CYLINDER_RADIUS, PLATE_HEIGHT, GREEN_TOP, green_rgb),
            Cylinder(*orange_xz, CYLINDER_RADIUS, PLATE_HEIGHT, ORANGE_TOP, orange_rgb)]
        return self

    def _raycast(self) -> tuple[np.ndarray, ...]:
        """Per pixel: ray slopes dx, dy, depth, shade, colour and the index of the cylinder hit."""
        k = self.intrinsics
        us, vs = np.meshgrid(np.arange(k.width, dtype=np.float64),
                             np.arange(k.height, dtype=np.float64))
        dx, dy = (us - k.cx) / k.fx, (vs - k.cy) / k.fy
        depth = np.full(dx.shape, self.wall_z)
        shade = np.full(dx.shape, 0.9)
        colour = np.empty((*dx.shape, 3))
        colour[:] = WALL_RGB
        labels = np.full(dx.shape, -1, dtype=np.int16)
        with np.errstate(divide="ignore", invalid="ignore"):
            t_floor = np.where(dy > 1e-9, self.camera_height / dy, np.inf)
        floor = t_floor < depth
        depth[floor], shade[floor] = t_floor[floor], 0.8
        colour[floor] = FLOOR_RGB
        for index, cyl in enumerate(self.cylinders):
            hit = self._draw_cylinder(cyl, dx, dy, depth, shade, colour)
            labels[hit] = index
        return dx, dy, depth, shade, colour, labels

    def labels(self) -> np.ndarray:
        """Per pixel, the index of the cylinder seen there (-1: floor or wall); after
        :meth:`add_faulty` on an empty scene, 1 is the green cylinder and 2 the orange one."""
        return self._raycast()[-1]

    def visibility(self) -> list[tuple[int, int]]:
        """Per cylinder: visible pixels and image columns they span (occlusion included)."""
        labels = self.labels()
        return [(int((labels == i).sum()), int((labels == i).any(axis=0).sum()))
                for i in range(len(self.cylinders))]

    def render(self, rng: np.random.Generator | None = None) -> tuple[np.ndarray, np.ndarray]:
        """(rgb HxWx3 uint8, xyz HxWx3 float32 optical frame, NaN outside 0.5-4.5 m)."""
        rng = rng or np.random.default_rng(0)
        dx, dy, depth, shade, colour, _ = self._raycast()
        rgb = np.clip(colour * shade[..., None] + rng.normal(0, 2.0, colour.shape), 0, 255)
        z = depth * (1.0 + rng.normal(0, 1.0, depth.shape) * self.depth_noise * depth)
        z[(depth < 0.5) | (depth > 4.5)] = np.nan
        xyz = np.stack([dx * z, dy * z, z], axis=-1).astype(np.float32)
        return rgb.astype(np.uint8), xyz

    def _draw_cylinder(self, cyl: Cylinder, dx: np.ndarray, dy: np.ndarray, depth: np.ndarray,
                       shade: np.ndarray, colour: np.ndarray) -> np.ndarray:
        a = dx * dx + 1.0
        b = dx * cyl.x + cyl.z
        c = cyl.x ** 2 + cyl.z ** 2 - cyl.radius ** 2
        disc = b * b - a * c
        with np.errstate(invalid="ignore"):
            t = (b - np.sqrt(disc)) / a
        height = self.camera_height - t * dy
        side = (disc > 0) & (t > 0) & (height >= cyl.bottom) & (height <= cyl.top) & (t < depth)
        nx = (t * dx - cyl.x) / cyl.radius
        nz = (t - cyl.z) / cyl.radius
        lambert = np.clip(-(nx * dx + nz) / np.sqrt(a), 0.0, 1.0)
        depth[side] = t[side]
        shade[side] = 0.45 + 0.55 * lambert[side]
        colour[side] = cyl.rgb
        hit = side
        if cyl.top < self.camera_height:
            with np.errstate(divide="ignore", invalid="ignore"):
                t_cap = np.where(dy > 1e-9, (self.camera_height - cyl.top) / dy, np.inf)
            cap = ((t_cap * dx - cyl.x) ** 2 + (t_cap - cyl.z) ** 2 <= cyl.radius ** 2) & \
                (t_cap < depth)
            depth[cap], shade[cap] = t_cap[cap], 1.0
            colour[cap] = cyl.rgb
            hit = side | cap
        return hit


def world_scene(camera: tuple[float, float, float], faulty: tuple[float, float, float],
                **scene_kwargs: object) -> Scene:
    """Faulty at world pose ``(x, y, yaw)`` seen by a camera at world pose ``(x, y, yaw)``
    (REP 103: x forward, y left, yaw counter-clockwise, radians)."""
    green, orange = cylinder_axes_in_camera(*camera, *faulty)
    return Scene(**scene_kwargs).add_faulty(green, orange)  # type: ignore[arg-type]


def faulty_scene(distance: float, bearing_deg: float, heading_deg: float,
                 **scene_kwargs: object) -> Scene:
    """Faulty at ``distance`` (horizontal range, m) and ``bearing_deg`` (+ right), facing
    ``heading_deg`` in the camera frame (clockwise from the optical axis, see geometry)."""
    b, h = math.radians(bearing_deg), math.radians(heading_deg)
    # Camera at the origin facing world +x; world yaw is counter-clockwise, camera angles clockwise.
    fx, fy = distance * math.cos(b), -distance * math.sin(b)
    green, orange = cylinder_axes_in_camera(0.0, 0.0, 0.0, fx, fy, -h)
    return Scene(**scene_kwargs).add_faulty(green, orange)  # type: ignore[arg-type]
