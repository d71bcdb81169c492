"""The cylinders' colour ranges: found from pixels the user names, and kept in a YAML file.

:func:`fit_range` turns the pixels of one cylinder (a region of a frame, or a labelled mask)
into an OpenCV HSV box: the dominant hue among the saturated pixels (hue is circular: a red
orange may wrap past 0), its 1st-99th percentile spread plus ``hue_margin``, and lower bounds of
saturation and value at a fraction of their 2nd percentile, so that the cylinder in shadow or
under dimmer light still falls inside (upper bounds 255). ``rosrun rason_vision calibrate``
(:mod:`rason_vision.calibrate`) writes the result; the synthesizer's ``~colours`` reads it.

The file::

    # rosrun rason_vision calibrate ... (how it was made)
    green: {lower: [52, 120, 40], upper: [70, 255, 255]}
    orange: {lower: [2, 150, 70], upper: [16, 255, 255]}
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml

from rason_vision.detector import GREEN, ORANGE, HsvRange

#: The cylinders a colours file names.
CYLINDERS = (GREEN, ORANGE)
#: Pixels less saturated than this are background (grey floor, walls, specular spots).
MIN_SATURATION = 40
#: Hue units (OpenCV: 0-179 for 360 deg) around the dominant hue that count as the cylinder.
HUE_WINDOW = 20
#: Fewest cylinder pixels a range is fitted from.
MIN_PIXELS = 20


@dataclass(frozen=True)
class Margins:
    """How far a fitted range reaches beyond the pixels it was fitted from."""

    hue: int = 4                 # hue units either side of the 1st-99th percentile
    saturation: float = 0.7      # lower S bound = this times the 2nd percentile of S
    value: float = 0.5           # lower V bound = this times the 2nd percentile of V (shadow)


def _circular(offset: np.ndarray) -> np.ndarray:
    """Hue differences wrapped into [-90, 90)."""
    return (offset + 90) % 180 - 90


def fit_range(hsv: np.ndarray, margins: Margins = Margins()) -> HsvRange:
    """The HSV box of one cylinder from its pixels (N x 3 OpenCV HSV, background allowed).

    Raises ValueError when fewer than :data:`MIN_PIXELS` saturated pixels share one hue.
    """
    pixels = np.asarray(hsv, dtype=np.int32).reshape(-1, 3)
    coloured = pixels[pixels[:, 1] >= MIN_SATURATION]
    if len(coloured) < MIN_PIXELS:
        raise ValueError(f"only {len(coloured)} coloured pixels (saturation >= "
                         f"{MIN_SATURATION}): name a region on the cylinder")
    counts = np.bincount(coloured[:, 0] % 180, minlength=180).astype(float)
    smooth = sum(np.roll(counts, k) for k in range(-3, 4))
    peak = int(np.argmax(smooth))
    offsets = _circular(coloured[:, 0] - peak)
    cylinder = coloured[np.abs(offsets) <= HUE_WINDOW]
    offsets = offsets[np.abs(offsets) <= HUE_WINDOW]
    if len(cylinder) < MIN_PIXELS:
        raise ValueError(f"only {len(cylinder)} pixels share the dominant hue {peak}")
    low = int(np.floor(np.percentile(offsets, 1))) - margins.hue
    high = int(np.ceil(np.percentile(offsets, 99))) + margins.hue
    sat = int(np.percentile(cylinder[:, 1], 2) * margins.saturation)
    val = int(np.percentile(cylinder[:, 2], 2) * margins.value)
    return HsvRange(((peak + low) % 180, max(sat, 0), max(val, 0)),
                    ((peak + high) % 180, 255, 255))


def to_hsv(rgb: np.ndarray) -> np.ndarray:
    """An RGB uint8 image in OpenCV's HSV (H 0-179)."""
    return cv2.cvtColor(np.ascontiguousarray(rgb, dtype=np.uint8), cv2.COLOR_RGB2HSV)


@dataclass(frozen=True)
class Region:
    """A rectangle of a frame: ``x, y`` its top-left pixel, ``w`` x ``h`` pixels."""

    x: int
    y: int
    w: int
    h: int

    #: half-size of the window a single named pixel stands for
    PIXEL_HALF = 3

    @classmethod
    def parse(cls, text: str) -> Region:
        """``"x,y,w,h"`` or ``"x,y"`` (a pixel: the 7 x 7 window around it)."""
        try:
            numbers = [int(float(v)) for v in str(text).split(",")]
        except ValueError:
            raise ValueError(f"region {text!r}: expected x,y,w,h or x,y") from None
        if len(numbers) == 2:
            half = cls.PIXEL_HALF
            return cls(numbers[0] - half, numbers[1] - half, 2 * half + 1, 2 * half + 1)
        if len(numbers) != 4 or numbers[2] <= 0 or numbers[3] <= 0:
            raise ValueError(f"region {text!r}: expected x,y,w,h (w, h > 0) or x,y")
        return cls(*numbers)

    def mask(self, shape: tuple[int, int]) -> np.ndarray:
        """The region as a boolean mask of a frame of `shape` (h, w), clipped to it. Raises
        ValueError when the region lies outside the frame."""
        height, width = shape
        x0, y0 = max(self.x, 0), max(self.y, 0)
        x1, y1 = min(self.x + self.w, width), min(self.y + self.h, height)
        if x0 >= x1 or y0 >= y1:
            raise ValueError(f"region {self.x},{self.y},{self.w},{self.h} is outside the "
                             f"{width}x{height} frame")
        mask = np.zeros(shape, dtype=bool)
        mask[y0:y1, x0:x1] = True
        return mask


#: Values of a labels image (a single-channel PNG of the frame's size) per cylinder.
LABELS = {GREEN: 1, ORANGE: 2}


def load_colours(path: str | Path) -> dict[str, HsvRange]:
    """The ranges of a colours file (ValueError naming the file when it is malformed)."""
    try:
        data = yaml.safe_load(Path(path).read_text(encoding="utf-8"))
    except (OSError, yaml.YAMLError) as err:
        raise ValueError(f"colours file {path}: {err}") from None
    if not isinstance(data, Mapping):
        raise ValueError(f"colours file {path}: a mapping of {', '.join(CYLINDERS)} expected")
    ranges = {}
    for name in CYLINDERS:
        entry = data.get(name)
        if not isinstance(entry, Mapping):
            raise ValueError(f"colours file {path}: no {name}: {{lower: [H, S, V], upper: "
                             f"[H, S, V]}}")
        ranges[name] = HsvRange(_triple(path, name, "lower", entry.get("lower")),
                                _triple(path, name, "upper", entry.get("upper")))
    return ranges


def _triple(path: str | Path, name: str, bound: str, value: Any) -> tuple[int, int, int]:
    try:
        h, s, v = (int(x) for x in value)
    except (TypeError, ValueError):
        raise ValueError(f"colours file {path}: {name}.{bound} must be [H, S, V], got "
                         f"{value!r}") from None
    if not (0 <= h <= 179 and 0 <= s <= 255 and 0 <= v <= 255):
        raise ValueError(f"colours file {path}: {name}.{bound} {value}: H must be in 0-179, "
                         f"S and V in 0-255")
    return (h, s, v)


def save_colours(path: str | Path, ranges: Mapping[str, HsvRange], note: str = "") -> None:
    """Write a colours file (with `note` as a comment line on top)."""
    body = {name: {"lower": list(r.lower), "upper": list(r.upper)}
            for name, r in ranges.items()}
    head = f"# {note}\n" if note else ""
    Path(path).write_text(head + yaml.safe_dump(body, default_flow_style=None,
                                                sort_keys=True), encoding="utf-8")
