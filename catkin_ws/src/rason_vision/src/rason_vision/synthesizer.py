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
``~slop`` [0.05] s and ``~queue_size`` [10] of the synchronizer and subscribers,
``~buff_size`` [1048576] of the subscribers; ``~timing`` [false] logs, per frame, the pair's
age at the callback (header stamp to message-in), the processing time and the age when the
perception is published; ``~perception_ttl`` [0.5] s (about 7 frame periods of the 15 Hz
Kinect): declared as the parameter ``jason/perception_ttl/<source>``, so an agent clears this
source's percepts when no frame has been processed for that long (camera unplugged, node dead);
0 declares nothing.
"""

from __future__ import annotations

import sys
import time
from typing import Any

from rason_vision.convert import cloud_to_xyz, image_to_rgb
from rason_vision.detector import DetectorConfig, HsvRange, detect
from rason_vision.geometry import format_literal

#: Seconds an agent keeps this node's last list without a new frame (about 7 frames at 15 Hz).
PERCEPTION_TTL = 0.5


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


class RobotSynthesizer:
    """The node's state: detector configuration, the publisher and the synchronizer."""

    def __init__(self) -> None:
        import message_filters
        import rospy
        from jason_msgs.msg import Perception
        from sensor_msgs.msg import Image, PointCloud2

        self._rospy = rospy
        self._perception = Perception
        self.config = config_from_params(rospy.get_param)
        self.robot_name = str(rospy.get_param("~robot_name", "faulty"))
        self.source = rospy.get_name().rsplit("/", 1)[-1] + "_robot"
        self.perception_ttl = float(rospy.get_param("~perception_ttl", PERCEPTION_TTL))
        self.declare_ttl()            # before the first publication, so agents find it at once
        self.publisher = rospy.Publisher("jason/perception", Perception, queue_size=10)
        # rospy's receive buffer: 1 MB measured faster than 64 kB or 16 MB for 5 MB clouds.
        big = int(rospy.get_param("~buff_size", 1 << 20))
        # Room for bursts (rosbag play catching up, a busy CPU) so no frame pair is lost;
        # processing takes a few ms, far below a frame period, so the queues stay short.
        queue = int(rospy.get_param("~queue_size", 10))
        image_sub = message_filters.Subscriber("camera/rgb/image_raw", Image, queue_size=queue,
                                               buff_size=big, tcp_nodelay=True)
        cloud_sub = message_filters.Subscriber("camera/depth_registered/points", PointCloud2,
                                               queue_size=queue, buff_size=big, tcp_nodelay=True)
        self.sync = message_filters.ApproximateTimeSynchronizer(
            [image_sub, cloud_sub], queue_size=queue, slop=float(rospy.get_param("~slop", 0.05)))
        self.sync.registerCallback(self.on_frame)
        self.frames = 0
        self.timing = bool(rospy.get_param("~timing", False))

    def declare_ttl(self) -> None:
        """Tell agents how long this source's list stays valid (also after a master restart)."""
        if self.perception_ttl > 0:
            self._rospy.set_param(f"jason/perception_ttl/{self.source}", self.perception_ttl)

    def perceptions(self, image_msg: Any, cloud_msg: Any) -> list[str]:
        """The complete perception list for one frame pair."""
        result = detect(image_to_rgb(image_msg), cloud_to_xyz(cloud_msg), self.config)
        det = result.detection
        if det is None:
            return []
        return [format_literal(self.robot_name, det.angle, det.depth, det.yaw)]

    def on_frame(self, image_msg: Any, cloud_msg: Any) -> None:
        """Synchronizer callback: detect and publish (an empty list when nothing is seen)."""
        start = time.perf_counter()
        entry_age = (self._rospy.Time.now() - cloud_msg.header.stamp).to_sec() if self.timing \
            else 0.0
        try:
            literals = self.perceptions(image_msg, cloud_msg)
        except ValueError as err:
            self._rospy.logwarn_throttle(5.0, f"robot_synthesizer: bad frame: {err}")
            literals = []
        self.publisher.publish(self._perception(source=self.source, perception=literals))
        self.frames += 1
        if self.timing:
            done = time.perf_counter()
            age = (self._rospy.Time.now() - cloud_msg.header.stamp).to_sec()
            self._rospy.loginfo(f"timing frame {self.frames}: stamp to callback "
                                f"{entry_age * 1000:.1f} ms, processing "
                                f"{(done - start) * 1000:.1f} ms, stamp to published "
                                f"{age * 1000:.1f} ms")
        self._rospy.logdebug(f"frame {self.frames}: {literals}")


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``rosrun rason_vision robot_synthesizer``."""
    import rospy

    from rason.ros.master_watch import watch_master

    rospy.init_node("robot_synthesizer", argv=argv if argv is not None else sys.argv)
    node = RobotSynthesizer()
    watch_master(on_registered=[node.declare_ttl])
    rospy.loginfo(f"robot_synthesizer: publishing {rospy.resolve_name('jason/perception')} "
                  f"as {node.source}")
    rospy.spin()
    return 0
