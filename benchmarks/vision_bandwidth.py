"""Bandwidth of each input choice of the robot synthesizer, and the cost of reading it.

    ./run.sh bench vision_bandwidth [--frames 12] [--seed 3] [--rate 30]

Frames rendered by the simulator (seeded scenarios: Kinect-like colour and depth noise) are
turned into every message form the synthesizer reads (``rason_vision_tools.messages``) and
serialized as rospy sends them over TCPROS. Reported per stream: the mean message size and the
bytes per second at ``--rate`` Hz (a Kinect's 30 by default); per input choice (colour +
depth + camera_info) the total; and the time this machine takes to turn one frame's messages
into the detector's arrays (median, one core). Clouds in two layouts: the simulator's 16-byte
points and depth_image_proc ``point_cloud_xyzrgb``'s 32-byte ones (a real robot's).
The simulated colour is smoother than a real Kinect's, so a real JPEG is likely larger.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse
import io
import statistics
import time
from collections.abc import Callable
from typing import Any

import cv2
import numpy as np

from rason_vision.compressed import compressed_depth_to_z, compressed_to_rgb
from rason_vision.convert import (
    cloud_to_xyz,
    depth_image_to_z,
    image_to_rgb,
    intrinsics_from_camera_info,
    intrinsics_from_cloud,
    z_to_xyz,
)
from rason_vision_tools.messages import (
    compressed_messages,
    driver_cloud_message,
    frame_messages,
    kinect_messages,
)
from rason_vision_tools.scenarios import random_scenarios, render


def serialized_size(msg: Any) -> int:
    """Bytes of a message on the wire (TCPROS: a 4-byte length, then the serialization)."""
    buffer = io.BytesIO()
    msg.serialize(buffer)
    return 4 + buffer.tell()


def median_ms(work: Callable[[], object], repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        work()
        times.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(times)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--seed", type=int, default=3)
    parser.add_argument("--rate", type=float, default=30.0)
    args = parser.parse_args()
    cv2.setNumThreads(1)
    frames = [render(s)[:2] for s in random_scenarios(args.seed, args.frames)]
    streams: dict[str, list[int]] = {}
    forms = []
    for rgb, xyz in frames:
        intr = intrinsics_from_cloud(xyz)
        image, cloud = frame_messages(rgb, xyz)
        bayer, depth, info = kinect_messages(rgb, xyz, intr)
        jpeg, png, _ = compressed_messages(rgb, xyz, intr)
        metric = kinect_messages(rgb, xyz, intr, depth_encoding="32FC1")[1]
        driver_cloud = driver_cloud_message(rgb, xyz)
        for name, msg in (("rgb8 image_raw", image), ("bayer_grbg8 image_raw", bayer),
                          ("compressed (JPEG q80)", jpeg), ("cloud, 16-byte points (sim)", cloud),
                          ("cloud, 32-byte points (depth_image_proc)", driver_cloud),
                          ("16UC1 depth image_raw", depth), ("32FC1 depth image", metric),
                          ("compressedDepth (PNG)", png), ("camera_info", info)):
            streams.setdefault(name, []).append(serialized_size(msg))
        forms.append((image, cloud, bayer, depth, info, jpeg, png, driver_cloud))
    height, width = frames[0][0].shape[:2]

    rate = args.rate
    print(f"{len(frames)} simulated {width}x{height} frames; bytes per message and per second "
          f"at {rate:g} Hz\n")
    print("| stream | bytes/message | MB/s |\n|---|---:|---:|")
    means = {name: float(np.mean(sizes)) for name, sizes in streams.items()}
    for name, mean in means.items():
        print(f"| {name} | {mean:,.0f} | {mean * rate / 1e6:.2f} |")

    image, cloud, bayer, depth, info, jpeg, png, driver_cloud = forms[0]
    choices = [
        ("rgb8 + cloud (sim; _depth_input:=cloud)", ["rgb8 image_raw",
                                                    "cloud, 16-byte points (sim)"],
         lambda: (image_to_rgb(image), intrinsics_from_cloud(cloud_to_xyz(cloud)))),
        ("bayer + depth_image_proc cloud (_depth_input:=cloud)",
         ["bayer_grbg8 image_raw", "cloud, 32-byte points (depth_image_proc)"],
         lambda: (image_to_rgb(bayer), intrinsics_from_cloud(cloud_to_xyz(driver_cloud)))),
        ("bayer + 16UC1 + camera_info (_depth_input:=image)",
         ["bayer_grbg8 image_raw", "16UC1 depth image_raw", "camera_info"],
         lambda: (image_to_rgb(bayer), z_to_xyz(depth_image_to_z(depth),
                                                 intrinsics_from_camera_info(info)))),
        ("JPEG + compressedDepth + camera_info (_colour_transport:=compressed "
         "_depth_input:=compressed)",
         ["compressed (JPEG q80)", "compressedDepth (PNG)", "camera_info"],
         lambda: (compressed_to_rgb(jpeg), z_to_xyz(compressed_depth_to_z(png),
                                                     intrinsics_from_camera_info(info)))),
    ]
    print("\n| input choice | MB/s | Mbit/s | decode ms/frame |\n|---|---:|---:|---:|")
    for label, names, work in choices:
        total = sum(means[n] for n in names) * rate
        cost = f"{median_ms(work, 15):.1f}"
        print(f"| {label} | {total / 1e6:.2f} | {total * 8 / 1e6:.0f} | {cost} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
