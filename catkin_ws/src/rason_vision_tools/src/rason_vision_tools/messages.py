"""Rendered frames as the ROS messages a Kinect driver publishes (for tests and benchmarks)."""

from __future__ import annotations

import numpy as np
from sensor_msgs.msg import Image, PointCloud2, PointField

from rason_vision.convert import cloud_fields, image_fields


def frame_messages(rgb: np.ndarray, xyz: np.ndarray) -> tuple[Image, PointCloud2]:
    """An ``rgb8`` Image and an organized x, y, z, rgb PointCloud2 of one rendered frame
    (headers left empty: the caller stamps them)."""
    image = image_fields(rgb)
    image["data"] = image["data"].tobytes()
    cloud = cloud_fields(xyz, rgb)
    cloud["fields"] = [PointField(name=name, offset=offset, datatype=datatype, count=count)
                       for name, offset, datatype, count in cloud["fields"]]
    cloud["data"] = cloud["data"].tobytes()
    return Image(**image), PointCloud2(**cloud)
