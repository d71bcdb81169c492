"""sensor_msgs Image / PointCloud2 <-> numpy, with numpy only (no cv_bridge, no rospy).

The functions take any object with the message's fields, so they work on rospy messages
(``data`` is ``bytes``) and on rosbags messages (``data`` is a numpy uint8 array) alike.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from turtlebot_model.cloud import FIELD_OFFSETS, POINT_STEP, pack_cloud

#: sensor_msgs/PointField datatype FLOAT32.
FLOAT32 = 7
#: Layout of the clouds we write: x, y, z, rgb (float32 each, rgb packed as 0x00RRGGBB).


def _buffer(data: Any) -> np.ndarray:
    if isinstance(data, np.ndarray):
        return data.view(np.uint8).reshape(-1)
    return np.frombuffer(data, dtype=np.uint8)


def image_to_rgb(msg: Any) -> np.ndarray:
    """An ``rgb8``/``bgr8``/``rgba8``/``bgra8`` Image as an HxWx3 RGB uint8 array."""
    channels = {"rgb8": 3, "bgr8": 3, "rgba8": 4, "bgra8": 4}.get(msg.encoding)
    if channels is None:
        raise ValueError(f"unsupported image encoding {msg.encoding!r}")
    flat = _buffer(msg.data)
    rows = np.lib.stride_tricks.as_strided(
        flat, shape=(msg.height, msg.width * channels), strides=(msg.step, 1))
    image = rows.reshape(msg.height, msg.width, channels)[..., :3]
    if msg.encoding.startswith("bgr"):
        image = image[..., ::-1]
    return np.ascontiguousarray(image)


def cloud_to_xyz(msg: Any) -> np.ndarray:
    """An organized PointCloud2's x, y, z as an HxWx3 float32 array (NaN kept)."""
    offsets = {f.name: f.offset for f in msg.fields}
    types = {f.name: f.datatype for f in msg.fields}
    if any(types.get(axis) != FLOAT32 for axis in "xyz"):
        raise ValueError("PointCloud2 needs float32 x, y, z fields")
    if msg.is_bigendian:
        raise ValueError("big-endian PointCloud2 is not supported")
    flat = _buffer(msg.data)
    height, width = max(int(msg.height), 1), int(msg.width)
    rows = np.lib.stride_tricks.as_strided(
        flat, shape=(height, width * msg.point_step), strides=(msg.row_step, 1))
    points = rows.reshape(height, width, msg.point_step)
    ox, oy, oz = offsets["x"], offsets["y"], offsets["z"]
    if msg.point_step % 4 == 0 and (oy, oz) == (ox + 4, ox + 8) and ox % 4 == 0:
        as_float = np.ascontiguousarray(points).view(np.float32)
        return as_float[..., ox // 4:ox // 4 + 3]
    return np.stack([np.ascontiguousarray(points[..., o:o + 4]).view(np.float32)[..., 0]
                     for o in (ox, oy, oz)], axis=-1)


def image_fields(rgb: np.ndarray) -> dict[str, Any]:
    """Field values of an ``rgb8`` sensor_msgs/Image (data as a uint8 array)."""
    height, width = rgb.shape[:2]
    return {"height": height, "width": width, "encoding": "rgb8", "is_bigendian": 0,
            "step": width * 3, "data": np.ascontiguousarray(rgb, dtype=np.uint8).reshape(-1)}


def cloud_fields(xyz: np.ndarray, rgb: np.ndarray) -> dict[str, Any]:
    """Field values of an organized x, y, z, rgb float32 PointCloud2 (fields as name/offset).

    ``fields`` is a list of ``(name, offset, datatype, count)`` tuples for the caller to wrap in
    its own PointField type.
    """
    height, width = xyz.shape[:2]
    packed = pack_cloud(xyz, rgb)
    return {"height": height, "width": width,
            "fields": [(name, offset, FLOAT32, 1) for name, offset in FIELD_OFFSETS.items()],
            "is_bigendian": False, "point_step": POINT_STEP,
            "row_step": POINT_STEP * width, "data": packed.view(np.uint8).reshape(-1),
            "is_dense": False}
