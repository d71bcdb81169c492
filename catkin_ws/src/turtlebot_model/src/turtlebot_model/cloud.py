"""PCL's organised XYZRGB layout (``PointXYZRGB``): x, y, z and a packed rgb, 16 bytes a point."""

from __future__ import annotations

import numpy as np

#: Byte offsets of the fields in one point, and the point step.
FIELD_OFFSETS = {"x": 0, "y": 4, "z": 8, "rgb": 12}
POINT_STEP = 16


def pack_rgb(rgb: np.ndarray) -> np.ndarray:
    """...x3 uint8 colours as PCL's float32 rgb field (the uint32 ``0x00RRGGBB`` reinterpreted)."""
    packed = ((rgb[..., 0].astype(np.uint32) << 16) | (rgb[..., 1].astype(np.uint32) << 8)
              | rgb[..., 2].astype(np.uint32))
    return packed.view(np.float32)


def unpack_rgb(packed: np.ndarray) -> np.ndarray:
    """Inverse of :func:`pack_rgb`: a float32 rgb field -> ...x3 uint8."""
    as_int = np.ascontiguousarray(packed, dtype=np.float32).view(np.uint32)
    return np.stack([(as_int >> 16) & 255, (as_int >> 8) & 255, as_int & 255],
                    axis=-1).astype(np.uint8)


def pack_cloud(xyz: np.ndarray, rgb: np.ndarray) -> np.ndarray:
    """Organised points as PCL packs them: HxWx4 float32 (x, y, z, rgb)."""
    out = np.empty((*xyz.shape[:2], 4), dtype=np.float32)
    out[..., :3] = xyz
    out[..., 3] = pack_rgb(rgb)
    return out
