"""Kinect frames with ground truth <-> ROS 1 bags, with the pure-Python ``rosbags`` library.

A bag holds, per frame and at one bag time, the frame in one of three forms (:class:`Form`)
and ``/ground_truth/faulty_relative`` (std_msgs/String, one JSON object, see
:mod:`rason_vision_tools.scenarios`):

* ``raw`` (the simulator's): ``/helper/camera/rgb/image_raw`` (sensor_msgs/Image rgb8) and
  ``/helper/camera/depth_registered/points`` (organized PointCloud2 x, y, z, rgb float32);
* ``kinect`` (what openni / freenect publish): ``/helper/camera/rgb/image_raw``
  (``bayer_grbg8``), ``/helper/camera/rgb/camera_info``,
  ``/helper/camera/depth_registered/image_raw`` (16UC1 mm, 0 = unknown) and
  ``/helper/camera/depth_registered/camera_info``, the depth ones stamped 0.055 s before
  the colour (a TurtleBot's offset);
* ``compressed``: ``/helper/camera/rgb/image_raw/compressed`` (JPEG),
  ``/helper/camera/depth_registered/image_raw/compressedDepth`` (16UC1 PNG) and the depth
  camera_info, stamped as ``kinect``.

The camera_info's intrinsics are fitted from the frame's cloud. Chunks are BZ2
compressed: rosbags' LZ4 chunks are unreadable by ROS 1's ``rosbag`` (ROSLZ4_DATA_ERROR), BZ2
ones are fine (``lz4`` here writes ROS-1-readable LZ4 frames instead). Messages are written
in time order so ``rosbag info``/``play`` agree.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path
from typing import Any

import lz4.frame
import numpy as np
from rosbags.rosbag1 import Reader, Writer
from rosbags.typesys import Stores, get_typestore

from rason_vision.compressed import (
    compressed_depth_fields,
    compressed_depth_to_z,
    compressed_image_fields,
    compressed_to_rgb,
)
from rason_vision.convert import (
    bayer_fields,
    camera_info_fields,
    cloud_fields,
    cloud_to_xyz,
    depth_fields,
    depth_image_to_z,
    image_fields,
    image_to_rgb,
    intrinsics_from_camera_info,
    intrinsics_from_cloud,
    z_to_xyz,
)
from rason_vision_tools.messages import KINECT_BAYER, KINECT_DEPTH_OFFSET

IMAGE_TOPIC = "/helper/camera/rgb/image_raw"
CLOUD_TOPIC = "/helper/camera/depth_registered/points"
RGB_INFO_TOPIC = "/helper/camera/rgb/camera_info"
DEPTH_TOPIC = "/helper/camera/depth_registered/image_raw"
DEPTH_INFO_TOPIC = "/helper/camera/depth_registered/camera_info"
JPEG_TOPIC = IMAGE_TOPIC + "/compressed"
PNG_DEPTH_TOPIC = DEPTH_TOPIC + "/compressedDepth"
TRUTH_TOPIC = "/ground_truth/faulty_relative"
FRAME_ID = "helper/camera_rgb_optical_frame"
DEPTH_FRAME_ID = "helper/camera_rgb_optical_frame"   # registered: the colour camera's frame


class Form(Enum):
    """The form of a bag's frames (see the module docstring)."""

    RAW = "raw"
    KINECT = "kinect"
    COMPRESSED = "compressed"

_STORE = get_typestore(Stores.ROS1_NOETIC)


@dataclass
class Frame:
    """One Kinect frame: RGB image, organized optical-frame point cloud, ground truth."""
    stamp_ns: int
    rgb: np.ndarray
    xyz: np.ndarray
    truth: dict[str, Any] = field(default_factory=dict)


def _header(stamp_ns: int, seq: int, frame_id: str = FRAME_ID) -> Any:
    types = _STORE.types
    stamp = types["builtin_interfaces/msg/Time"](sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)
    return types["std_msgs/msg/Header"](seq=seq, stamp=stamp, frame_id=frame_id)


def _message(msgtype: str, header: Any, fields: dict[str, Any]) -> Any:
    """A rosbags message of `msgtype` (``sensor_msgs/msg/...``) from field values."""
    values = dict(fields)
    if "data" in values and isinstance(values["data"], bytes):
        values["data"] = np.frombuffer(values["data"], dtype=np.uint8)
    if msgtype == "sensor_msgs/msg/CameraInfo":
        values = {k: np.asarray(v, dtype=np.float64) if k in ("D", "K", "R", "P") else v
                  for k, v in values.items()}
        values.update(binning_x=0, binning_y=0, roi=_STORE.types[
            "sensor_msgs/msg/RegionOfInterest"](x_offset=0, y_offset=0, height=0, width=0,
                                                do_rectify=False))
    return _STORE.types[msgtype](header=header, **values)


def frame_records(frame: Frame, seq: int, form: Form) -> list[tuple[str, str, Any]]:
    """``(topic, msgtype, message)`` of one frame in `form` (the truth not included)."""
    if form is Form.RAW:
        return [(IMAGE_TOPIC, "sensor_msgs/msg/Image", image_message(frame, seq)),
                (CLOUD_TOPIC, "sensor_msgs/msg/PointCloud2", cloud_message(frame, seq))]
    colour = _header(frame.stamp_ns, seq)
    depth = _header(frame.stamp_ns + round(KINECT_DEPTH_OFFSET * 1e9), seq, DEPTH_FRAME_ID)
    info = camera_info_fields(intrinsics_from_cloud(frame.xyz))
    z = frame.xyz[..., 2]
    depth_info = (DEPTH_INFO_TOPIC, "sensor_msgs/msg/CameraInfo",
                  _message("sensor_msgs/msg/CameraInfo", depth, info))
    if form is Form.KINECT:
        return [(IMAGE_TOPIC, "sensor_msgs/msg/Image",
                 _message("sensor_msgs/msg/Image", colour, bayer_fields(frame.rgb, KINECT_BAYER))),
                (RGB_INFO_TOPIC, "sensor_msgs/msg/CameraInfo",
                 _message("sensor_msgs/msg/CameraInfo", colour, info)),
                (DEPTH_TOPIC, "sensor_msgs/msg/Image",
                 _message("sensor_msgs/msg/Image", depth, depth_fields(z))), depth_info]
    return [(JPEG_TOPIC, "sensor_msgs/msg/CompressedImage",
             _message("sensor_msgs/msg/CompressedImage", colour,
                      compressed_image_fields(frame.rgb))),
            (PNG_DEPTH_TOPIC, "sensor_msgs/msg/CompressedImage",
             _message("sensor_msgs/msg/CompressedImage", depth, compressed_depth_fields(z))),
            depth_info]


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


def write_bag(path: str | Path, frames: Iterable[Frame], compression: str = "bz2",
              form: Form = Form.RAW) -> int:
    """Write frames (in time order) to a ROS 1 bag in `form`; return how many.

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
        conns: dict[str, Any] = {}

        def write(topic: str, msgtype: str, msg: Any, t: int) -> None:
            if topic not in conns:
                conns[topic] = writer.add_connection(topic, msgtype, typestore=_STORE)
            writer.write(conns[topic], t, _STORE.serialize_ros1(msg, msgtype))

        last = -1
        for seq, frame in enumerate(frames):
            if frame.stamp_ns <= last:
                raise ValueError("frames must be in increasing time order")
            last = t = frame.stamp_ns
            for topic, msgtype, msg in frame_records(frame, seq, form):
                write(topic, msgtype, msg, t)
            text = json.dumps(frame.truth, sort_keys=True)
            write(TRUTH_TOPIC, "std_msgs/msg/String",
                  _STORE.types["std_msgs/msg/String"](data=text), t)
            count += 1
    return count


def _parts(topic: str, msg: Any) -> dict[str, Any]:
    """What one message of a frame contributes to it (see :func:`read_bag`)."""
    if topic == IMAGE_TOPIC:
        return {"rgb": image_to_rgb(msg)}
    if topic == JPEG_TOPIC:
        return {"rgb": compressed_to_rgb(msg)}
    if topic == CLOUD_TOPIC:
        return {"xyz": np.array(cloud_to_xyz(msg))}
    if topic == DEPTH_TOPIC:
        return {"z": depth_image_to_z(msg)}
    if topic == PNG_DEPTH_TOPIC:
        return {"z": compressed_depth_to_z(msg)}
    if topic == DEPTH_INFO_TOPIC:
        return {"info": intrinsics_from_camera_info(msg)}
    if topic == TRUTH_TOPIC:
        return {"truth": json.loads(msg.data)}
    return {}


def read_bag(path: str | Path) -> Iterator[Frame]:
    """Frames of a bag written by :func:`write_bag` in any form (a frame's messages joined by
    bag time; a depth image made a cloud with its camera_info)."""
    pending: dict[int, dict[str, Any]] = {}
    with Reader(Path(path)) as reader:
        for conn, t, raw in reader.messages():
            msg: Any = _STORE.deserialize_ros1(raw, conn.msgtype)
            parts = _parts(conn.topic, msg)
            if not parts:
                continue
            frame = pending.setdefault(t, {})
            frame.update(parts)
            if {"z", "info"} <= frame.keys():
                frame["xyz"] = z_to_xyz(frame.pop("z"), frame.pop("info"))
            if {"rgb", "xyz", "truth"} <= frame.keys():
                del pending[t]
                yield Frame(t, frame["rgb"], frame["xyz"], frame["truth"])
