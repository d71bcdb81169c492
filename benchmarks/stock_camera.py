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
import statistics
import time

from _moving import robots_moving

from rason.process.harness import RosHarness
from rason_diagnosis.paths import world_file
from turtlebot_sim.stats import read_stats


def run(ros: RosHarness, rate: float, width: int, seconds: float) -> dict[str, float]:
    import rospy
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
    with robots_moving(ns):
        time.sleep(3.0)
        start, wall0, mark = dict(counts), time.monotonic(), len(sim.lines())
        time.sleep(seconds)
        wall = time.monotonic() - wall0
        got = {k: (counts[k] - start[k]) / wall for k in counts}
    for sub in subs:
        sub.unregister()
    sim.stop()
    stats = read_stats(sim.lines()[mark:])
    return {"rgb": got["rgb"], "depth": got["depth"],
            "ms": statistics.fmean(s.render_ms for s in stats) if stats else math.nan,
            "rtf": statistics.fmean(s.rtf for s in stats) if stats else math.nan,
            "dropped": sum(s.dropped for s in stats)}


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
