"""The room (floor and four walls) drawn by ray casting in numpy instead of TinyRenderer.

TinyRenderer's cost is per covered pixel: the floor and the walls, which fill the whole Kinect
picture, cost ~50 of its ~65 ms per 640x480 frame. Under pybullet's directional light a flat
surface has one colour, so the room is drawn exactly enough by intersecting each background
pixel's ray with the six-sided room and painting the plane's colour, measured once from
TinyRenderer itself (:func:`calibrate`). Robots and distractors are still rendered by
TinyRenderer; the room fills the pixels where it saw nothing.

The room is centred on the world origin: floor z = 0, walls at x = ±size_x/2 and y = ±size_y/2,
``height`` high. Beyond the walls' top is TinyRenderer's empty background (white, no depth).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pybullet as p

#: TinyRenderer's colour where nothing is drawn.
BACKGROUND = (255, 255, 255)


class Room:
    """Floor and walls: plane colours (uint8 RGB) and the ray casting that paints them."""

    def __init__(self, size: Sequence[float], height: float, colors: Sequence[Sequence[int]]):
        """``colors``: floor, wall +x, wall -x, wall +y, wall -y (as TinyRenderer shades them)."""
        self.half = (float(size[0]) / 2.0, float(size[1]) / 2.0)
        self.height = float(height)
        self.palette = np.array([*colors, BACKGROUND], dtype=np.uint8)

    def fill(self, rgb: np.ndarray, z: np.ndarray, eye: np.ndarray, rotation: np.ndarray,
             ray_x: np.ndarray, ray_y: np.ndarray) -> None:
        """Paint the room into the pixels where ``z`` is inf (in place).

        ``ray_x`` (W,) and ``ray_y`` (H,) are the optical-frame ray slopes (u - cx)/fx and
        (v - cy)/fy; ``rotation`` is the world-from-mount rotation (x forward, y left, z up) of
        the camera at ``eye``, which must be inside the room.

        From inside a convex box a ray leaves through the plane it reaches first, i.e. the
        plane with the largest 1/t = (n . d) / distance, an affine function of the pixel's
        slopes. Which plane that is is decided on a half-resolution grid (plane borders may be
        off by a pixel, where both planes' depths agree anyway); the depth is then computed
        per pixel from that plane's affine map. The open top has the background colour and no
        depth.
        """
        mask = ~np.isfinite(z)
        if not mask.any():
            return
        hx, hy = self.half
        # (outward normal axis, sign, offset along it): floor, walls +x -x +y -y, open top
        planes = ((2, -1.0, 0.0), (0, 1.0, hx), (0, -1.0, hx), (1, 1.0, hy), (1, -1.0, hy),
                  (2, 1.0, self.height))
        # 1/t = cf - cl * ray_x - cu * ray_y for the ray d = fwd - ray_x * left - ray_y * up
        coef = np.empty((3, len(planes)), dtype=np.float32)
        for k, (axis, sign, offset) in enumerate(planes):
            distance = max(offset - sign * float(eye[axis]), 1e-6)
            coef[:, k] = [sign * rotation[axis, col] / distance for col in range(3)]
        cf, cl, cu = coef
        half_x, half_y = ray_x[::2], ray_y[::2]
        inv = (cf[:, None, None] - cu[:, None, None] * half_y[None, :, None]) - \
            (cl[:, None, None] * half_x[None, None, :])
        index = inv.argmax(axis=0).astype(np.uint8)
        index = np.repeat(np.repeat(index, 2, axis=0), 2, axis=1)[:z.shape[0], :z.shape[1]]
        inv_t = (cf[index] - cu[index] * ray_y[:, None]) - cl[index] * ray_x[None, :]
        with np.errstate(divide="ignore"):
            t = np.float32(1.0) / inv_t
        t[(index == len(planes) - 1) | (inv_t <= 0)] = np.inf
        np.copyto(z, t, where=mask)
        np.copyto(rgb, self.palette[index], where=mask[:, :, None])


def calibrate(client: int, size: Sequence[float], height: float,
              light: dict) -> list[tuple[int, int, int]]:
    """Each plane's colour as TinyRenderer shades it (the room's visual bodies must be there)."""
    hx, hy = float(size[0]) / 2.0, float(size[1]) / 2.0
    h = min(1.0, height / 2.0)
    views = [((0.0, 0.0, 1.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)),      # floor, from above
             ((hx - 1.0, 0.0, h), (hx, 0.0, h), (0.0, 0.0, 1.0)),
             ((-hx + 1.0, 0.0, h), (-hx, 0.0, h), (0.0, 0.0, 1.0)),
             ((0.0, hy - 1.0, h), (0.0, hy, h), (0.0, 0.0, 1.0)),
             ((0.0, -hy + 1.0, h), (0.0, -hy, h), (0.0, 0.0, 1.0))]
    projection = p.computeProjectionMatrixFOV(20.0, 1.0, 0.05, 20.0)
    colors = []
    for eye, target, up in views:
        _, _, rgba, _, _ = p.getCameraImage(
            8, 8, p.computeViewMatrix(eye, target, up), projection,
            lightDirection=list(light["direction"]), lightColor=list(light["color"]),
            lightDistance=float(light["distance"]), shadow=0,
            lightAmbientCoeff=float(light["ambient"]), lightDiffuseCoeff=float(light["diffuse"]),
            lightSpecularCoeff=float(light["specular"]), renderer=p.ER_TINY_RENDERER,
            physicsClientId=client)
        pixel = np.asarray(rgba, dtype=np.uint8).reshape(8, 8, 4)[4, 4, :3]
        colors.append((int(pixel[0]), int(pixel[1]), int(pixel[2])))
    return colors
