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


#: Largest frame converted by default (pixels): 2048 x 2048, ample for a Kinect's 640 x 480.
MAX_PIXELS = 1 << 22


def _buffer(data: Any) -> np.ndarray:
    if isinstance(data, np.ndarray):
        return data.view(np.uint8).reshape(-1)
    return np.frombuffer(data, dtype=np.uint8)


def _dimensions(kind: str, height: Any, width: Any, max_pixels: int) -> tuple[int, int]:
    """Checked frame dimensions: positive, and at most `max_pixels` pixels."""
    height, width = int(height), int(width)
    if height <= 0 or width <= 0:
        raise ValueError(f"empty {kind}: {width}x{height}")
    if height * width > max_pixels:
        raise ValueError(f"{kind} of {width}x{height} is larger than {max_pixels} pixels")
    return height, width


def _needs(kind: str, flat: np.ndarray, rows: int, row_step: int, row_bytes: int) -> None:
    """Refuse a buffer too short for `rows` rows of `row_bytes` bytes, `row_step` apart."""
    if row_step < row_bytes:
        raise ValueError(f"{kind}: row step {row_step} is shorter than a row ({row_bytes} bytes)")
    needed = (rows - 1) * row_step + row_bytes
    if flat.size < needed:
        raise ValueError(f"{kind}: {flat.size} bytes of data, the header needs {needed}")


def image_to_rgb(msg: Any, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """An ``rgb8``/``bgr8``/``rgba8``/``bgra8`` Image as an HxWx3 RGB uint8 array.

    Raises ValueError for an unknown encoding, an empty or oversized image, or data shorter
    than its header says (checked before any array view).
    """
    channels = {"rgb8": 3, "bgr8": 3, "rgba8": 4, "bgra8": 4}.get(msg.encoding)
    if channels is None:
        raise ValueError(f"unsupported image encoding {msg.encoding!r}")
    height, width = _dimensions("image", msg.height, msg.width, max_pixels)
    flat = _buffer(msg.data)
    step = int(msg.step)
    _needs("image", flat, height, step, width * channels)
    rows = np.lib.stride_tricks.as_strided(
        flat, shape=(height, width * channels), strides=(step, 1), writeable=False)
    image = rows.reshape(height, width, channels)[..., :3]
    if msg.encoding.startswith("bgr"):
        image = image[..., ::-1]
    return np.ascontiguousarray(image)


def cloud_to_xyz(msg: Any, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """An organized PointCloud2's x, y, z as an HxWx3 float32 array.

    NaN where there is no depth, including points at z <= 0 (a sensor's "no reading"). Raises
    ValueError for missing or non-float32 x, y, z fields, an empty or oversized cloud, fields
    outside the point, or data shorter than its header says (checked before any array view).
    """
    offsets = {f.name: int(f.offset) for f in msg.fields}
    types = {f.name: f.datatype for f in msg.fields}
    if any(types.get(axis) != FLOAT32 for axis in "xyz"):
        raise ValueError("PointCloud2 needs float32 x, y, z fields")
    if msg.is_bigendian:
        raise ValueError("big-endian PointCloud2 is not supported")
    height, width = _dimensions("cloud", max(int(msg.height), 1), msg.width, max_pixels)
    point_step = int(msg.point_step)
    ox, oy, oz = offsets["x"], offsets["y"], offsets["z"]
    if min(ox, oy, oz) < 0 or max(ox, oy, oz) + 4 > point_step:
        raise ValueError(f"cloud: x, y, z fields at {ox}, {oy}, {oz} do not fit a "
                         f"{point_step}-byte point")
    flat = _buffer(msg.data)
    row_step = int(msg.row_step)
    _needs("cloud", flat, height, row_step, width * point_step)
    rows = np.lib.stride_tricks.as_strided(
        flat, shape=(height, width * point_step), strides=(row_step, 1), writeable=False)
    points = rows.reshape(height, width, point_step)
    if point_step % 4 == 0 and (oy, oz) == (ox + 4, ox + 8) and ox % 4 == 0:
        xyz = np.ascontiguousarray(points).view(np.float32)[..., ox // 4:ox // 4 + 3].copy()
    else:
        xyz = np.stack([np.ascontiguousarray(points[..., o:o + 4]).view(np.float32)[..., 0]
                        for o in (ox, oy, oz)], axis=-1)
    with np.errstate(invalid="ignore"):
        xyz[~(xyz[..., 2] > 0.0)] = np.nan
    return xyz


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
