"""Speed of the robot-observer detector and of the ``robot_synthesizer`` node.

    ./run.sh bench vision_speed [--frames 20] [--seconds 5] [--messages 100]

1. Detector throughput on 640x480 frames on one core (process pinned to one CPU, OpenCV
   single-threaded): frames rendered by the simulator (seeded scenarios), the detector run
   over them in a loop; also with the message -> numpy conversion included. Target >= 60 fps.
2. Node latency: a private roscore (``rason.process.harness.RosHarness``), ``rosrun rason_vision
   robot_synthesizer __ns:=/bench _timing:=true``; this process publishes image + cloud pairs
   (rospy, header stamp = publish time), one pair at a time at ~10 Hz. Reported:
   * node message-in -> perception-out: the synchronized pair's callback to the perception
     published (conversion, detection, publishing), from the node's timing log. Target p50
     < 15 ms.
   * transport in: header stamp -> the node's callback (rospy serialisation, TCP, the node's
     deserialisation and synchronizer): the cost of moving 5.8 MB per frame through rospy.
   * end to end: just before publishing the pair -> this process has the perception.
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse
import re
import sys
import threading
import time
from types import SimpleNamespace
from typing import Any

import cv2
import numpy as np

from rason_vision.convert import cloud_fields, cloud_to_xyz, image_fields, image_to_rgb
from rason_vision.detector import detect
from rason_vision_tools.scenarios import random_scenarios, render


def sim_frames(count: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``count`` simulator frames (a mix of all scenario kinds)."""
    return [render(s)[:2] for s in random_scenarios(seed, count)]


def as_messages(rgb: np.ndarray, xyz: np.ndarray) -> tuple[Any, Any]:
    """Message-like objects with bytes payloads, as rospy delivers them."""
    image = SimpleNamespace(**image_fields(rgb))
    image.data = image.data.tobytes()
    values = cloud_fields(xyz, rgb)
    values["fields"] = [SimpleNamespace(name=n, offset=o, datatype=d, count=c)
                        for n, o, d, c in values["fields"]]
    cloud = SimpleNamespace(**values)
    cloud.data = cloud.data.tobytes()
    return image, cloud


def detector_fps(frames: list[tuple[np.ndarray, np.ndarray]], seconds: float,
                 with_conversion: bool) -> tuple[float, np.ndarray]:
    """Frames per second and per-frame times (ms) of the detector on one core."""
    messages = [as_messages(*f) for f in frames] if with_conversion else None
    times = []
    start = time.perf_counter()
    i = 0
    while time.perf_counter() - start < seconds:
        t0 = time.perf_counter()
        if messages is not None:
            image, cloud = messages[i % len(messages)]
            detect(image_to_rgb(image), cloud_to_xyz(cloud))
        else:
            detect(*frames[i % len(frames)])
        times.append(time.perf_counter() - t0)
        i += 1
    elapsed = time.perf_counter() - start
    return i / elapsed, np.array(times) * 1000.0


TIMING = re.compile(r"stamp to callback ([\d.]+) ms, processing ([\d.]+) ms")


def node_latency(frames: list[tuple[np.ndarray, np.ndarray]],
                 count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """End-to-end, transport-in and in-node latencies (ms) of the robot_synthesizer node."""
    import rospy
    from jason_msgs.msg import Perception
    from sensor_msgs.msg import Image, PointCloud2

    from rason.process.harness import RosHarness
    from rason_vision_tools.messages import frame_messages

    pairs = [frame_messages(*f) for f in frames]
    latencies: list[float] = []
    with RosHarness() as ros:
        node = ros.rosrun("rason_vision", "robot_synthesizer", ns="/bench",
                          params={"timing": True})
        ros.wait_for_subscriber("/bench/camera/depth_registered/points", watch=[node])
        ros.wait_for_topic("/bench/jason/perception", watch=[node])
        ros.init_rospy("vision_speed")
        got = threading.Event()
        sub = rospy.Subscriber("/bench/jason/perception", Perception, lambda _m: got.set(),
                               tcp_nodelay=True)
        image_pub = rospy.Publisher("/bench/camera/rgb/image_raw", Image, queue_size=2,
                                    tcp_nodelay=True)
        cloud_pub = rospy.Publisher("/bench/camera/depth_registered/points", PointCloud2,
                                    queue_size=2, tcp_nodelay=True)
        deadline = time.monotonic() + 10
        while (image_pub.get_num_connections() < 1 or cloud_pub.get_num_connections() < 1
               or sub.get_num_connections() < 1) and time.monotonic() < deadline:
            time.sleep(0.05)
        time.sleep(0.5)
        warmup = 5
        for i in range(count + warmup):
            image, cloud = pairs[i % len(pairs)]
            stamp = rospy.Time.now()
            image.header.stamp = cloud.header.stamp = stamp
            got.clear()
            t0 = time.perf_counter()
            image_pub.publish(image)
            cloud_pub.publish(cloud)
            if got.wait(2.0) and i >= warmup:
                latencies.append((time.perf_counter() - t0) * 1000.0)
            time.sleep(0.1)
        sub.unregister()
        image_pub.unregister()
        cloud_pub.unregister()
        timings = [TIMING.search(line) for line in node.lines()]
    found = [(float(m.group(1)), float(m.group(2))) for m in timings if m][5:]
    transport = np.array([t for t, _ in found])
    inside = np.array([p for _, p in found])
    return np.array(latencies), transport, inside


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--frames", type=int, default=20, help="distinct frames to cycle")
    parser.add_argument("--seed", type=int, default=5)
    parser.add_argument("--seconds", type=float, default=5.0)
    parser.add_argument("--messages", type=int, default=100)
    parser.add_argument("--skip-node", action="store_true")
    args = parser.parse_args(argv)
    frames = sim_frames(args.frames, args.seed)
    cpu = sorted(os.sched_getaffinity(0))[-1]
    os.sched_setaffinity(0, {cpu})
    cv2.setNumThreads(1)
    ok = True
    print(f"vision speed: {len(frames)} simulator frames 640x480, pinned to CPU {cpu}, "
          f"cv2 threads {cv2.getNumThreads()}")
    detector_fps(frames, 0.5, False)  # warm-up
    for label, conv in (("detector", False), ("detector + message conversion", True)):
        fps, ms = detector_fps(frames, args.seconds, conv)
        print(f"  {label:30s} {fps:7.1f} fps  per frame p50 {np.percentile(ms, 50):.2f} ms "
              f"p95 {np.percentile(ms, 95):.2f} ms max {ms.max():.2f} ms  (target >= 60 fps)")
        ok &= fps >= 60
    os.sched_setaffinity(0, set(range(os.cpu_count() or 1)))
    if not args.skip_node:
        lat, transport, inside = node_latency(frames, args.messages)
        if len(lat) < args.messages or len(inside) == 0:
            print(f"  node: only {len(lat)}/{args.messages} perceptions came back")
            ok = False
        for label, values in (("node message-in -> perception-out", inside),
                              ("transport in (stamp -> callback)", transport),
                              ("end to end (publish -> perception)", lat)):
            if len(values):
                print(f"  {label:36s} p50 {np.percentile(values, 50):5.1f} ms  "
                      f"p95 {np.percentile(values, 95):5.1f} ms  max {values.max():5.1f} ms  "
                      f"({len(values)} pairs)")
        if len(inside):
            ok &= float(np.percentile(inside, 50)) < 15.0
            print("  (target: node message-in -> perception-out p50 < 15 ms)")
    print("PASS" if ok else "FAIL")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
