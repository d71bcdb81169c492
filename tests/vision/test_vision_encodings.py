"""Every colour encoding and depth form a Kinect driver publishes, decoded without ROS: Bayer
patterns, 16-bit and grey images, 16UC1 / 32FC1 depth images, image_transport's compressed
and compressedDepth forms, and the intrinsics from camera_info or from the cloud itself."""

from __future__ import annotations

import struct
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from rason_vision.compressed import (
    DEPTH_HEADER,
    compressed_depth_fields,
    compressed_depth_to_z,
    compressed_image_fields,
    compressed_to_rgb,
    encoded_size,
)
from rason_vision.convert import (
    BAYER_CODES,
    bayer_fields,
    camera_info_fields,
    depth_fields,
    depth_image_to_z,
    image_to_rgb,
    intrinsics_from_camera_info,
    intrinsics_from_cloud,
    z_to_xyz,
)
from rason_vision.detector import DetectorConfig, detect
from rason_vision.geometry import KINECT_VGA
from rason_vision_tools.synthetic import faulty_scene


@pytest.fixture(scope="module")
def frame():
    scene = faulty_scene(1.8, -8.0, -60.0, intrinsics=KINECT_VGA)
    return scene.render(np.random.default_rng(5))


def msg(**fields):
    return SimpleNamespace(**fields)


@pytest.mark.parametrize("pattern", sorted(BAYER_CODES))
def test_every_bayer_pattern_debayers_to_the_right_colours(pattern):
    rgb = np.zeros((48, 64, 3), np.uint8)
    rgb[:, :32] = (240, 120, 20)
    rgb[:, 32:] = (40, 170, 60)
    out = image_to_rgb(msg(**bayer_fields(rgb, pattern)))
    assert out.shape == rgb.shape
    # away from the colour edge a bilinear demosaic gives the flat colours back exactly
    assert np.array_equal(out[4:-4, 4:28], rgb[4:-4, 4:28])
    assert np.array_equal(out[4:-4, 36:-4], rgb[4:-4, 36:-4])


def test_a_kinect_bayer_frame_gives_the_rgb8_detection(frame):
    rgb, xyz = frame
    config = DetectorConfig(intrinsics=KINECT_VGA)
    direct = detect(rgb, xyz, config).detection
    via = detect(image_to_rgb(msg(**bayer_fields(rgb, "grbg"))), xyz, config).detection
    assert direct is not None and via is not None
    assert abs(via.angle - direct.angle) < 0.2 and abs(via.depth - direct.depth) < 0.01
    assert abs(via.yaw - direct.yaw) < 3.0


def test_sixteen_bit_grey_and_big_endian_images():
    rgb = np.random.default_rng(0).integers(0, 256, (6, 8, 3), dtype=np.uint8)
    wide = rgb.astype(np.uint16) * 257
    for order, encoding in (("<", "rgb16"), (">", "rgb16")):
        data = wide.astype(f"{order}u2").tobytes()
        out = image_to_rgb(msg(height=6, width=8, encoding=encoding, step=48,
                               is_bigendian=order == ">", data=data))
        assert np.array_equal(out, rgb)
    bgra = np.concatenate([rgb[..., ::-1], np.full((6, 8, 1), 255, np.uint8)], axis=-1)
    assert np.array_equal(image_to_rgb(msg(height=6, width=8, encoding="bgra8", step=32,
                                           is_bigendian=0, data=bgra.tobytes())), rgb)
    grey = image_to_rgb(msg(height=6, width=8, encoding="mono8", step=8, is_bigendian=0,
                            data=rgb[..., 0].tobytes()))
    assert np.array_equal(grey, np.repeat(rgb[..., :1], 3, axis=-1))
    uyvy = cv2.cvtColor(rgb, cv2.COLOR_RGB2YUV)  # any bytes: yuv422 is read, 2 per pixel
    out = image_to_rgb(msg(height=6, width=8, encoding="yuv422", step=16, is_bigendian=0,
                           data=uyvy[..., :2].tobytes()))
    assert out.shape == (6, 8, 3)
    with pytest.raises(ValueError, match=r"unsupported image encoding .32FC1.*bayer_grbg8"):
        image_to_rgb(msg(height=6, width=8, encoding="32FC1", step=32, data=bytes(192)))
    with pytest.raises(ValueError, match="bytes of data"):
        image_to_rgb(msg(**{**bayer_fields(rgb), "data": bytes(10)}))


def test_depth_images_in_millimetres_and_metres():
    z = np.array([[1.5, np.nan], [0.0, 4.25]], np.float32)
    mm = depth_image_to_z(msg(**depth_fields(z, "16UC1")))
    metres = depth_image_to_z(msg(**depth_fields(z, "32FC1")))
    for out in (mm, metres):
        assert out[0, 0] == pytest.approx(1.5) and out[1, 1] == pytest.approx(4.25)
        assert np.isnan(out[0, 1]) and np.isnan(out[1, 0])     # 0 and NaN: no depth
    with pytest.raises(ValueError, match="unsupported depth encoding"):
        depth_image_to_z(msg(height=2, width=2, encoding="rgb8", step=6, data=bytes(12)))


def test_compressed_colour_and_depth_round_trip(frame):
    rgb, xyz = frame
    packed = compressed_image_fields(rgb)
    assert packed["format"] == "rgb8; jpeg compressed bgr8"
    assert encoded_size(packed["data"]) == (640, 480)
    out = compressed_to_rgb(msg(**packed))
    assert out.shape == rgb.shape and np.abs(out.astype(int) - rgb).mean() < 4
    png = compressed_image_fields(rgb, "png")
    assert np.array_equal(compressed_to_rgb(msg(**png)), rgb)   # PNG is lossless
    depth = compressed_depth_fields(xyz[..., 2])
    assert depth["format"] == "16UC1; compressedDepth png"
    z = compressed_depth_to_z(msg(**depth))
    assert np.array_equal(np.isnan(z), np.isnan(xyz[..., 2]))
    assert np.nanmax(np.abs(z - xyz[..., 2])) <= 0.0006             # millimetre rounding


def test_compressed_depth_of_32fc1_is_inverse_depth():
    """compressed_depth_image_transport's 32FC1 coding: q = A / z + B, z = A / (q - B)."""
    depth_max, z0 = 10.0, 100.0        # the publisher's defaults (depth_max, depth_quantization)
    quant_a = z0 * (z0 + 1.0)
    quant_b = 1.0 - quant_a / depth_max
    z = np.array([[0.8, 2.0], [3.7, np.nan]], np.float32)
    q = np.where(np.isnan(z), 0, quant_a / np.nan_to_num(z, nan=1.0) + quant_b).astype(np.uint16)
    ok, png = cv2.imencode(".png", q)
    assert ok
    data = struct.pack("<iff", 0, quant_a, quant_b) + png.tobytes()
    out = compressed_depth_to_z(msg(format="32FC1; compressedDepth png", data=data))
    assert np.isnan(out[1, 1])
    assert np.allclose(out[~np.isnan(z)], z[~np.isnan(z)], rtol=0.01)


def test_bad_compressed_frames_are_refused_before_decoding():
    huge_png = (b"\x89PNG\r\n\x1a\n" + struct.pack(">I", 13) + b"IHDR"
                + struct.pack(">II", 50000, 50000) + bytes(20))
    with pytest.raises(ValueError, match="larger than"):
        compressed_to_rgb(msg(format="jpeg", data=huge_png))
    with pytest.raises(ValueError, match="neither a PNG nor a JPEG"):
        compressed_to_rgb(msg(format="jpeg", data=b"GIF89a" + bytes(30)))
    with pytest.raises(ValueError, match="no image after the header"):
        compressed_depth_to_z(msg(format="16UC1; compressedDepth png",
                                  data=DEPTH_HEADER.pack(0, 0.0, 0.0)))
    with pytest.raises(ValueError, match="rvl"):
        compressed_depth_to_z(msg(format="16UC1; compressedDepth rvl", data=bytes(40)))


def test_intrinsics_from_camera_info_and_from_the_cloud(frame):
    _, xyz = frame
    info = msg(**camera_info_fields(KINECT_VGA))
    assert intrinsics_from_camera_info(info) == KINECT_VGA
    fitted = intrinsics_from_cloud(xyz)
    assert fitted.fx == pytest.approx(525.0, rel=1e-4) and fitted.cy == pytest.approx(239.5,
                                                                                      abs=0.05)
    rebuilt = z_to_xyz(xyz[..., 2], KINECT_VGA)
    assert np.allclose(rebuilt, xyz, equal_nan=True, atol=1e-5)
    with pytest.raises(ValueError, match="not a camera matrix"):
        intrinsics_from_camera_info(msg(width=640, height=480, K=[0.0] * 9))
    with pytest.raises(ValueError, match="camera_info is for 640x480"):
        z_to_xyz(np.ones((240, 320), np.float32), KINECT_VGA)


def test_a_depth_image_proc_cloud_reads_like_the_simulators(frame):
    """depth_image_proc's point_cloud_xyzrgb layout (32-byte points, rgb at 16, NaN holes)."""
    from rason_vision.convert import cloud_to_xyz
    from rason_vision_tools.messages import DRIVER_POINT_STEP, driver_cloud_message

    rgb, xyz = frame
    cloud = driver_cloud_message(rgb, xyz)
    assert cloud.point_step == DRIVER_POINT_STEP == 32
    read = cloud_to_xyz(cloud)
    assert np.array_equal(read, xyz, equal_nan=True)
    assert intrinsics_from_cloud(read).fx == pytest.approx(525.0, rel=1e-4)
