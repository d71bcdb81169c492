"""``rosrun rason_vision robot_synthesizer``: Kinect frames in, ``robot(...)`` perceptions out.

Subscribes (relative names, so ``__ns:=/helper`` puts them under the robot), as
``~colour_transport`` and ``~depth_input`` choose (:class:`Inputs`):

* colour: ``camera/rgb/image_raw`` (sensor_msgs/Image in any encoding a Kinect driver
  publishes: Bayer, rgb8, bgr8, mono8, ...; :data:`rason_vision.convert.COLOUR_ENCODINGS`),
  or its ``compressed`` transport ``camera/rgb/image_raw/compressed`` (JPEG/PNG);
* depth: ``camera/depth_registered/points`` (organized PointCloud2, float32 x y z at any
  offsets, NaN holes; the intrinsics are fitted from the first cloud), or the registered
  depth image ``camera/depth_registered/image_raw`` (16UC1 mm or 32FC1 m) or its
  ``compressedDepth`` transport ``.../image_raw/compressedDepth``, each with
  ``camera/depth_registered/camera_info`` (the intrinsics: K);

paired by timestamp with ``message_filters.ApproximateTimeSynchronizer`` (``~slop`` fits a
Kinect's depth stamps, 0.055 s before the colour's on a TurtleBot). For every pair it
publishes a ``jason_msgs/Perception`` on ``jason/perception`` with source
``<node_name>_robot`` and the complete current list: ``["robot(faulty,Angle,Depth,Yaw)"]`` or
``[]`` (thesis 5.4); when only one cylinder is seen (the other hidden behind it),
``["robot_partial(faulty,Angle,Depth,Colour)"]``: that cylinder's bearing and depth, yaw
unknown. Conventions of Angle/Depth/Yaw: :mod:`rason_vision.geometry`.

With ``~odom_bearings`` it also subscribes ``odom`` (nav_msgs/Odometry) and adds to a sighting
``seen_at(Name,Heading)``: the sighting's Angle as a heading of the robot's own odometry frame
(degrees, positive clockwise as Angle, in (-180, 180]), from the robot's heading at the frame's
stamp. A motion decomposer's ``turn_to(Heading)`` then faces what was seen however late the
percept reached the agent, and while the robot was still turning.

Private parameters: :class:`RobotParams` (``rosrun rason_vision robot_synthesizer --help``
prints them), those of every synthesizer (:mod:`rason.execution.synthesizer`) included.

Bad frames (empty, truncated, huge, image and cloud of different sizes, a cloud with no valid
depth at all) are rejected with a rate-limited warning and publish nothing; the node carries on.
"""

from __future__ import annotations

import bisect
import dataclasses
import math
import sys
import threading
from collections import deque
from dataclasses import dataclass
from enum import Enum
from typing import Any, NamedTuple

import numpy as np
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, CompressedImage, Image, PointCloud2

from rason.execution.synthesizer import BadFrame, Synthesizer, SynthesizerParams, run
from rason_vision.colours import load_colours
from rason_vision.compressed import compressed_depth_to_z, compressed_to_rgb
from rason_vision.convert import (
    MAX_PIXELS,
    cloud_to_xyz,
    depth_image_to_z,
    image_to_rgb,
    intrinsics_from_camera_info,
    intrinsics_from_cloud,
    z_to_xyz,
)
from rason_vision.detector import GREEN, ORANGE, DetectorConfig, HsvRange, detect
from rason_vision.geometry import format_literal, format_partial_literal
from rosnode_kit.params import param
from turtlebot_model.geometry import angle_diff_deg, wrap_deg, yaw_from_quaternion

_BASE = DetectorConfig()


class ColourTransport(Enum):
    """How the colour image arrives (``~colour_transport``)."""

    RAW = "raw"                    # camera/rgb/image_raw, sensor_msgs/Image
    COMPRESSED = "compressed"      # camera/rgb/image_raw/compressed, JPEG or PNG


class DepthInput(Enum):
    """What carries the depth (``~depth_input``)."""

    CLOUD = "cloud"                # camera/depth_registered/points
    IMAGE = "image"                # camera/depth_registered/image_raw + camera_info
    COMPRESSED = "compressed"      # .../image_raw/compressedDepth + camera_info


COLOUR_TOPIC = "camera/rgb/image_raw"
CLOUD_TOPIC = "camera/depth_registered/points"
DEPTH_TOPIC = "camera/depth_registered/image_raw"
INFO_TOPIC = "camera/depth_registered/camera_info"


@dataclass(frozen=True)
class Inputs:
    """The topics and message types the node synchronizes for a choice of inputs."""

    colour: ColourTransport
    depth: DepthInput

    def topics(self) -> tuple[tuple[str, type], ...]:
        """``(topic, type)`` of the colour, the depth and (for a depth image) its camera_info."""
        colour = ((COLOUR_TOPIC, Image) if self.colour is ColourTransport.RAW
                  else (COLOUR_TOPIC + "/compressed", CompressedImage))
        if self.depth is DepthInput.CLOUD:
            return (colour, (CLOUD_TOPIC, PointCloud2))
        depth = ((DEPTH_TOPIC, Image) if self.depth is DepthInput.IMAGE
                 else (DEPTH_TOPIC + "/compressedDepth", CompressedImage))
        return (colour, depth, (INFO_TOPIC, CameraInfo))

    @classmethod
    def from_params(cls, colour: str, depth: str) -> Inputs:
        """The inputs named by ``~colour_transport`` and ``~depth_input`` (ValueError if not)."""
        try:
            return cls(ColourTransport(colour), DepthInput(depth))
        except ValueError:
            raise ValueError(f"~colour_transport must be one of "
                             f"{[c.value for c in ColourTransport]} and ~depth_input one of "
                             f"{[d.value for d in DepthInput]}; got {colour!r}, {depth!r}"
                             ) from None


@dataclass(frozen=True)
class RobotParams(SynthesizerParams):
    """The robot synthesizer's private parameters (HSV as OpenCV's: H 0-179, S and V 0-255)."""

    robot_name: str = param("faulty", "the observed robot's name in robot(Name, ...)")
    colour_transport: str = param("raw", "raw: camera/rgb/image_raw (Image: Bayer, rgb8, bgr8, "
                                  "mono8, ...); compressed: camera/rgb/image_raw/compressed "
                                  "(JPEG/PNG CompressedImage)")
    depth_input: str = param("cloud", "cloud: camera/depth_registered/points (organized "
                             "PointCloud2); image: camera/depth_registered/image_raw (16UC1 mm "
                             "or 32FC1 m) + camera/depth_registered/camera_info; compressed: "
                             ".../image_raw/compressedDepth (PNG) + the camera_info")
    colours: str = param("", "YAML file of the cylinders' colour ranges (rosrun rason_vision "
                         "calibrate writes it); when set, it replaces the *_lower/*_upper "
                         "parameters")
    slop: float = param(0.075, "s by which paired colour and depth stamps may differ: a "
                        "Kinect's depth is stamped 0.055 s before its colour", minimum=0.0)
    green_lower: list[str] = param(list(_BASE.green.lower), "HSV lower bound of green")
    green_upper: list[str] = param(list(_BASE.green.upper), "HSV upper bound of green")
    orange_lower: list[str] = param(list(_BASE.orange.lower), "HSV lower bound of orange")
    orange_upper: list[str] = param(list(_BASE.orange.upper), "HSV upper bound of orange")
    spacing: float = param(_BASE.spacing, "distance of the cylinders' axes (m)", minimum=0.01)
    tolerance_low: float = param(round(_BASE.spacing - _BASE.min_spacing, 6),
                                 "pairs closer than spacing minus this are not Faulty (m)",
                                 minimum=0.0)
    tolerance_high: float = param(round(_BASE.max_spacing - _BASE.spacing, 6),
                                  "pairs farther than spacing plus this are not Faulty (m)",
                                  minimum=0.0)
    radius: float = param(_BASE.radius, "cylinder radius (m)", minimum=0.001)
    max_pixels: int = param(MAX_PIXELS, "larger frames are refused", minimum=1)
    perception_ttl: float = param(0.5, "s the robot(...) percept stays valid after the last "
                                  "frame: about 7 periods of the 15 Hz Kinect", minimum=0.0)
    odom_bearings: bool = param(False, "also report seen_at(Name, Heading): a sighting's bearing "
                                "as a heading of the robot's odometry frame (odom) at the "
                                "frame's time, degrees clockwise; and annotate [moving] a "
                                "sighting whose frame was not taken with the camera at rest")
    frame_stamps: bool = param(False, "annotate every sighting [stamp(Ms)] and add frame(Ms) to "
                               "every frame's list, with or without a sighting: the frame's "
                               "time, milliseconds of ROS time (the agents' .time(T))")
    rest_margin: float = param(0.1, "s the odometry must show the camera at rest before a "
                               "frame's stamp (and up to its newest message) for the frame "
                               "not to be [moving]", minimum=0.0)


#: the camera is at rest while its odometry pose stays within these of the newest one
REST_TURN_DEG = 0.3
REST_MOVE_M = 0.005
#: the newest odometry may be this much older than a frame (one or two 50 Hz periods)
ODOM_LAG_S = 0.05


class OdomSample(NamedTuple):
    """One odometry message: its time (s), heading (degrees clockwise) and position (m)."""

    t: float
    heading: float
    x: float
    y: float


class HeadingHistory:
    """The robot's recent odometry headings (degrees clockwise, as a camera bearing) and
    positions by time, to read the heading at a camera frame's stamp and whether the camera was
    at rest then."""

    def __init__(self, seconds: float = 5.0) -> None:
        self.seconds = seconds
        self._samples: deque[OdomSample] = deque()
        self._lock = threading.Lock()

    def add(self, t: float, heading: float, x: float = 0.0, y: float = 0.0) -> None:
        with self._lock:
            if self._samples and t < self._samples[-1].t:    # time went back (a sim reset)
                self._samples.clear()
            self._samples.append(OdomSample(t, heading, x, y))
            while self._samples and self._samples[0].t < t - self.seconds:
                self._samples.popleft()

    def at_rest(self, t: float, margin: float) -> bool:
        """Whether the odometry shows the robot at rest from `margin` s before `t` up to its
        newest sample (so at `t`, and in the pose it has now): the newest sample must be at
        most ODOM_LAG_S older than `t`, and the history must reach back to `t` - `margin`."""
        with self._lock:
            samples = list(self._samples)
        if not samples or samples[-1].t < t - ODOM_LAG_S:
            return False                       # the odometry does not know `t` yet
        first = bisect.bisect_right(_times(samples), t - margin) - 1
        if first < 0:
            return False                       # nothing as old as `t` - `margin`
        now = samples[-1]
        return all(abs(angle_diff_deg(s.heading, now.heading)) <= REST_TURN_DEG
                   and math.hypot(s.x - now.x, s.y - now.y) <= REST_MOVE_M
                   for s in samples[first:])

    def at(self, t: float, tolerance: float = 0.1) -> float | None:
        """The heading at time `t`, interpolated between the samples around it; None when no
        sample lies within `tolerance` s of it."""
        with self._lock:
            samples = list(self._samples)
        if not samples:
            return None
        i = bisect.bisect_left(_times(samples), t)
        if i == len(samples):
            last = samples[-1]
            return last.heading if t - last.t <= tolerance else None
        after = samples[i]
        if i == 0 or after.t == t:
            return after.heading if after.t - t <= tolerance else None
        before = samples[i - 1]
        turned = angle_diff_deg(after.heading, before.heading)
        return wrap_deg(before.heading + turned * (t - before.t) / (after.t - before.t))


def _times(samples: list[OdomSample]) -> list[float]:
    """The samples' times, to bisect (bisect's key= is Python 3.10+; the robots run 3.8)."""
    return [sample.t for sample in samples]


def sighting_annotations(t: float, headings: HeadingHistory | None, rest_margin: float,
                         stamps: bool) -> str:
    """``[moving,stamp(Ms)]`` for a frame taken at `t` (s): ``moving`` when `headings` (the
    robot's odometry) does not show the camera at rest from `rest_margin` s before `t` up to
    now; ``stamp`` when `stamps`, in whole milliseconds. ``""`` when neither applies."""
    annots = []
    if headings is not None and not headings.at_rest(t, rest_margin):
        annots.append("moving")
    if stamps:
        annots.append(f"stamp({round(t * 1000.0)})")
    return f"[{','.join(annots)}]" if annots else ""


def frame_literal(t: float) -> str:
    """``frame(Ms)``: a frame was processed, taken at `t` (s), in whole milliseconds."""
    return f"frame({round(t * 1000.0)})"


def _hsv(name: str, value: list[str]) -> tuple[int, int, int]:
    try:
        h, s, v = (int(float(x)) for x in value)
    except ValueError:
        raise ValueError(f"~{name}: expected three numbers H, S, V, got {value}") from None
    if not (0 <= h <= 179 and 0 <= s <= 255 and 0 <= v <= 255):
        raise ValueError(f"~{name}: H must be in 0-179, S and V in 0-255, got {value}")
    return (h, s, v)


def config_from_params(p: RobotParams) -> DetectorConfig:
    """The detector's configuration from the node's parameters (ValueError if inconsistent)."""
    if p.colours:
        ranges = load_colours(p.colours)
        green, orange = ranges[GREEN], ranges[ORANGE]
    else:
        green = HsvRange(_hsv("green_lower", p.green_lower), _hsv("green_upper", p.green_upper))
        orange = HsvRange(_hsv("orange_lower", p.orange_lower),
                          _hsv("orange_upper", p.orange_upper))
    return DetectorConfig(
        green=green, orange=orange,
        spacing=p.spacing, min_spacing=p.spacing - p.tolerance_low,
        max_spacing=p.spacing + p.tolerance_high, radius=p.radius)


class RobotSynthesizer(Synthesizer):
    """Kinect colour + depth (cloud or depth image) -> ``robot(Name, Angle, Depth, Yaw)``."""

    inputs = Inputs(ColourTransport.RAW, DepthInput.CLOUD).topics()
    source_suffix = "_robot"
    Params = RobotParams

    def setup(self) -> None:
        self.config = config_from_params(self.params)
        self.choice = Inputs.from_params(self.params.colour_transport, self.params.depth_input)
        self.cloud_intrinsics: dict[tuple[int, ...], Any] = {}
        self.inputs = self.choice.topics()
        self.robot_name: str = self.params.robot_name
        self.max_pixels: int = self.params.max_pixels
        self.headings: HeadingHistory | None = None
        if self.params.odom_bearings:
            self.headings = HeadingHistory()
            rospy.Subscriber("odom", Odometry, self.on_odom, queue_size=50)

    def on_odom(self, msg: Odometry) -> None:
        q = msg.pose.pose.orientation
        yaw = yaw_from_quaternion(q.x, q.y, q.z, q.w)
        p = msg.pose.pose.position
        if math.isfinite(yaw) and math.isfinite(p.x) and math.isfinite(p.y):
            assert self.headings is not None
            self.headings.add(msg.header.stamp.to_sec(), wrap_deg(-math.degrees(yaw)), p.x, p.y)

    def seen_at(self, stamp: Any, angle: float) -> list[str]:
        """``[seen_at(Name,Heading)]`` for a sighting at `angle` in a frame of `stamp`, or []."""
        if self.headings is None:
            return []
        heading = self.headings.at(stamp.to_sec())
        if heading is None:
            return []
        return [f"seen_at({self.robot_name},{wrap_deg(heading + angle):.1f})"]

    def annotations(self, stamp: Any) -> str:
        """The annotations of a sighting in a frame of `stamp`: ``[moving,stamp(Ms)]``, each
        when its parameter asks for it; ``""`` for none."""
        return sighting_annotations(stamp.to_sec(), self.headings, self.params.rest_margin,
                                    self.params.frame_stamps)

    def frame_arrays(self, colour_msg: Any, depth_msg: Any,
                     info_msg: Any = None) -> tuple[np.ndarray, np.ndarray, Any]:
        """RGB, organized cloud and intrinsics of one synchronized set of messages."""
        if self.choice.colour is ColourTransport.RAW:
            rgb = image_to_rgb(colour_msg, self.max_pixels)
        else:
            rgb = compressed_to_rgb(colour_msg, self.max_pixels)
        if self.choice.depth is DepthInput.CLOUD:
            xyz = cloud_to_xyz(depth_msg, self.max_pixels)
            if not np.isfinite(xyz[..., 2]).any():
                raise BadFrame("the cloud has no valid depth point")
            intrinsics = self.cloud_intrinsics.get(xyz.shape[:2])
            if intrinsics is None:     # one camera's clouds keep their intrinsics: fit once
                intrinsics = self.cloud_intrinsics[xyz.shape[:2]] = intrinsics_from_cloud(xyz)
        else:
            intrinsics = intrinsics_from_camera_info(info_msg)
            z = (depth_image_to_z(depth_msg, self.max_pixels)
                 if self.choice.depth is DepthInput.IMAGE
                 else compressed_depth_to_z(depth_msg, self.max_pixels))
            if not np.isfinite(z).any():
                raise BadFrame("the depth image has no valid depth")
            xyz = z_to_xyz(z, intrinsics)
        if rgb.shape[:2] != xyz.shape[:2]:
            raise BadFrame(f"image {rgb.shape[1]}x{rgb.shape[0]} and depth "
                           f"{xyz.shape[1]}x{xyz.shape[0]} differ in size")
        return rgb, xyz, intrinsics

    def perceive(self, colour_msg: Any, depth_msg: Any, info_msg: Any = None) -> list[str]:
        """The complete perception list for one synchronized set of frames."""
        rgb, xyz, intrinsics = self.frame_arrays(colour_msg, depth_msg, info_msg)
        if self.config.intrinsics != intrinsics:
            self.config = dataclasses.replace(self.config, intrinsics=intrinsics)
        stamp = colour_msg.header.stamp
        percepts = self.sightings(detect(rgb, xyz, self.config), stamp)
        if self.params.frame_stamps:
            percepts.append(frame_literal(stamp.to_sec()))
        return percepts

    def sightings(self, result: Any, stamp: Any) -> list[str]:
        """The percepts of one detection result in a frame of `stamp`."""
        det = result.detection
        if det is not None:
            return [format_literal(self.robot_name, det.angle, det.depth, det.yaw)
                    + self.annotations(stamp), *self.seen_at(stamp, det.angle)]
        if result.partial is not None:
            part = result.partial
            return [format_partial_literal(self.robot_name, part.angle, part.depth, part.colour)
                    + self.annotations(stamp), *self.seen_at(stamp, part.angle)]
        return []


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``rosrun rason_vision robot_synthesizer``."""
    return run(RobotSynthesizer, "robot_synthesizer", argv if argv is not None else sys.argv,
               usage="rosrun rason_vision robot_synthesizer [__ns:=/helper] [_name:=value ...]")
