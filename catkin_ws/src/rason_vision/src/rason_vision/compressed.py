"""image_transport's ``compressed`` and ``compressedDepth`` sensor_msgs/CompressedImage <-> numpy.

``compressed`` (compressed_image_transport): ``data`` is a JPEG or PNG file; ``format`` is
``"<encoding>; jpeg compressed bgr8"`` (or ``png``), or just ``"jpeg"`` from older publishers.

``compressedDepth`` (compressed_depth_image_transport): ``format`` is ``"<encoding>;
compressedDepth png"`` (older publishers: ``"<encoding>; compressedDepth"``); ``data`` starts
with a 12-byte ConfigHeader (int32 format, float32 depthQuantA, float32 depthQuantB, native
little-endian), then a 16-bit single-channel PNG. For a ``16UC1`` image the PNG holds the
millimetres themselves (0 = unknown); for ``32FC1`` it holds the quantized inverse depth ``q``
and the depth is ``depthQuantA / (q - depthQuantB)`` metres (0 = unknown). Its ``rvl`` codec is
not read.

Dimensions are read from the file's header and checked against the size limit before the
pixels are decoded, so a small message cannot make the node allocate a huge image.
"""

from __future__ import annotations

import struct
from typing import Any

import cv2
import numpy as np

from rason_vision.convert import MAX_PIXELS, buffer_of, checked_dimensions, depth_millimetres

#: The ConfigHeader in front of a compressedDepth PNG: format enum, depthQuantA, depthQuantB.
DEPTH_HEADER = struct.Struct("<iff")
#: PNG's signature; its IHDR chunk gives width and height at bytes 16-23.
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
#: JPEG start-of-frame markers (they carry the image size); C4, C8 and CC are other segments.
_JPEG_SOF = set(range(0xC0, 0xD0)) - {0xC4, 0xC8, 0xCC}


def encoded_size(data: bytes) -> tuple[int, int]:
    """(width, height) from a PNG's or JPEG's header. Raises ValueError for another format or
    a header cut short."""
    if data.startswith(PNG_SIGNATURE):
        if len(data) < 24:
            raise ValueError("PNG header cut short")
        width, height = struct.unpack(">II", data[16:24])
        return width, height
    if not data.startswith(b"\xff\xd8"):
        raise ValueError("neither a PNG nor a JPEG")
    pos = 2
    while pos + 9 <= len(data):
        if data[pos] != 0xFF:
            raise ValueError("JPEG segment markers out of step")
        marker = data[pos + 1]
        if marker in _JPEG_SOF:
            height, width = struct.unpack(">HH", data[pos + 5:pos + 9])
            return width, height
        if marker == 0xFF:             # fill byte
            pos += 1
            continue
        pos += 2 + struct.unpack(">H", data[pos + 2:pos + 4])[0]
    raise ValueError("JPEG without a frame header")


def _decode(data: bytes, flags: int, max_pixels: int, kind: str) -> np.ndarray:
    width, height = encoded_size(data)
    checked_dimensions(kind, height, width, max_pixels)
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), flags)
    if image is None:
        raise ValueError(f"{kind}: the data does not decode")
    return image


def compressed_to_rgb(msg: Any, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """A ``compressed`` colour image (JPEG or PNG) as HxWx3 RGB uint8."""
    data = buffer_of(msg.data).tobytes()
    bgr = _decode(data, cv2.IMREAD_COLOR, max_pixels, "compressed image")
    return cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB)


def compressed_depth_to_z(msg: Any, max_pixels: int = MAX_PIXELS) -> np.ndarray:
    """A ``compressedDepth`` image (PNG codec) as HxW float32 metres, NaN = no depth."""
    encoding, _, codec = str(msg.format).partition(";")
    encoding, codec = encoding.strip().lower(), codec.strip()
    if codec not in ("", "compressedDepth", "compressedDepth png"):
        raise ValueError(f"compressedDepth codec {codec!r} is not read (png only)")
    if encoding not in ("16uc1", "32fc1"):
        raise ValueError(f"compressedDepth of {encoding!r}: 16UC1 or 32FC1 expected")
    data = buffer_of(msg.data).tobytes()
    if len(data) <= DEPTH_HEADER.size:
        raise ValueError(f"compressedDepth of {len(data)} bytes: no image after the header")
    _, quant_a, quant_b = DEPTH_HEADER.unpack_from(data)
    raw = _decode(data[DEPTH_HEADER.size:], cv2.IMREAD_UNCHANGED, max_pixels,
                  "compressed depth")
    if raw.dtype != np.uint16 or raw.ndim != 2:
        raise ValueError("compressedDepth: the PNG is not 16-bit single-channel")
    with np.errstate(divide="ignore", invalid="ignore"):
        if encoding == "16uc1":
            z = raw.astype(np.float32) * np.float32(0.001)
        else:
            z = (np.float32(quant_a) / (raw.astype(np.float32) - np.float32(quant_b)))
        z[(raw == 0) | ~(z > 0.0) | ~np.isfinite(z)] = np.nan
    return z.astype(np.float32)


def compressed_image_fields(rgb: np.ndarray, codec: str = "jpeg",
                            quality: int = 80) -> dict[str, Any]:
    """Field values (``format``, ``data`` bytes) of the ``compressed`` form of an rgb8 image,
    as compressed_image_transport writes it (default JPEG quality 80)."""
    bgr = cv2.cvtColor(np.ascontiguousarray(rgb, dtype=np.uint8), cv2.COLOR_RGB2BGR)
    params = [cv2.IMWRITE_JPEG_QUALITY, quality] if codec == "jpeg" else []
    ok, data = cv2.imencode(f".{codec}", bgr, params)
    if not ok:
        raise ValueError(f"cannot encode {codec}")
    return {"format": f"rgb8; {codec} compressed bgr8", "data": data.tobytes()}


def compressed_depth_fields(z: np.ndarray) -> dict[str, Any]:
    """Field values (``format``, ``data`` bytes) of the ``compressedDepth`` form of a 16UC1
    depth image made from `z` (metres, NaN = none), as compressed_depth_image_transport writes
    it (quantization parameters unused for 16UC1: zero)."""
    ok, png = cv2.imencode(".png", depth_millimetres(z), [cv2.IMWRITE_PNG_COMPRESSION, 1])
    if not ok:
        raise ValueError("cannot encode the depth PNG")
    return {"format": "16UC1; compressedDepth png",
            "data": DEPTH_HEADER.pack(0, 0.0, 0.0) + png.tobytes()}
