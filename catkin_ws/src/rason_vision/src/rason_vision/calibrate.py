"""Calibrate the cylinders' colour ranges from frames, for the synthesizer's ``_colours:=FILE``.

``rosrun rason_vision calibrate`` reads frames of a live topic or a bag and writes the YAML
file the synthesizer loads with ``_colours:=FILE``.

The user names where each cylinder is: ``_green:=x,y,w,h`` and ``_orange:=x,y,w,h`` (a region;
``x,y`` alone is the 7 x 7 window around a pixel), or ``_labels:=labels.png``, a single-channel
image of the frame's size whose pixels are 1 on the green cylinder and 2 on the orange one.
The same places are read in each of ``~frames`` frames (from ``~skip`` on) and one range per
cylinder is fitted to all their pixels (:func:`rason_vision.colours.fit_range`). Frames come
from ``~bag`` (read with ROS 1's rosbag API; no roscore needed), or else from the live
``~topic`` (an Image in any Kinect encoding, or a ``.../compressed`` CompressedImage).

It prints the ranges and, per cylinder, the share of its named pixels inside its range and
how many pixels elsewhere in the frames fall inside it too (candidates for false blobs).
"""

from __future__ import annotations

import sys
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml

from rason_vision.colours import (
    CYLINDERS,
    LABELS,
    MIN_SATURATION,
    Margins,
    Region,
    fit_range,
    save_colours,
    to_hsv,
)
from rason_vision.compressed import compressed_to_rgb
from rason_vision.convert import image_to_rgb
from rason_vision.detector import HsvRange
from rosnode_kit.params import ParamError, exit_on_help, param, parse, unknown_names

USAGE = ("rosrun rason_vision calibrate [_snapshot:=frame.png] _out:=colours.yaml "
         "(_green:=x,y,w,h _orange:=x,y,w,h | _labels:=labels.png) [_bag:=file.bag] "
         "[_topic:=camera/rgb/image_raw] [__ns:=/helper]")


@dataclass(frozen=True)
class CalibrateParams:
    """The calibration's private parameters."""

    out: str = param("", "the colours file (YAML) to write (required unless only taking a "
                     "~snapshot)")
    snapshot: str = param("", "also write the first frame used here (PNG): open it in an "
                          "image viewer to read the cylinders' pixels, or paint a labels image "
                          "on it")
    green: str = param("", "where the green cylinder is: x,y,w,h (a region) or x,y (a pixel)")
    orange: str = param("", "where the orange cylinder is: x,y,w,h or x,y")
    labels: str = param("", "a labels image (PNG, the frame's size): 1 = green, 2 = orange; "
                        "instead of the regions")
    bag: str = param("", "read the frames from this bag (else from the live topic)")
    topic: str = param("camera/rgb/image_raw", "the colour topic: an Image in any Kinect "
                       "encoding, or a .../compressed CompressedImage; in a bag, the topic "
                       "whose name ends with it")
    frames: int = param(1, "frames to fit the ranges to", minimum=1)
    skip: int = param(0, "frames to pass over first", minimum=0)
    timeout: float = param(10.0, "s to wait for each live frame", minimum=0.1)
    hue_margin: int = param(Margins.hue, "hue units added either side of the pixels' spread",
                            minimum=0, maximum=30)
    saturation_factor: float = param(Margins.saturation, "lower S bound: this times the "
                                     "pixels' 2nd percentile of S", minimum=0.0, maximum=1.0)
    value_factor: float = param(Margins.value, "lower V bound: this times the pixels' 2nd "
                                "percentile of V (room for shadow)", minimum=0.0, maximum=1.0)


def rgb_of(msg: Any) -> np.ndarray:
    """A colour message (Image or CompressedImage) as RGB."""
    return compressed_to_rgb(msg) if hasattr(msg, "format") else image_to_rgb(msg)


def bag_frames(path: str, topic: str) -> Iterator[np.ndarray]:
    """The colour frames of `topic` (the bag's topic ending with it) in a bag."""
    import rosbag

    with rosbag.Bag(path) as bag:
        topics = list(bag.get_type_and_topic_info().topics)
        wanted = [t for t in topics if t.rstrip("/").endswith(topic.strip("/"))]
        if not wanted:
            raise ValueError(f"{path}: no topic ends with {topic} (it has {', '.join(topics)})")
        for _, msg, _ in bag.read_messages(topics=wanted[:1]):
            yield rgb_of(msg)


def live_frames(topic: str, timeout: float) -> Iterator[np.ndarray]:
    """Colour frames as they arrive on a live topic."""
    import rospy
    from sensor_msgs.msg import CompressedImage, Image

    kind = CompressedImage if topic.rstrip("/").endswith("/compressed") else Image
    while not rospy.is_shutdown():
        try:
            msg = rospy.wait_for_message(topic, kind, timeout=timeout)
        except rospy.ROSException:
            raise ValueError(f"no frame on {rospy.resolve_name(topic)} within {timeout} s"
                             ) from None
        yield rgb_of(msg)


def masks_of(p: CalibrateParams, shape: tuple[int, int]) -> dict[str, np.ndarray]:
    """Per cylinder, the boolean mask of its named pixels in a frame of `shape` (h, w)."""
    if p.labels:
        labels = cv2.imread(p.labels, cv2.IMREAD_UNCHANGED)
        if labels is None:
            raise ValueError(f"cannot read the labels image {p.labels}")
        if labels.ndim == 3:
            labels = labels[..., 0]
        if labels.shape != shape:
            raise ValueError(f"labels image {p.labels} is {labels.shape[1]}x{labels.shape[0]}, "
                             f"the frames {shape[1]}x{shape[0]}")
        return {name: labels == LABELS[name] for name in CYLINDERS}
    masks = {}
    for name in CYLINDERS:
        text = getattr(p, name)
        if not text:
            raise ValueError(f"name where the {name} cylinder is (_{name}:=x,y,w,h) or give "
                             f"_labels:=labels.png")
        masks[name] = Region.parse(text).mask(shape)
    return masks


@dataclass
class Report:
    """Per cylinder: its range, the share of its named pixels inside it, and the pixels
    outside the named ones that fall inside it."""

    ranges: dict[str, HsvRange]
    inside: dict[str, float]
    elsewhere: dict[str, int]

    def text(self) -> str:
        return "\n".join(
            f"{name}: lower {list(r.lower)} upper {list(r.upper)}; "
            f"{self.inside[name]:.0%} of the named pixels inside, "
            f"{self.elsewhere[name]} other pixels inside" for name, r in self.ranges.items())


def calibrate(frames: list[np.ndarray], masks: dict[str, np.ndarray],
              margins: Margins) -> Report:
    """Fit each cylinder's range to its pixels in every frame."""
    hsvs = [to_hsv(rgb) for rgb in frames]
    ranges, inside, elsewhere = {}, {}, {}
    for name, mask in masks.items():
        pixels = np.concatenate([hsv[mask] for hsv in hsvs])
        try:
            ranges[name] = fit_range(pixels, margins)
        except ValueError as err:
            raise ValueError(f"{name}: {err}") from None
        hits = [ranges[name].mask(hsv) > 0 for hsv in hsvs]
        coloured = pixels[:, 1] >= MIN_SATURATION
        named_hits = np.concatenate([hit[mask] for hit in hits])
        inside[name] = float(named_hits[coloured].mean()) if coloured.any() else 0.0
        elsewhere[name] = int(sum((hit & ~mask).sum() for hit in hits))
    return Report(ranges, inside, elsewhere)


def run(p: CalibrateParams, argv: list[str]) -> Report | None:
    """Read the frames, fit, write the file; the report (None when only a snapshot was
    asked for)."""
    if p.bag:
        source: Iterator[np.ndarray] = bag_frames(p.bag, p.topic)
    else:
        from rosnode_kit.signals import init_node

        init_node("calibrate", argv=argv, anonymous=True)
        source = live_frames(p.topic, p.timeout)
    frames = []
    for index, rgb in enumerate(source):
        if index >= p.skip:
            frames.append(rgb)
        if len(frames) == p.frames:
            break
    if not frames:
        raise ValueError(f"no frame after skipping {p.skip}")
    if p.snapshot:
        if not cv2.imwrite(p.snapshot, cv2.cvtColor(frames[0], cv2.COLOR_RGB2BGR)):
            raise ValueError(f"cannot write the snapshot {p.snapshot}")
        if not (p.out or p.labels or p.green or p.orange):
            return None
    if not p.out:
        raise ValueError("~out is required: the colours file to write")
    masks = masks_of(p, frames[0].shape[:2])
    report = calibrate(frames, masks, Margins(p.hue_margin, p.saturation_factor,
                                              p.value_factor))
    where = f"bag {Path(p.bag).name}" if p.bag else f"topic {p.topic}"
    named = f"labels {Path(p.labels).name}" if p.labels else f"green {p.green}, orange {p.orange}"
    save_colours(p.out, report.ranges,
                 f"rosrun rason_vision calibrate: {len(frames)} frame(s) of {where}, {named}")
    return report


def private_args(argv: list[str]) -> dict[str, Any]:
    """``_name:=value`` arguments as a mapping (values read as YAML, as rosrun does)."""
    given = {}
    for arg in argv[1:]:
        if arg.startswith("_") and not arg.startswith("__") and ":=" in arg:
            name, value = arg[1:].split(":=", 1)
            given[name] = yaml.safe_load(value) if value else ""
    return given


def main(argv: list[str] | None = None) -> int:
    """Entry point; exit status 2 for bad parameters or frames that cannot be calibrated."""
    argv = list(argv if argv is not None else sys.argv)
    summary = __doc__.strip().split("\n")[0] if __doc__ else ""
    exit_on_help(argv, CalibrateParams, USAGE, summary)
    given = private_args(argv)
    for warning in unknown_names(CalibrateParams, given):     # a typo is not silently ignored
        print(f"calibrate: {warning}", file=sys.stderr)
    try:
        params = parse(CalibrateParams, given)
        report = run(params, argv)
    except (ParamError, ValueError, OSError) as err:
        print(f"calibrate: {err}", file=sys.stderr)
        return 2
    if params.snapshot:
        print(f"wrote the frame {params.snapshot}")
    if report is not None:
        print(report.text())
        print(f"wrote {params.out}: rosrun rason_vision robot_synthesizer "
              f"_colours:={params.out}")
    return 0
