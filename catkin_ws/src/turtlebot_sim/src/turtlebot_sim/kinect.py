"""The Kinect model: intrinsics, pybullet camera matrices, depth noise, point cloud packing.

Pure numpy + pybullet; no ROS. The optical frame is x right, y down, z forward (metres).
Pixel (u, v) (column, row; centres at integer coordinates) sees the ray
``x/z = (u - cx) / fx, y/z = (v - cy) / fy`` with ``cx = (W - 1) / 2`` and ``cy = (H - 1) / 2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pybullet as p

NEAR, FAR = 0.02, 12.0          # OpenGL clip planes of the simulated camera
BASELINE_FX = 0.075 * 580.0     # Kinect IR baseline (m) times IR focal length (px)
DISPARITY_STEP = 1.0 / 8.0      # Kinect disparity resolution (px)


@dataclass(frozen=True)
class Intrinsics:
    """A pinhole camera of ``width`` x ``height`` pixels and horizontal FOV ``hfov_deg``."""

    width: int = 640
    height: int = 480
    hfov_deg: float = 57.0

    @property
    def fx(self) -> float:
        return (self.width / 2.0) / math.tan(math.radians(self.hfov_deg) / 2.0)

    @property
    def fy(self) -> float:
        return self.fx

    @property
    def cx(self) -> float:
        return (self.width - 1) / 2.0

    @property
    def cy(self) -> float:
        return (self.height - 1) / 2.0

    @property
    def vfov_deg(self) -> float:
        """Vertical FOV (what pybullet's computeProjectionMatrixFOV takes): 44.31 deg at 4:3."""
        return math.degrees(2.0 * math.atan((self.height / 2.0) / self.fy))

    def projection_matrix(self) -> list[float]:
        return list(p.computeProjectionMatrixFOV(self.vfov_deg, self.width / self.height,
                                                 NEAR, FAR))


@dataclass(frozen=True)
class NoiseModel:
    """Kinect-like depth and colour imperfections.

    Depth noise sigma(z) = a + b * (z - z0)^2 (m); ``quantize`` rounds the disparity to 1/8 px
    (depth steps ~ 2.9 mm * z^2); depth outside [min_range, max_range] is NaN; ``edge_dropout``
    > 0 drops pixels whose depth differs from a 4-neighbour by more than that fraction (the
    Kinect's shadows at depth discontinuities). ``color_noise`` is the sigma of Gaussian noise
    added to each RGB channel (0-255 units).
    """

    a: float = 0.0012
    b: float = 0.0019
    z0: float = 0.4
    quantize: bool = True
    min_range: float = 0.5
    max_range: float = 4.5
    edge_dropout: float = 0.0
    color_noise: float = 3.0

    @classmethod
    def from_config(cls, camera: dict[str, Any]) -> NoiseModel:
        a, b, z0 = camera.get("depth_noise", (0.0012, 0.0019, 0.4))
        return cls(a=float(a), b=float(b), z0=float(z0),
                   quantize=bool(camera.get("quantize_depth", True)),
                   min_range=float(camera.get("min_range", 0.5)),
                   max_range=float(camera.get("max_range", 4.5)),
                   edge_dropout=float(camera.get("edge_dropout", 0.0)),
                   color_noise=float(camera.get("color_noise", 3.0)))

    def sigma(self, z: np.ndarray) -> np.ndarray:
        return self.a + self.b * (z - self.z0) ** 2


def view_matrix(position: np.ndarray, rotation: np.ndarray) -> list[float]:
    """OpenGL view matrix of a camera at ``position`` looking along the body's +x axis.

    ``rotation`` is the 3x3 world-from-body rotation of the camera mount (x forward, z up).
    """
    forward, up = rotation[:, 0], rotation[:, 2]
    return list(p.computeViewMatrix(position.tolist(), (position + forward).tolist(), up.tolist()))


def linear_depth(buffer: np.ndarray) -> np.ndarray:
    """pybullet's non-linear depth buffer -> distance along the optical axis (m), inf = nothing."""
    buffer = np.asarray(buffer, dtype=np.float32)
    z = (FAR * NEAR / (FAR - (FAR - NEAR) * buffer)).astype(np.float32)
    z[buffer >= 0.9999] = np.inf
    return z


class NoiseBank:
    """Pre-drawn standard normal samples; a frame's noise is a random window into them.

    Drawing 1.2 M normals per 640x480 frame costs ~15 ms; a window costs nothing. Successive
    frames get independent-looking noise (random offsets), deterministic for a seeded ``rng``.
    """

    def __init__(self, size: int, seed: int = 20150401):
        self.size = size
        self.samples = np.random.default_rng(seed).standard_normal(2 * size, dtype=np.float32)

    def draw(self, n: int, rng: np.random.Generator) -> np.ndarray:
        if n > self.size:
            raise ValueError(f"bank of {self.size} cannot give {n} samples")
        offset = int(rng.integers(0, self.size + 1))
        return self.samples[offset:offset + n]


_BANKS: dict[int, NoiseBank] = {}


def _bank(n: int) -> NoiseBank:
    """The process's (fixed) bank for frames of ``n`` values; the offsets carry the randomness."""
    if n not in _BANKS:
        _BANKS[n] = NoiseBank(n)
    return _BANKS[n]


def sense(rgb: np.ndarray, z: np.ndarray, intr: Intrinsics, noise: NoiseModel,
          rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Ideal picture -> Kinect data.

    Args:
        rgb: HxWx3 (or HxWx4) uint8 colours as rendered.
        z: HxW float32 distance along the optical axis (m), inf where nothing is seen.
    Returns:
        (rgb HxWx3 uint8 with colour noise, xyz HxWx3 float32 in the optical frame with depth
        noise and quantisation, NaN where there is no depth).
    """
    h, w = intr.height, intr.width
    bank = _bank(h * w * 3)
    rgb = np.asarray(rgb, dtype=np.uint8).reshape(h, w, -1)[:, :, :3]
    if noise.color_noise > 0:
        jitter = bank.draw(h * w * 3, rng).reshape(h, w, 3) * np.float32(noise.color_noise)
        rgb = np.clip(rgb + jitter, 0, 255).astype(np.uint8)
    else:
        rgb = rgb.copy()
    z = np.asarray(z, dtype=np.float32).reshape(h, w)
    invalid = ~np.isfinite(z)
    z = np.where(invalid, np.float32(FAR), z)
    z += bank.draw(h * w, rng).reshape(h, w) * noise.sigma(z).astype(np.float32)
    if noise.quantize:
        disparity = np.round(BASELINE_FX / np.maximum(z, 1e-3) / DISPARITY_STEP) * DISPARITY_STEP
        z = (BASELINE_FX / np.maximum(disparity, DISPARITY_STEP)).astype(np.float32)
    invalid |= (z < noise.min_range) | (z > noise.max_range)
    if noise.edge_dropout > 0:
        invalid |= _depth_edges(z, noise.edge_dropout)
    z[invalid] = np.nan
    u = (np.arange(w, dtype=np.float32) - intr.cx) / intr.fx
    v = (np.arange(h, dtype=np.float32) - intr.cy) / intr.fy
    xyz = np.empty((h, w, 3), dtype=np.float32)
    xyz[:, :, 0] = z * u[None, :]
    xyz[:, :, 1] = z * v[:, None]
    xyz[:, :, 2] = z
    return rgb, xyz


def _depth_edges(z: np.ndarray, fraction: float) -> np.ndarray:
    """Pixels whose depth jumps by more than ``fraction`` of it to a 4-neighbour."""
    edges = np.zeros(z.shape, dtype=bool)
    jump_x = np.abs(np.diff(z, axis=1)) > fraction * z[:, 1:]
    jump_y = np.abs(np.diff(z, axis=0)) > fraction * z[1:, :]
    edges[:, 1:] |= jump_x
    edges[:, :-1] |= jump_x
    edges[1:, :] |= jump_y
    edges[:-1, :] |= jump_y
    return edges
