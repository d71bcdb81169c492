#!/usr/bin/env python3
"""Kinect frames per wall second under ``rosrun turtlebot_sim sim _drivers:=stock``.

The stock profile runs on wall time, so a frame the renderer cannot finish in time is dropped
(no physics waiting, unlike the default profile). Both robots move (every frame a fresh render);
a subscriber takes ``camera/rgb/image_raw`` and ``camera/depth_registered/image_raw``. For each
asked rate and width: images received per wall second, the sim's own count of dropped frames,
ms per rendered frame, and the real-time factor of the physics loop (docs/drivers.md).

    ./run.sh bench stock_camera [--seconds 12] [--rates 30,15] [--widths 640,320]
"""

from __future__ import annotations

import argparse
import math
import os
import re
import threading
import time

from rason.process.harness import RosHarness
from rason_diagnosis.paths import world_file

COMMANDS = {"faulty": (0.3, 0.3), "helper": (0.0, 0.4)}      # m/s, rad/s: keep both moving


def run(ros: RosHarness, rate: float, width: int, seconds: float) -> dict[str, float]:
    import rospy
    from geometry_msgs.msg import Twist
    from sensor_msgs.msg import Image

    ns = f"/stock{rate:.0f}w{width}"
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns,
                     params={"world": str(world_file()), "drivers": "stock", "camera_rate": rate,
                             "camera_width": width, "stats_period": seconds / 2})
    ros.wait_for_topic(f"{ns}/helper/camera/depth_registered/image_raw", timeout=60,
                       watch=[sim])
    ros.init_rospy("stock_camera")
    counts = {"rgb": 0, "depth": 0}

    def counter(key: str):
        return lambda _msg: counts.__setitem__(key, counts[key] + 1)

    subs = [rospy.Subscriber(f"{ns}/helper/camera/rgb/image_raw", Image, counter("rgb"),
                             queue_size=2, buff_size=2 ** 24),
            rospy.Subscriber(f"{ns}/helper/camera/depth_registered/image_raw", Image,
                             counter("depth"), queue_size=2, buff_size=2 ** 24)]
    pubs = {name: rospy.Publisher(f"{ns}/{name}/mobile_base/commands/velocity", Twist,
                                  queue_size=1) for name in COMMANDS}
    stop = threading.Event()

    def command() -> None:
        while not stop.is_set():
            for name, (v, w) in COMMANDS.items():
                msg = Twist()
                msg.linear.x, msg.angular.z = v, w
                pubs[name].publish(msg)
            time.sleep(0.05)

    driver = threading.Thread(target=command, daemon=True)
    driver.start()
    time.sleep(3.0)
    start, wall0, mark = dict(counts), time.monotonic(), len(sim.lines())
    time.sleep(seconds)
    wall = time.monotonic() - wall0
    got = {k: (counts[k] - start[k]) / wall for k in counts}
    stop.set()
    driver.join()
    for sub in subs:
        sub.unregister()
    for pub in pubs.values():
        pub.unregister()
    sim.stop()
    stats = [line for line in sim.lines()[mark:] if "turtlebot_sim stats" in line]

    def figure(pattern: str) -> float:
        found = [float(m.group(1)) for m in (re.search(pattern, s) for s in stats) if m]
        return sum(found) / len(found) if found else math.nan

    dropped = sum(int(m.group(1)) for m in (re.search(r"dropped (\d+)", s) for s in stats) if m)
    return {"rgb": got["rgb"], "depth": got["depth"], "ms": figure(r"render ([\d.]+) ms"),
            "rtf": figure(r"rtf ([\d.]+)"), "dropped": dropped}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=12.0)
    parser.add_argument("--rates", default="30,15")
    parser.add_argument("--widths", default="640,320")
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    print("| Kinect Hz asked | width | RGB images/s | depth images/s | dropped | ms per frame "
          "| physics rtf | load |")
    print("|---|---|---|---|---|---|---|---|")
    with RosHarness() as ros:
        for rate in (float(r) for r in args.rates.split(",")):
            for width in (int(w) for w in args.widths.split(",")):
                r = run(ros, rate, width, args.seconds)
                print(f"| {rate:.0f} | {width} | {r['rgb']:.1f} | {r['depth']:.1f} | "
                      f"{r['dropped']} | {r['ms']:.1f} | {r['rtf']:.2f} | "
                      f"{os.getloadavg()[0]:.1f} |", flush=True)
        ros.cleanup_logs()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
