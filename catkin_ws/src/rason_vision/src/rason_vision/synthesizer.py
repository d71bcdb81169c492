"""``rosrun rason_vision robot_synthesizer``: Kinect frames in, ``robot(...)`` perceptions out.

Subscribes (relative names, so ``__ns:=/helper`` puts them under the robot):

* ``camera/rgb/image_raw`` (sensor_msgs/Image, rgb8 or bgr8)
* ``camera/depth_registered/points`` (sensor_msgs/PointCloud2, organized, float32 x y z)

paired by timestamp with ``message_filters.ApproximateTimeSynchronizer``. For every pair it
publishes a ``jason_msgs/Perception`` on ``jason/perception`` with source
``<node_name>_robot`` and the complete current list: ``["robot(faulty,Angle,Depth,Yaw)"]`` or
``[]`` (thesis 5.4). Conventions of Angle/Depth/Yaw: :mod:`rason_vision.geometry`.

Private parameters (defaults in brackets):
``~robot_name`` [faulty], ``~green_lower``/``~green_upper`` [[40,90,40]/[85,255,255]],
``~orange_lower``/``~orange_upper`` [[5,130,60]/[22,255,255]] (OpenCV HSV),
``~spacing`` [0.227], ``~tolerance_low``/``~tolerance_high`` [0.007/0.023] (pairs within
``[spacing - low, spacing + high]`` = [0.22, 0.25] m), ``~radius`` [0.03],
``~max_pixels`` [4194304]: larger frames are refused. ``~slop``, ``~queue_size``,
``~buff_size``, ``~source``, ``~timing``, ``~perception_ttl`` [0.5 s, about 7 frame periods of
the 15 Hz Kinect]: as every synthesizer (:mod:`rason.execution.synthesizer`).

Bad frames (empty, truncated, huge, image and cloud of different sizes, a cloud with no valid
depth at all) are rejected with a rate-limited warning and publish nothing; the node carries on.
"""

from __future__ import annotations

import sys
from typing import Any

import numpy as np
from sensor_msgs.msg import Image, PointCloud2

from rason.execution.synthesizer import BadFrame, Synthesizer, run
from rason_vision.convert import MAX_PIXELS, cloud_to_xyz, image_to_rgb
from rason_vision.detector import DetectorConfig, HsvRange, detect
from rason_vision.geometry import format_literal


def config_from_params(get: Any) -> DetectorConfig:
    """A DetectorConfig from private parameters; ``get(name, default)`` is rospy.get_param."""
    base = DetectorConfig()

    def hsv(name: str, default: tuple[int, int, int]) -> tuple[int, int, int]:
        value = get(f"~{name}", list(default))
        return (int(value[0]), int(value[1]), int(value[2]))

    spacing = float(get("~spacing", base.spacing))
    low = float(get("~tolerance_low", round(base.spacing - base.min_spacing, 6)))
    high = float(get("~tolerance_high", round(base.max_spacing - base.spacing, 6)))
    return DetectorConfig(
        green=HsvRange(hsv("green_lower", base.green.lower), hsv("green_upper", base.green.upper)),
        orange=HsvRange(hsv("orange_lower", base.orange.lower),
                        hsv("orange_upper", base.orange.upper)),
        spacing=spacing, min_spacing=spacing - low, max_spacing=spacing + high,
        radius=float(get("~radius", base.radius)))


class RobotSynthesizer(Synthesizer):
    """Kinect image + organized cloud pairs -> ``robot(Name, Angle, Depth, Yaw)``."""

    inputs = (("camera/rgb/image_raw", Image), ("camera/depth_registered/points", PointCloud2))
    source_suffix = "_robot"
    #: About 7 frame periods of the 15 Hz Kinect: a camera silent that long is gone.
    perception_ttl = 0.5

    def setup(self) -> None:
        import rospy

        self.config = config_from_params(rospy.get_param)
        self.robot_name = str(rospy.get_param("~robot_name", "faulty"))
        self.max_pixels = int(rospy.get_param("~max_pixels", MAX_PIXELS))

    def perceive(self, image_msg: Any, cloud_msg: Any) -> list[str]:
        """The complete perception list for one frame pair."""
        rgb = image_to_rgb(image_msg, self.max_pixels)
        xyz = cloud_to_xyz(cloud_msg, self.max_pixels)
        if rgb.shape[:2] != xyz.shape[:2]:
            raise BadFrame(f"image {rgb.shape[1]}x{rgb.shape[0]} and cloud "
                           f"{xyz.shape[1]}x{xyz.shape[0]} differ in size")
        if not np.isfinite(xyz[..., 2]).any():
            raise BadFrame("the cloud has no valid depth point")
        det = detect(rgb, xyz, self.config).detection
        if det is None:
            return []
        return [format_literal(self.robot_name, det.angle, det.depth, det.yaw)]


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``rosrun rason_vision robot_synthesizer``."""
    return run(RobotSynthesizer, "robot_synthesizer", argv if argv is not None else sys.argv)
