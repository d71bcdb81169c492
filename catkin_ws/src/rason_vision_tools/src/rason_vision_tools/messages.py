"""Rendered frames as the ROS messages a Kinect driver publishes (for tests and benchmarks).

Three forms of one frame (headers left empty: the caller stamps them):

* :func:`frame_messages`: the simulator's ``rgb8`` Image and organized x, y, z, rgb cloud
  (:func:`driver_cloud_message`: the same cloud in depth_image_proc's 32-byte layout);
* :func:`kinect_messages`: what openni / freenect publish: ``bayer_grbg8``
  ``rgb/image_raw``, the 16UC1 registered ``depth_registered/image_raw`` (mm, 0 = unknown)
  and its CameraInfo;
* :func:`compressed_messages`: the same through image_transport's ``compressed`` (JPEG) and
  ``compressedDepth`` (PNG) transports, with the CameraInfo.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from sensor_msgs.msg import CameraInfo, CompressedImage, Image, PointCloud2, PointField

from rason_vision.compressed import compressed_depth_fields, compressed_image_fields
from rason_vision.convert import (
    bayer_fields,
    camera_info_fields,
    cloud_fields,
    depth_fields,
    image_fields,
)
from rason_vision.geometry import Intrinsics
from turtlebot_model.cloud import pack_rgb

#: The Kinect's colour pattern (both drivers) and its depth stamp offset on a TurtleBot (s).
KINECT_BAYER = "grbg"
KINECT_DEPTH_OFFSET = -0.055
#: Bytes a point in depth_image_proc's point_cloud_xyzrgb clouds.
DRIVER_POINT_STEP = 32


def _image(fields: dict[str, Any]) -> Image:
    fields = dict(fields)
    fields["data"] = np.asarray(fields["data"]).tobytes()
    return Image(**fields)


def frame_messages(rgb: np.ndarray, xyz: np.ndarray) -> tuple[Image, PointCloud2]:
    """An ``rgb8`` Image and an organized x, y, z, rgb PointCloud2 of one rendered frame."""
    cloud = cloud_fields(xyz, rgb)
    cloud["fields"] = [PointField(name=name, offset=offset, datatype=datatype, count=count)
                       for name, offset, datatype, count in cloud["fields"]]
    cloud["data"] = cloud["data"].tobytes()
    return _image(image_fields(rgb)), PointCloud2(**cloud)


def driver_cloud_message(rgb: np.ndarray, xyz: np.ndarray) -> PointCloud2:
    """The organized cloud as depth_image_proc's ``point_cloud_xyzrgb`` lays it out: x, y, z
    at 0, 4, 8 and the packed rgb at 16, 32 bytes a point, NaN where there is no depth."""
    height, width = xyz.shape[:2]
    points = np.zeros((height, width, DRIVER_POINT_STEP // 4), dtype=np.float32)
    points[..., :3] = xyz
    points[..., 4] = pack_rgb(rgb)
    fields = [PointField(name=name, offset=offset, datatype=PointField.FLOAT32, count=1)
              for name, offset in (("x", 0), ("y", 4), ("z", 8), ("rgb", 16))]
    return PointCloud2(height=height, width=width, fields=fields, is_bigendian=False,
                       point_step=DRIVER_POINT_STEP, row_step=DRIVER_POINT_STEP * width,
                       data=points.tobytes(), is_dense=False)


def kinect_messages(rgb: np.ndarray, xyz: np.ndarray, intrinsics: Intrinsics,
                    depth_encoding: str = "16UC1") -> tuple[Image, Image, CameraInfo]:
    """A Kinect driver's ``bayer_grbg8`` colour, registered depth image (``16UC1`` mm or
    ``32FC1`` m) and CameraInfo of one rendered frame (`xyz`'s z is the depth)."""
    return (_image(bayer_fields(rgb, KINECT_BAYER)),
            _image(depth_fields(xyz[..., 2], depth_encoding)),
            CameraInfo(**camera_info_fields(intrinsics)))


def compressed_messages(rgb: np.ndarray, xyz: np.ndarray, intrinsics: Intrinsics
                        ) -> tuple[CompressedImage, CompressedImage, CameraInfo]:
    """The ``compressed`` (JPEG) colour, ``compressedDepth`` (16UC1 PNG) depth and CameraInfo
    of one rendered frame."""
    return (CompressedImage(**compressed_image_fields(rgb)),
            CompressedImage(**compressed_depth_fields(xyz[..., 2])),
            CameraInfo(**camera_info_fields(intrinsics)))
