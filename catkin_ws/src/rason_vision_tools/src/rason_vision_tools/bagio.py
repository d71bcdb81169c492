"""Kinect frames with ground truth <-> ROS 1 bags, with the pure-Python ``rosbags`` library.

A bag holds, per frame and with one timestamp: ``/helper/camera/rgb/image_raw``
(sensor_msgs/Image rgb8), ``/helper/camera/depth_registered/points`` (organized
sensor_msgs/PointCloud2 x, y, z, rgb float32) and ``/ground_truth/faulty_relative``
(std_msgs/String, one JSON object, see :mod:`rason_vision_tools.scenarios`). Chunks are BZ2
compressed: rosbags' LZ4 chunks are unreadable by ROS 1's ``rosbag`` (ROSLZ4_DATA_ERROR), BZ2
ones are fine (``lz4`` here writes ROS-1-readable LZ4 frames instead). Messages are written
in time order so ``rosbag info``/``play`` agree.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import lz4.frame
import numpy as np
from rosbags.rosbag1 import Reader, Writer
from rosbags.typesys import Stores, get_typestore

from rason_vision.convert import cloud_fields, cloud_to_xyz, image_fields, image_to_rgb

IMAGE_TOPIC = "/helper/camera/rgb/image_raw"
CLOUD_TOPIC = "/helper/camera/depth_registered/points"
TRUTH_TOPIC = "/ground_truth/faulty_relative"
FRAME_ID = "helper/camera_rgb_optical_frame"

_STORE = get_typestore(Stores.ROS1_NOETIC)


@dataclass
class Frame:
    """One Kinect frame: RGB image, organized optical-frame point cloud, ground truth."""
    stamp_ns: int
    rgb: np.ndarray
    xyz: np.ndarray
    truth: dict[str, Any] = field(default_factory=dict)


def _header(stamp_ns: int, seq: int) -> Any:
    types = _STORE.types
    stamp = types["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    return types["std_msgs/msg/Header"](seq=seq, stamp=stamp, frame_id=FRAME_ID)


def image_message(frame: Frame, seq: int) -> Any:
    """A rosbags sensor_msgs/Image for the frame."""
    return _STORE.types["sensor_msgs/msg/Image"](header=_header(frame.stamp_ns, seq),
                                                 **image_fields(frame.rgb))


def cloud_message(frame: Frame, seq: int) -> Any:
    """A rosbags sensor_msgs/PointCloud2 for the frame."""
    values = cloud_fields(frame.xyz, frame.rgb)
    point_field = _STORE.types["sensor_msgs/msg/PointField"]
    values["fields"] = [point_field(name=n, offset=o, datatype=d, count=c)
                        for n, o, d, c in values["fields"]]
    return _STORE.types["sensor_msgs/msg/PointCloud2"](header=_header(frame.stamp_ns, seq),
                                                       **values)


def _ros1_lz4(data: bytes) -> bytes:
    """LZ4 frames as ROS 1's roslz4 reads them (rosbags' own LZ4 chunks are unreadable)."""
    return lz4.frame.compress(data, block_linked=False, content_checksum=True, store_size=False)


def write_bag(path: str | Path, frames: Iterable[Frame], compression: str = "bz2") -> int:
    """Write frames (in time order) to a ROS 1 bag; return how many.

    ``compression``: ``bz2`` (smallest, slow), ``lz4`` (fast; frames ROS 1 can read) or ``none``.
    """
    path = Path(path)
    path.unlink(missing_ok=True)
    count = 0
    writer = Writer(path)
    if compression == "bz2":
        writer.set_compression(Writer.CompressionFormat.BZ2)
    elif compression == "lz4":
        writer.set_compression(Writer.CompressionFormat.LZ4)
        writer.compressor = _ros1_lz4
    elif compression != "none":
        raise ValueError(f"unknown compression {compression!r}")
    with writer:
        conns = {
            "image": writer.add_connection(IMAGE_TOPIC, "sensor_msgs/msg/Image", typestore=_STORE),
            "cloud": writer.add_connection(CLOUD_TOPIC, "sensor_msgs/msg/PointCloud2",
                                           typestore=_STORE),
            "truth": writer.add_connection(TRUTH_TOPIC, "std_msgs/msg/String", typestore=_STORE),
        }
        last = -1
        for seq, frame in enumerate(frames):
            if frame.stamp_ns <= last:
                raise ValueError("frames must be in increasing time order")
            last = frame.stamp_ns
            t = frame.stamp_ns
            writer.write(conns["image"], t, _STORE.serialize_ros1(
                image_message(frame, seq), "sensor_msgs/msg/Image"))
            writer.write(conns["cloud"], t, _STORE.serialize_ros1(
                cloud_message(frame, seq), "sensor_msgs/msg/PointCloud2"))
            text = json.dumps(frame.truth, sort_keys=True)
            writer.write(conns["truth"], t, _STORE.serialize_ros1(
                _STORE.types["std_msgs/msg/String"](data=text), "std_msgs/msg/String"))
            count += 1
    return count


def read_bag(path: str | Path) -> Iterator[Frame]:
    """Frames of a bag written by :func:`write_bag` (image, cloud and truth joined by stamp)."""
    pending: dict[int, dict[str, Any]] = {}
    with Reader(Path(path)) as reader:
        for conn, t, raw in reader.messages():
            msg: Any = _STORE.deserialize_ros1(raw, conn.msgtype)
            if conn.topic == IMAGE_TOPIC:
                stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
                pending.setdefault(stamp, {})["rgb"] = image_to_rgb(msg)
            elif conn.topic == CLOUD_TOPIC:
                stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
                pending.setdefault(stamp, {})["xyz"] = np.array(cloud_to_xyz(msg))
            elif conn.topic == TRUTH_TOPIC:
                stamp = t
                pending.setdefault(stamp, {})["truth"] = json.loads(msg.data)
            else:
                continue
            parts = pending[stamp]
            if {"rgb", "xyz", "truth"} <= parts.keys():
                del pending[stamp]
                yield Frame(stamp, parts["rgb"], parts["xyz"], parts["truth"])
