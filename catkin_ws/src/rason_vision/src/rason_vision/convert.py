"""sensor_msgs Image / PointCloud2 / CameraInfo <-> numpy, with numpy and OpenCV (no
cv_bridge, no rospy).

The functions take any object with the message's fields, so they work on rospy messages
(``data`` is ``bytes``) and on rosbags messages (``data`` is a numpy uint8 array) alike.
OpenCV's ``cvtColor`` demosaics Bayer images (the PyPI OpenCV the detector already uses;
Debian's cv_bridge would bring a second OpenCV into the process).
"""

from __future__ import annotations

import math
from typing import Any

import cv2
import numpy as np

from rason_vision.geometry import Intrinsics
from turtlebot_model.cloud import FIELD_OFFSETS, POINT_STEP, pack_cloud

#: sensor_msgs/PointField datatype FLOAT32.
FLOAT32 = 7
#: Layout of the clouds we write: x, y, z, rgb (float32 each, rgb packed as 0x00RRGGBB).


#: Largest frame converted by default (pixels): 2048 x 2048, ample for a Kinect's 640 x 480.
MAX_PIXELS = 1 << 22


def buffer_of(data: Any) -> np.ndarray:
    if isinstance(data, np.ndarray):
        return data.view(np.uint8).reshape(-1)
    return np.frombuffer(data, dtype=np.uint8)


def checked_dimensions(kind: str, height: Any, width: Any, max_pixels: int) -> tuple[int, int]:
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


#: OpenCV's demosaicing code per ROS Bayer pattern (OpenCV names a pattern by the second row's
#: second and third pixels, ROS by the first row's first two: ``grbg`` is OpenCV's ``GB``).
BAYER_CODES = {"rggb": cv2.COLOR_BayerBG2RGB, "bggr": cv2.COLOR_BayerRG2RGB,
               "gbrg": cv2.COLOR_BayerGR2RGB, "grbg": cv2.COLOR_BayerGB2RGB}
#: Offsets (row, column) of the red, green (two) and blue samples in a ROS Bayer pattern's 2x2.
_BAYER_SITES = {pattern: {c: [(i // 2, i % 2) for i, x in enumerate(pattern) if x == c]
                          for c in "rgb"} for pattern in BAYER_CODES}
#: Colour encodings read (sensor_msgs/image_encodings): channels, and the RGB channel order.
_COLOUR = {"rgb": (3, (0, 1, 2)), "bgr": (3, (2, 1, 0)), "rgba": (4, (0, 1, 2)),
           "bgra": (4, (2, 1, 0)), "mono": (1, (0, 0, 0))}
#: Every colour encoding :func:`image_to_rgb` accepts (for messages and --help).
COLOUR_ENCODINGS = (*(f"{kind}{bits}" for kind in _COLOUR for bits in (8, 16)),
                    *(f"bayer_{p}{bits}" for p in BAYER_CODES for bits in (8, 16)), "yuv422")


def _pixels(kind: str, msg: Any, channels: int, dtype: np.dtype,
            max_pixels: int) -> np.ndarray:
    """An Image's data as an HxWxC array of ``dtype`` (a copy), its size checked first."""
    height, width = checked_dimensions(kind, msg.height, msg.width, max_pixels)
    flat = buffer_of(msg.data)
    step = int(msg.step)
    row_bytes = width * channels * dtype.itemsize
    _needs(kind, flat, height, step, row_bytes)
    rows = np.lib.stride_tricks.as_strided(flat, shape=(height, row_bytes), strides=(step, 1),
                                           writeable=False)
    if getattr(msg, "is_bigendian", False):
        dtype = dtype.newbyteorder(">")
    return np.ascontiguousarray(rows).view(dtype).reshape(height, width, channels)


def image_to_rgb(msg: Any, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """A colour sensor_msgs/Image in any encoding a Kinect driver publishes as HxWx3 RGB uint8.

    Encodings: :data:`COLOUR_ENCODINGS`: rgb8/bgr8/rgba8/bgra8 and their 16-bit forms, mono8/16
    (grey: every channel the same), the four Bayer patterns (``bayer_grbg8`` is what openni and
    freenect publish as ``rgb/image_raw``), demosaiced with OpenCV's bilinear method as
    image_proc's debayer does, and yuv422 (UYVY). Raises ValueError for another encoding, an
    empty or oversized image, or data shorter than its header says (checked before any view).
    """
    encoding = str(msg.encoding).lower()
    if encoding == "yuv422":
        packed = _pixels("image", msg, 2, np.dtype(np.uint8), max_pixels)
        return cv2.cvtColor(packed, cv2.COLOR_YUV2RGB_UYVY)
    bits = 16 if encoding.endswith("16") else 8
    kind = encoding[:-len(str(bits))] if encoding.endswith(str(bits)) else ""
    dtype = np.dtype(np.uint16 if bits == 16 else np.uint8)
    if kind.startswith("bayer_") and kind[6:] in BAYER_CODES:
        raw = _pixels("image", msg, 1, dtype, max_pixels)[..., 0]
        if bits == 16:
            raw = (raw >> 8).astype(np.uint8)
        return cv2.cvtColor(raw, BAYER_CODES[kind[6:]])
    if kind not in _COLOUR:
        raise ValueError(f"unsupported image encoding {msg.encoding!r} (read: "
                         f"{', '.join(COLOUR_ENCODINGS)})")
    channels, order = _COLOUR[kind]
    image = _pixels("image", msg, channels, dtype, max_pixels)[..., list(order)]
    if bits == 16:
        image = image >> 8
    return np.ascontiguousarray(image, dtype=np.uint8)


def bayer_mosaic(rgb: np.ndarray, pattern: str = "grbg") -> np.ndarray:
    """The HxW raw image a Bayer sensor of `pattern` (ROS order, e.g. ``grbg``) takes of `rgb`."""
    raw = np.empty(rgb.shape[:2], dtype=np.uint8)
    for channel, colour in enumerate("rgb"):
        for dy, dx in _BAYER_SITES[pattern][colour]:
            raw[dy::2, dx::2] = rgb[dy::2, dx::2, channel]
    return raw


#: Depth encodings :func:`depth_image_to_z` reads: scale to metres, and "no reading" values.
DEPTH_ENCODINGS: dict[str, tuple[np.dtype, float]] = {
    "16uc1": (np.dtype(np.uint16), 0.001), "mono16": (np.dtype(np.uint16), 0.001),
    "32fc1": (np.dtype(np.float32), 1.0)}


def depth_image_to_z(msg: Any, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """A registered depth Image as HxW float32 metres along the optical axis, NaN = no depth.

    ``16UC1`` is millimetres with 0 = unknown (openni / freenect ``depth_registered/image_raw``),
    ``32FC1`` metres with NaN (depth_image_proc's ``convert_metric``). Raises ValueError for
    another encoding, an empty or oversized image, or data shorter than its header says.
    """
    spec = DEPTH_ENCODINGS.get(str(msg.encoding).lower())
    if spec is None:
        raise ValueError(f"unsupported depth encoding {msg.encoding!r} (read: 16UC1 mm, "
                         f"32FC1 m)")
    dtype, scale = spec
    depth = _pixels("depth image", msg, 1, dtype, max_pixels)[..., 0]
    z = depth.astype(np.float32) * np.float32(scale)
    with np.errstate(invalid="ignore"):
        z[~((z > 0.0) & np.isfinite(z))] = np.nan
    return z


def depth_millimetres(z: np.ndarray) -> np.ndarray:
    """Metres (NaN = none) as a Kinect's 16UC1 depth image: rounded millimetres, 0 = unknown."""
    mm = np.nan_to_num(np.asarray(z, dtype=np.float64) * 1000.0, nan=0.0, posinf=0.0)
    return np.clip(np.round(mm), 0, 65535).astype(np.uint16)


def depth_fields(z: np.ndarray, encoding: str = "16UC1") -> dict[str, Any]:
    """Field values of a registered depth sensor_msgs/Image of `z` (metres, NaN = none):
    ``16UC1`` millimetres (0 = unknown) or ``32FC1`` metres (NaN)."""
    data = depth_millimetres(z) if encoding == "16UC1" else np.ascontiguousarray(z, np.float32)
    height, width = data.shape
    return {"height": height, "width": width, "encoding": encoding, "is_bigendian": 0,
            "step": width * data.itemsize, "data": data.reshape(-1).view(np.uint8)}


def bayer_fields(rgb: np.ndarray, pattern: str = "grbg") -> dict[str, Any]:
    """Field values of the raw ``bayer_<pattern>8`` sensor_msgs/Image a Kinect takes of `rgb`."""
    raw = bayer_mosaic(rgb, pattern)
    height, width = raw.shape
    return {"height": height, "width": width, "encoding": f"bayer_{pattern}8",
            "is_bigendian": 0, "step": width, "data": raw.reshape(-1)}


def intrinsics_from_camera_info(msg: Any) -> Intrinsics:
    """The pinhole intrinsics of a sensor_msgs/CameraInfo (its K; the raw image's camera).

    Raises ValueError when K is not a camera matrix (fx or fy not positive, not finite).
    """
    k = [float(v) for v in msg.K] if hasattr(msg, "K") else [float(v) for v in msg.k]
    width, height = int(msg.width), int(msg.height)
    if len(k) != 9 or not all(math.isfinite(v) for v in k) or k[0] <= 0 or k[4] <= 0:
        raise ValueError(f"camera_info: K = {k} is not a camera matrix")
    if width <= 0 or height <= 0:
        raise ValueError(f"camera_info: empty image size {width}x{height}")
    return Intrinsics(width, height, k[0], k[4], k[2], k[5])


def camera_info_fields(intr: Intrinsics) -> dict[str, Any]:
    """Field values of the sensor_msgs/CameraInfo of an undistorted pinhole camera."""
    k = [intr.fx, 0.0, intr.cx, 0.0, intr.fy, intr.cy, 0.0, 0.0, 1.0]
    return {"width": intr.width, "height": intr.height, "distortion_model": "plumb_bob",
            "D": [0.0] * 5, "K": k, "R": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0],
            "P": [intr.fx, 0.0, intr.cx, 0.0, 0.0, intr.fy, intr.cy, 0.0, 0.0, 0.0, 1.0, 0.0]}


def z_to_xyz(z: np.ndarray, intr: Intrinsics) -> np.ndarray:
    """A registered depth image (HxW metres, NaN = none) as an organized HxWx3 optical-frame
    cloud, as depth_image_proc's ``point_cloud_xyzrgb`` makes it. Raises ValueError when the
    intrinsics are for another image size."""
    height, width = z.shape
    if (width, height) != (intr.width, intr.height):
        raise ValueError(f"camera_info is for {intr.width}x{intr.height}, the depth image is "
                         f"{width}x{height}")
    u = (np.arange(width, dtype=np.float32) - np.float32(intr.cx)) / np.float32(intr.fx)
    v = (np.arange(height, dtype=np.float32) - np.float32(intr.cy)) / np.float32(intr.fy)
    xyz = np.empty((height, width, 3), dtype=np.float32)
    xyz[..., 0] = z * u[None, :]
    xyz[..., 1] = z * v[:, None]
    xyz[..., 2] = z
    return xyz


def _line(t: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares slope and intercept of ``y`` against ``t``."""
    t_mean, y_mean = float(t.mean()), float(y.mean())
    dt = t - t_mean
    slope = float((dt * (y - y_mean)).sum() / max(float((dt * dt).sum()), 1e-12))
    return slope, y_mean - slope * t_mean


def intrinsics_from_cloud(xyz: np.ndarray) -> Intrinsics:
    """The pinhole intrinsics an organized registered cloud was made with (x/z and y/z are
    linear in the pixel's column and row), fitted by least squares on a grid of its valid
    points. Raises ValueError when fewer than two columns or rows have a valid point."""
    height, width = xyz.shape[:2]
    grid = xyz[::4, ::4]
    with np.errstate(invalid="ignore", divide="ignore"):
        slope_x = grid[..., 0] / grid[..., 2]
        slope_y = grid[..., 1] / grid[..., 2]
    valid = np.isfinite(slope_x) & np.isfinite(slope_y)
    if valid.any(axis=1).sum() < 2 or valid.any(axis=0).sum() < 2:
        raise ValueError("too few valid cloud points to find the camera's intrinsics")
    rows, cols = np.nonzero(valid)
    # x/z = (u - cx) / fx: a line in u of slope 1/fx and intercept -cx/fx (y/z likewise in v)
    ax, bx = _line(cols * 4.0, slope_x[valid])
    ay, by = _line(rows * 4.0, slope_y[valid])
    if ax <= 0 or ay <= 0:
        raise ValueError("the cloud's x/z does not grow to the right: not an organized "
                         "optical-frame cloud")
    return Intrinsics(width, height, float(1.0 / ax), float(1.0 / ay), float(-bx / ax),
                      float(-by / ay))


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
    height, width = checked_dimensions("cloud", max(int(msg.height), 1), msg.width, max_pixels)
    point_step = int(msg.point_step)
    ox, oy, oz = offsets["x"], offsets["y"], offsets["z"]
    if min(ox, oy, oz) < 0 or max(ox, oy, oz) + 4 > point_step:
        raise ValueError(f"cloud: x, y, z fields at {ox}, {oy}, {oz} do not fit a "
                         f"{point_step}-byte point")
    flat = buffer_of(msg.data)
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
