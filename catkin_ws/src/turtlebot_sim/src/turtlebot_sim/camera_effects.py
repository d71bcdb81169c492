"""What a real Kinect's colour camera adds to the ideal picture: motion blur over the exposure
and auto exposure (numpy only, no pybullet, no ROS).

Set by optional keys of the world's ``camera`` section (defaults: off, today's pictures)::

    camera: {exposure_s: 0.03, auto_exposure: true, auto_exposure_target: 110,
             auto_exposure_max_gain: 4.0}

* ``exposure_s`` > 0: while the camera turns at ``yaw_rate`` (rad/s) the picture slides
  sideways by ``fx * yaw_rate * exposure_s`` pixels during the exposure; each pixel is the mean
  along that slide (a horizontal box blur). The robot's turn dominates a TurtleBot's blur
  (Helper's search sweep: 120 deg/s, 2.1 rad/s, so 33 px at 30 ms and fx 525).
* ``auto_exposure``: the gain brings the frame's mean luma to ``auto_exposure_target``
  (0-255), within ``1/max_gain`` .. ``max_gain``; bright pixels saturate at 255. The gain is
  set per frame (no lag).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

#: ITU-R BT.601 luma weights of R, G, B (what OpenCV's RGB2GRAY uses).
LUMA = np.array([0.299, 0.587, 0.114], dtype=np.float32)


@dataclass(frozen=True)
class CameraEffects:
    """The effects of a world's ``camera`` section (see the module docstring)."""

    exposure_s: float = 0.0
    auto_exposure: bool = False
    auto_exposure_target: float = 110.0
    auto_exposure_max_gain: float = 4.0

    @classmethod
    def from_config(cls, camera: dict[str, Any]) -> CameraEffects:
        return cls(exposure_s=float(camera.get("exposure_s", 0.0)),
                   auto_exposure=bool(camera.get("auto_exposure", False)),
                   auto_exposure_target=float(camera.get("auto_exposure_target", 110.0)),
                   auto_exposure_max_gain=float(camera.get("auto_exposure_max_gain", 4.0)))

    @property
    def active(self) -> bool:
        return self.exposure_s > 0.0 or self.auto_exposure

    def blur_pixels(self, yaw_rate: float, fx: float) -> int:
        """Length of the horizontal slide during the exposure (pixels, 0 = none)."""
        return round(abs(yaw_rate) * self.exposure_s * fx)

    def apply(self, rgb: np.ndarray, yaw_rate: float, fx: float) -> np.ndarray:
        """The picture as the camera records it: blurred by the turn, then exposed."""
        out = rgb
        length = self.blur_pixels(yaw_rate, fx)
        if length > 1:
            out = box_blur_rows(out, length)
        if self.auto_exposure:
            out = expose(out, self.auto_exposure_target, self.auto_exposure_max_gain)
        return out


def expose(rgb: np.ndarray, target: float, max_gain: float) -> np.ndarray:
    """`rgb` times the gain that brings its mean luma to `target` (gain within 1/max_gain ..
    max_gain), saturating at 255."""
    luma = float((rgb.reshape(-1, 3).astype(np.float32) @ LUMA).mean())
    gain = float(np.clip(target / max(luma, 1.0), 1.0 / max_gain, max_gain))
    return np.clip(rgb.astype(np.float32) * gain, 0, 255).astype(np.uint8)


def box_blur_rows(rgb: np.ndarray, length: int) -> np.ndarray:
    """Each pixel the mean of the `length` pixels of its row centred on it (the border pixels
    repeated beyond the image's edges)."""
    before = length // 2
    padded = np.pad(rgb.astype(np.float32), ((0, 0), (before, length - 1 - before), (0, 0)),
                    mode="edge")
    sums = np.cumsum(padded, axis=1, dtype=np.float64)
    sums = np.concatenate([np.zeros_like(sums[:, :1]), sums], axis=1)
    window = (sums[:, length:] - sums[:, :-length]) / length
    return np.clip(np.round(window), 0, 255).astype(np.uint8)
