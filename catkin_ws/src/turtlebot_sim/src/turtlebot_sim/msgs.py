"""ROS messages built from the simulation's numbers and numpy arrays (no cv_bridge)."""

from __future__ import annotations

import math

import genpy
import numpy as np
from geometry_msgs.msg import Quaternion
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import Image, PointCloud2, PointField

from turtlebot_model.cloud import unpack_rgb

#: kobuki_node's odometry covariances (no gyro fusion): x, y 0.1; yaw 0.2; the rest "unused".
_POSE_COV = [0.0] * 36
_POSE_COV[0] = _POSE_COV[7] = 0.1
_POSE_COV[14] = _POSE_COV[21] = _POSE_COV[28] = 1e6
_POSE_COV[35] = 0.2
_TWIST_COV = list(_POSE_COV)

CLOUD_FIELDS = [PointField(name=n, offset=4 * i, datatype=PointField.FLOAT32, count=1)
                for i, n in enumerate(("x", "y", "z", "rgb"))]


def stamp(seconds: float) -> genpy.Time:
    """Sim seconds -> a ROS time, rounded to the nanosecond."""
    ns = round(seconds * 1e9)
    return genpy.Time(ns // 1_000_000_000, ns % 1_000_000_000)


def clock(seconds: float) -> Clock:
    return Clock(clock=stamp(seconds))


def yaw_quaternion(yaw: float) -> Quaternion:
    return Quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))


def odometry(t: float, frame: str, child: str, x: float, y: float, yaw: float, v: float,
             w: float, pose_covariance: list[float] | None = None,
             twist_covariance: list[float] | None = None) -> Odometry:
    """A planar nav_msgs/Odometry (twist in the child frame, as kobuki_node sends it); the
    covariances default to this profile's (see ``_POSE_COV``)."""
    msg = Odometry()
    msg.header.stamp = stamp(t)
    msg.header.frame_id = frame
    msg.child_frame_id = child
    msg.pose.pose.position.x = x
    msg.pose.pose.position.y = y
    msg.pose.pose.orientation = yaw_quaternion(yaw)
    msg.pose.covariance = _POSE_COV if pose_covariance is None else pose_covariance
    msg.twist.twist.linear.x = v
    msg.twist.twist.angular.z = w
    msg.twist.covariance = _TWIST_COV if twist_covariance is None else twist_covariance
    return msg


def image(t: float, frame: str, rgb: np.ndarray) -> Image:
    """sensor_msgs/Image, encoding rgb8, from an HxWx3 uint8 array."""
    h, w, _ = rgb.shape
    msg = Image(height=h, width=w, encoding="rgb8", is_bigendian=0, step=3 * w)
    msg.header.stamp = stamp(t)
    msg.header.frame_id = frame
    msg.data = np.ascontiguousarray(rgb, dtype=np.uint8).tobytes()
    return msg


def cloud(t: float, frame: str, packed: np.ndarray) -> PointCloud2:
    """Organised sensor_msgs/PointCloud2 (x, y, z, rgb float32) from an HxWx4 float32 array."""
    h, w, _ = packed.shape
    msg = PointCloud2(height=h, width=w, fields=CLOUD_FIELDS, is_bigendian=False,
                      point_step=16, row_step=16 * w, is_dense=False)
    msg.header.stamp = stamp(t)
    msg.header.frame_id = frame
    msg.data = np.ascontiguousarray(packed, dtype="<f4").tobytes()
    return msg


def cloud_to_arrays(msg: PointCloud2) -> tuple[np.ndarray, np.ndarray]:
    """Inverse of :func:`cloud` for x, y, z, rgb at offsets 0/4/8/12: (xyz HxWx3, rgb HxWx3)."""

    raw = np.frombuffer(msg.data, dtype="<f4").reshape(msg.height, msg.width,
                                                       msg.point_step // 4)
    return raw[:, :, :3], unpack_rgb(raw[:, :, 3])
