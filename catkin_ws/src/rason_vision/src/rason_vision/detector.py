"""Find Faulty's green and orange cylinders in one Kinect frame (numpy + OpenCV, no ROS).

The pipeline of thesis 6.2.1: RGB -> HSV, ``inRange`` per colour, morphological opening
(erode, dilate) then closing (dilate, erode), connected components as candidate blobs per
colour, then every (green, orange) pair whose distance is within ``[min_spacing,
max_spacing]`` and, among them, the one closest to ``spacing`` (22.7 cm).

The distance is measured in the horizontal plane (optical x, z; the vertical y ignored): the
cylinders have different heights and the far one may only show above the near one, so the
blob centroids sit at different heights and only their horizontal positions are comparable.
It is the 3-D distance of the two cylinder axes.

A blob is cut along depth jumps of more than ``depth_gap`` (a cylinder in front of a
similar-coloured object); slivers narrower than ``min_width_fraction`` of a cylinder's width
at their depth are not candidates. Each blob's position is the mean of its valid point-cloud
points, pushed back along the horizontal viewing ray by ``pi/4 * radius``: the visible half
of a cylinder is on average that much closer than its axis. A blob cut by the image's left or
right border is placed from its one true silhouette edge instead. When a blob may be cut
short (image border, or the other cylinder in front of it) the pair's lower distance bound
is relaxed by one radius. Blobs with too few valid depth points are dropped, so NaN never
reaches the output.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import cv2
import numpy as np

from rason_vision.geometry import (
    CYLINDER_RADIUS,
    CYLINDER_SPACING,
    Intrinsics,
    Relative,
    bearing_deg,
    relative_from_axes,
    thesis_angle_deg,
)

GREEN = "green"
ORANGE = "orange"


@dataclass(frozen=True)
class HsvRange:
    """An OpenCV HSV box (H in 0..179, S and V in 0..255); ``lower[0] > upper[0]`` wraps hue."""

    lower: tuple[int, int, int]
    upper: tuple[int, int, int]

    def mask(self, hsv: np.ndarray) -> np.ndarray:
        """uint8 mask (255 inside) of the pixels of ``hsv`` inside this box."""
        lo, hi = np.array(self.lower, np.uint8), np.array(self.upper, np.uint8)
        if self.lower[0] <= self.upper[0]:
            return cv2.inRange(hsv, lo, hi)
        first = cv2.inRange(hsv, lo, np.array((179, *self.upper[1:]), np.uint8))
        second = cv2.inRange(hsv, np.array((0, *self.lower[1:]), np.uint8), hi)
        return cv2.bitwise_or(first, second)


@dataclass(frozen=True)
class DetectorConfig:
    """Everything the detector can be tuned with (the node maps private params onto this)."""

    green: HsvRange = HsvRange((40, 90, 40), (85, 255, 255))
    orange: HsvRange = HsvRange((5, 130, 60), (22, 255, 255))
    spacing: float = CYLINDER_SPACING
    min_spacing: float = 0.22
    max_spacing: float = 0.25
    radius: float = CYLINDER_RADIUS
    open_kernel: int = 3
    close_kernel: int = 5
    min_area: int = 15
    min_valid_points: int = 6
    depth_gap: float = 0.10
    min_width_fraction: float = 0.25
    max_blobs: int = 10
    partial_height: float = 0.25
    bgr: bool = False
    intrinsics: Intrinsics = field(default_factory=Intrinsics)


@dataclass(frozen=True)
class Blob:
    """One candidate blob: pixel statistics and its estimated cylinder axis (optical x, z)."""

    colour: str
    area: int
    u: float
    v: float
    bbox: tuple[int, int, int, int]
    axis: tuple[float, float]
    centroid_depth: float
    valid_points: int
    cut: bool = False


@dataclass(frozen=True)
class Detection:
    """The chosen pair and what it says about Faulty, with the thesis' variants beside ours."""

    green: Blob
    orange: Blob
    spacing: float
    relative: Relative
    angle_pinhole_2d: float
    angle_thesis: float
    depth_thesis: float

    @property
    def angle(self) -> float:
        return self.relative.angle

    @property
    def depth(self) -> float:
        return self.relative.depth

    @property
    def yaw(self) -> float:
        return self.relative.yaw


@dataclass(frozen=True)
class Partial:
    """One cylinder of Faulty's pair seen without the other (the thesis' self-occlusion case):
    its bearing and depth (of the cylinder's axis); Faulty's heading is unknown."""

    blob: Blob
    angle: float
    depth: float

    @property
    def colour(self) -> str:
        return self.blob.colour


@dataclass
class FrameResult:
    """What the detector found in a frame: the chosen detection (or None), a partial sighting
    when no pair was found but one cylinder was (or None), and all blobs."""

    detection: Detection | None
    blobs: dict[str, list[Blob]]
    partial: Partial | None = None


def _kernel(size: int) -> np.ndarray:
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size, size))


def clean_mask(mask: np.ndarray, config: DetectorConfig) -> np.ndarray:
    """Opening (erode, dilate) to drop specks, then closing (dilate, erode) to fill holes."""
    if config.open_kernel > 1:
        mask = cv2.morphologyEx(mask, cv2.MORPH_OPEN, _kernel(config.open_kernel))
    if config.close_kernel > 1:
        mask = cv2.morphologyEx(mask, cv2.MORPH_CLOSE, _kernel(config.close_kernel))
    return mask


def colour_masks(image: np.ndarray, config: DetectorConfig) -> dict[str, np.ndarray]:
    """Cleaned binary masks of the green and orange pixels of an RGB (or BGR) image."""
    hsv = cv2.cvtColor(image, cv2.COLOR_BGR2HSV if config.bgr else cv2.COLOR_RGB2HSV)
    return {GREEN: clean_mask(config.green.mask(hsv), config),
            ORANGE: clean_mask(config.orange.mask(hsv), config)}


def _centroid_depth(points: np.ndarray, ys: np.ndarray, xs: np.ndarray, u: float,
                    v: float) -> float:
    """z of the valid blob point nearest the centroid pixel (the thesis' centroid depth)."""
    nearest = int(np.argmin((xs - u) ** 2 + (ys - v) ** 2))
    return float(points[nearest, 2])


def _axis_from_surface(points: np.ndarray, radius: float) -> tuple[float, float]:
    """Axis behind the mean visible surface point: ``pi/4 * radius`` further along the ray."""
    sx, sz = (float(c) for c in points[:, (0, 2)].mean(axis=0))
    norm = math.hypot(sx, sz)
    push = radius * math.pi / 4.0
    return (sx + push * sx / norm, sz + push * sz / norm)


def _axis_from_tangent(points: np.ndarray, xs: np.ndarray, cut_left: bool,
                       radius: float) -> tuple[float, float]:
    """Axis of a cylinder cut by the image border, from its one visible silhouette edge.

    The inner edge column looks along a ray tangent to the cylinder; the axis lies ``radius``
    from that tangent point, perpendicular to the ray, on the border's side.
    """
    edge = xs == (xs.max() if cut_left else xs.min())
    tx, tz = (float(c) for c in np.median(points[edge][:, (0, 2)], axis=0))
    norm = math.hypot(tx, tz)
    dx, dz = tx / norm, tz / norm
    side = -1.0 if cut_left else 1.0  # left of the ray is (-dz, dx)
    return (tx + side * radius * dz, tz - side * radius * dx)


def _split_at_depth_edges(sub: np.ndarray, z: np.ndarray, gap: float) -> np.ndarray:
    """``sub`` (a component's pixels with valid depth) minus the far side of every depth jump.

    Where two neighbouring pixels differ in depth by more than ``gap``, the farther one is
    dropped, so a cylinder and a similar-coloured object behind it fall apart while the near
    object keeps all its pixels.
    """
    keep = sub & np.isfinite(z)
    with np.errstate(invalid="ignore"):
        for axis in (0, 1):
            a = z[:-1, :] if axis == 0 else z[:, :-1]
            b = z[1:, :] if axis == 0 else z[:, 1:]
            both = (keep[:-1, :] & keep[1:, :]) if axis == 0 else (keep[:, :-1] & keep[:, 1:])
            jump = both & (np.abs(a - b) > gap)
            first_far, second_far = jump & (a > b), jump & (b > a)
            if axis == 0:
                keep[:-1, :] &= ~first_far
                keep[1:, :] &= ~second_far
            else:
                keep[:, :-1] &= ~first_far
                keep[:, 1:] &= ~second_far
    return keep


def _make_blob(colour: str, xs: np.ndarray, ys: np.ndarray, points: np.ndarray,
               image_width: int, config: DetectorConfig) -> Blob | None:
    """A Blob from one part's pixel coordinates (full image) and their valid 3-D points."""
    size = len(xs)
    if size < max(config.min_valid_points, config.min_area // 2):
        return None
    bx0, by0 = int(xs.min()), int(ys.min())
    bw, bh = int(xs.max()) - bx0 + 1, int(ys.max()) - by0 + 1
    cut_left, cut_right = bx0 == 0, bx0 + bw >= image_width
    expected = 2.0 * config.radius * config.intrinsics.fx / float(np.median(points[:, 2]))
    if bw < config.min_width_fraction * expected and not (cut_left or cut_right):
        return None  # a sliver (e.g. an object seen between Faulty's poles), not a cylinder
    if cut_left != cut_right:
        axis = _axis_from_tangent(points, xs, cut_left, config.radius)
    else:
        axis = _axis_from_surface(points, config.radius)
    u, v = float(xs.mean()), float(ys.mean())
    return Blob(colour, size, u, v, (bx0, by0, bw, bh), axis,
                _centroid_depth(points, ys, xs, u, v), size, cut_left or cut_right)


def blobs_from_component(colour: str, sub: np.ndarray, origin: tuple[int, int],
                         xyz: np.ndarray, config: DetectorConfig) -> list[Blob]:
    """One connected component (boolean ``sub`` at ``origin`` = (x, y) in the image) as
    Blobs, one per depth-continuous part.

    A blob of one colour can join a cylinder and a similar-coloured object behind it; the
    component is cut along depth jumps larger than ``depth_gap`` and each 4-connected part
    with at least ``min_valid_points`` valid depths, and at least ``min_width_fraction`` of a
    cylinder's expected width at its depth (unless cut by the image border), becomes a
    candidate. Pixels without depth are left out of every part: no NaN ever comes out.
    """
    x0, y0 = origin
    h, w = sub.shape
    window = xyz[y0:y0 + h, x0:x0 + w]
    keep = _split_at_depth_edges(sub, window[..., 2], config.depth_gap)
    width = xyz.shape[1]
    if np.array_equal(keep, sub):  # all depths valid, no jump: the component is one part
        ys, xs = np.nonzero(sub)
        blob = _make_blob(colour, xs + x0, ys + y0, window[ys, xs], width, config)
        return [blob] if blob else []
    count, parts = cv2.connectedComponents(keep.astype(np.uint8), connectivity=4)
    blobs = []
    for part in range(1, count):
        ys, xs = np.nonzero(parts == part)
        blob = _make_blob(colour, xs + x0, ys + y0, window[ys, xs], width, config)
        if blob:
            blobs.append(blob)
    return blobs


def find_blobs(colour: str, mask: np.ndarray, xyz: np.ndarray,
               config: DetectorConfig) -> list[Blob]:
    """Candidate blobs of one colour (largest first), each with a cylinder-axis estimate."""
    rx, ry, rw, rh = cv2.boundingRect(mask)  # label only the part of the image with pixels
    if rw == 0 or rh == 0:
        return []
    _, labels, stats, _ = cv2.connectedComponentsWithStats(
        mask[ry:ry + rh, rx:rx + rw], connectivity=8, ltype=cv2.CV_32S)
    order = [i for i in np.argsort(-stats[1:, cv2.CC_STAT_AREA]) + 1
             if stats[i, cv2.CC_STAT_AREA] >= config.min_area][:config.max_blobs]
    blobs = []
    for index in order:
        x0, y0, w, h = (int(v) for v in stats[index, :4])
        sub = labels[y0:y0 + h, x0:x0 + w] == index
        blobs += blobs_from_component(colour, sub, (x0 + rx, y0 + ry), xyz, config)
    return blobs


def pair_distance(green: Blob, orange: Blob) -> float:
    """Horizontal distance of two blobs' cylinder axes (m)."""
    return math.hypot(green.axis[0] - orange.axis[0], green.axis[1] - orange.axis[1])


def _truncated(green: Blob, orange: Blob) -> bool:
    """True when a blob's width may be cut: by the image border, or by the other cylinder in
    front of it (their columns touch), so its axis estimate may be off by up to a radius."""
    if green.cut or orange.cut:
        return True
    g0, g1 = green.bbox[0], green.bbox[0] + green.bbox[2]
    o0, o1 = orange.bbox[0], orange.bbox[0] + orange.bbox[2]
    return g0 <= o1 + 2 and o0 <= g1 + 2


def choose_pair(greens: list[Blob], oranges: list[Blob],
                config: DetectorConfig) -> tuple[Blob, Blob, float] | None:
    """The pair within [min_spacing, max_spacing] closest to ``spacing``, or None.

    For a pair whose blobs may be cut (see :func:`_truncated`) the lower bound is relaxed by
    one cylinder radius.
    """
    best: tuple[Blob, Blob, float] | None = None
    for green in greens:
        for orange in oranges:
            dist = pair_distance(green, orange)
            low = config.min_spacing - (config.radius if _truncated(green, orange) else 0.0)
            if not low <= dist <= config.max_spacing:
                continue
            if best is None or abs(dist - config.spacing) < abs(best[2] - config.spacing):
                best = (green, orange, dist)
    return best


def describe_pair(green: Blob, orange: Blob, dist: float, config: DetectorConfig) -> Detection:
    """Angle, depth and yaw of a chosen pair, plus the thesis' formulas for comparison."""
    cx_pair = (green.u + orange.u) / 2.0
    return Detection(
        green=green, orange=orange, spacing=dist,
        relative=relative_from_axes(green.axis, orange.axis),
        angle_pinhole_2d=config.intrinsics.pinhole_angle_deg(cx_pair),
        angle_thesis=thesis_angle_deg(cx_pair, config.intrinsics.width),
        depth_thesis=(green.centroid_depth + orange.centroid_depth) / 2.0)


def _cylinder_like(blob: Blob, xyz: np.ndarray, config: DetectorConfig) -> bool:
    """A blob that can be one of Faulty's cylinders seen alone: not cut by the image border, about
    a cylinder wide at its depth (half to twice), and at the cylinders' height (its centroid
    within ``partial_height`` of the optical axis, the Kinect being about level with them)."""
    if blob.cut:
        return False
    depth = blob.axis[1]
    expected = 2.0 * config.radius * config.intrinsics.fx / max(depth, 1e-3)
    if not 0.5 * expected <= blob.bbox[2] <= 2.0 * expected:
        return False
    height = (blob.v - config.intrinsics.cy) / config.intrinsics.fy * depth  # optical y, down
    return abs(height) <= config.partial_height


def choose_partial(blobs: dict[str, list[Blob]], xyz: np.ndarray,
                   config: DetectorConfig) -> Partial | None:
    """The largest cylinder-like blob when no pair was found (see :func:`_cylinder_like`)."""
    candidates = [b for colour in (GREEN, ORANGE) for b in blobs[colour]
                  if _cylinder_like(b, xyz, config)]
    if not candidates:
        return None
    best = max(candidates, key=lambda b: b.area)
    return Partial(best, bearing_deg(*best.axis), best.axis[1])


def detect(image: np.ndarray, xyz: np.ndarray,
           config: DetectorConfig | None = None) -> FrameResult:
    """Run the whole pipeline on one frame.

    Args:
        image: HxWx3 uint8, RGB (or BGR with ``config.bgr``).
        xyz: HxWx3 float32 organized point cloud in the optical frame, NaN where no depth.
        config: thresholds and geometry; defaults to :class:`DetectorConfig`.
    """
    config = config or DetectorConfig()
    masks = colour_masks(image, config)
    blobs = {colour: find_blobs(colour, mask, xyz, config) for colour, mask in masks.items()}
    chosen = choose_pair(blobs[GREEN], blobs[ORANGE], config)
    detection = describe_pair(*chosen, config) if chosen else None
    partial = None if detection else choose_partial(blobs, xyz, config)
    return FrameResult(detection, blobs, partial)
