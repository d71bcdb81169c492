#!/usr/bin/env python3
"""Simulation speed: real-time factor with two robots and the Kinect at 15 and 30 Hz.

Three measurements, all with both robots moving (Faulty drives a curve, Helper turns) so every
Kinect frame is a fresh TinyRenderer picture (the worst case; a still scene is not re-rendered):

1. one frame on one core: TinyRenderer 640x480 RGB + depth, then the Kinect noise + packing;
2. the library pipeline without ROS (``World`` + ``RenderPool`` exactly as the node runs them),
   as fast as possible;
3. the real node, ``rosrun turtlebot_sim sim _real_time_factor:=0`` (as fast as possible) with a
   subscriber on both camera topics, real-time factor measured from /clock over wall time.

Target: at least 1x real time with the Kinect at 15 Hz on this 2-core machine.

    ./run.sh bench sim_speed [--seconds 12] [--workers 1,2] [--no-ros]
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import time

import numpy as np
from _moving import COMMANDS, robots_moving

from rason.process.harness import RosHarness
from rason_diagnosis.paths import world_file
from turtlebot_model.cloud import pack_cloud
from turtlebot_sim import kinect
from turtlebot_sim.render import RenderPool
from turtlebot_sim.stats import read_stats
from turtlebot_sim.world import World

WORLD = str(world_file())          # the case study's world


def single_frame(frames: int = 20) -> tuple[float, float]:
    """(ms TinyRenderer, ms noise + packing) per frame, median, one core, no cache hits."""
    with World.from_yaml(WORLD) as world:
        rng = np.random.default_rng(0)
        render, sense = [], []
        for i in range(frames):
            world.set_pose("helper", 0.0, 0.0, -math.pi / 2 + 0.01 * i)
            start = time.perf_counter()
            rgba, depth = world.render_raw("helper")
            mid = time.perf_counter()
            rgb, xyz = kinect.sense(rgba, depth, world.intrinsics, world.noise, rng)
            pack_cloud(xyz, rgb)
            end = time.perf_counter()
            render.append((mid - start) * 1000)
            sense.append((end - mid) * 1000)
    return statistics.median(render[2:]), statistics.median(sense[2:])


def pipeline(rate: float, workers: int, seconds: float) -> tuple[float, float, int]:
    """Library loop as the node runs it: (real-time factor, worker ms per frame, frames)."""
    with World.from_yaml(WORLD) as world, RenderPool(world.config, workers=workers) as pool:
        world.set_cmd_vel("faulty", *COMMANDS["faulty"])
        world.set_cmd_vel("helper", *COMMANDS["helper"])
        next_frame, ms, frames = 0.0, [], 0
        start = time.perf_counter()
        while world.time < seconds:
            world.step()
            if world.time + 1e-9 >= next_frame:
                next_frame += 1.0 / rate
                while pool.busy():
                    done = pool.collect(block=True)
                    ms += [f.render_ms for f in done]
                pool.submit(world.time, "helper", world.base_states())
            done = pool.collect()
            ms += [f.render_ms for f in done]
        while True:
            done = pool.collect(block=True)
            if not done:
                break
            ms += [f.render_ms for f in done]
        wall = time.perf_counter() - start
        frames = len(ms)
    return world.time / wall, statistics.fmean(ms), frames


def node(ros: RosHarness, rate: float, workers: int, seconds: float) -> tuple[float, float, int]:
    """The ROS node at full speed: (real-time factor from /clock, worker ms per frame, frames)."""
    import rospy
    from rosgraph_msgs.msg import Clock
    from sensor_msgs.msg import Image, PointCloud2

    ns = f"/bench{rate:.0f}w{workers}"
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns,
                     params={"world": WORLD, "real_time_factor": 0, "camera_rate": rate,
                             "render_workers": workers, "stats_period": 1000})
    ros.wait_for_topic(f"{ns}/helper/camera/depth_registered/points", timeout=60,
                       watch=[sim])
    ros.init_rospy("sim_speed")
    clock = [0.0]
    frames = [0]
    subs = [rospy.Subscriber("/clock", Clock, lambda m: clock.__setitem__(0, m.clock.to_sec())),
            rospy.Subscriber(f"{ns}/helper/camera/rgb/image_raw", Image,
                             lambda m: None, queue_size=2, buff_size=2 ** 24),
            rospy.Subscriber(f"{ns}/helper/camera/depth_registered/points", PointCloud2,
                             lambda m: frames.__setitem__(0, frames[0] + 1), queue_size=2,
                             buff_size=2 ** 24)]
    with robots_moving(ns, period=0.02):
        time.sleep(3.0)                                   # connections up, warm
        sim_start, frames_start, wall_start = clock[0], frames[0], time.monotonic()
        log_mark = len(sim.lines())
        time.sleep(seconds)
        sim_span, wall = clock[0] - sim_start, time.monotonic() - wall_start
        got = frames[0] - frames_start
    for sub in subs:
        sub.unregister()
    sim.stop()
    stats = read_stats(sim.lines()[log_mark:])
    return sim_span / wall, stats[-1].render_ms if stats else math.nan, got


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=12.0, help="length of each run")
    parser.add_argument("--workers", default="1,2", help="render worker counts to try")
    parser.add_argument("--no-ros", action="store_true", help="skip the ROS node runs")
    args = parser.parse_args()
    worker_counts = [int(w) for w in args.workers.split(",")]
    print(f"machine: {os.cpu_count()} cores, load average {os.getloadavg()[0]:.2f}")
    render_ms, sense_ms = single_frame()
    print(f"\none Kinect frame on one core: render (TinyRenderer robots + ray-cast room) "
          f"{render_ms:.1f} ms + noise/packing {sense_ms:.1f} ms = {render_ms + sense_ms:.1f} ms\n")
    print("| run | Kinect Hz | render workers | real-time factor | ms per rendered frame | frames |")
    print("|---|---|---|---|---|---|")
    best: dict[tuple[str, float], float] = {}
    for rate in (15.0, 30.0):
        for workers in worker_counts:
            rtf, ms, frames = pipeline(rate, workers, args.seconds)
            print(f"| library (no ROS) | {rate:.0f} | {workers} | {rtf:.2f} | {ms:.1f} | {frames} |",
                  flush=True)
            best[("library", rate)] = max(best.get(("library", rate), 0.0), rtf)
    if not args.no_ros:
        with RosHarness() as ros:
            for rate in (15.0, 30.0):
                for workers in worker_counts:
                    rtf, ms, frames = node(ros, rate, workers, args.seconds)
                    print(f"| ROS node | {rate:.0f} | {workers} | {rtf:.2f} | {ms:.1f} | "
                          f"{frames} |", flush=True)
                    best[("node", rate)] = max(best.get(("node", rate), 0.0), rtf)
        ros.cleanup_logs()
    kind = "library" if args.no_ros else "node"
    verdict = "PASS" if best[(kind, 15.0)] >= 1.0 else "FAIL"
    print(f"\ntarget: >= 1x real time with the Kinect at 15 Hz ({kind}, best worker count): "
          f"{best[(kind, 15.0)]:.2f}x {verdict}; at 30 Hz: {best[(kind, 30.0)]:.2f}x")
    print(f"load average after the runs: {os.getloadavg()[0]:.2f} (other processes on the "
          "machine slow the figures down)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
