"""Record the odometry sequences replayed by ``test_motion_checks.py`` (run by hand, not by pytest).

    python tests/robot/record_odometry.py        # after: source env.sh

Starts roscore + turtlebot_sim (Faulty alone, sim time) + the fault injector, and for each
fault drives the base open loop at 0.2 m/s for a few sim seconds, writing what the decomposer
would see (``/faulty/odom``, after the injector) and the simulator's ground truth to
``data/odom_<fault>.csv``: ``t, x, y, yaw, gt_x, gt_y, gt_yaw`` (t in sim seconds from the
first command; poses relative to the start, yaw in radians).
"""

from __future__ import annotations

import csv
import math
import sys
import tempfile
import threading
import time
from pathlib import Path

import rospy
from geometry_msgs.msg import Twist, Vector3
from nav_msgs.msg import Odometry

from kobuki_fault_injector.srv import FaultInjector
from rason.process.harness import RosHarness
from turtlebot_model.geometry import yaw_from_quaternion

DATA = Path(__file__).resolve().parent / "data"
SCENARIOS = {"none": 6.0, "left_actuator": 3.0, "right_actuator": 3.0, "both_actuators": 2.0,
             "odometry": 2.0}
SPEED = 0.2
WORLD = "robots:\n  - {name: faulty, kind: faulty, x: -3.0, y: 0.0, yaw: 0.0}\n"


def pose(msg: Odometry) -> tuple[float, float, float]:
    p, q = msg.pose.pose.position, msg.pose.pose.orientation
    return p.x, p.y, yaw_from_quaternion(q.x, q.y, q.z, q.w)


def relative(p: tuple[float, float, float], p0: tuple[float, float, float]) -> list[float]:
    dx, dy = p[0] - p0[0], p[1] - p0[1]
    c, s = math.cos(p0[2]), math.sin(p0[2])
    return [c * dx + s * dy, -s * dx + c * dy, math.remainder(p[2] - p0[2], 2 * math.pi)]


def record(fault: str, seconds: float, fault_service: rospy.ServiceProxy) -> list[list[float]]:
    lock = threading.Lock()
    truth: list[Odometry] = []
    rows: list[tuple[Odometry, Odometry]] = []

    def on_truth(msg: Odometry) -> None:
        with lock:
            truth[:] = [msg]

    def on_odom(msg: Odometry) -> None:
        with lock:
            if truth:
                rows.append((msg, truth[0]))

    subs = [rospy.Subscriber("/faulty/ground_truth/odom", Odometry, on_truth, queue_size=100),
            rospy.Subscriber("/faulty/odom", Odometry, on_odom, queue_size=100)]
    cmd = rospy.Publisher("/faulty/cmd_vel", Twist, queue_size=10)
    time.sleep(1.0)                                  # connections up (a recording, not a test)
    fault_service("cancel")
    time.sleep(0.3)                                  # odometry seen before the fault
    if fault != "none":
        fault_service(fault)
    with lock:
        rows.clear()
    t0: float | None = None
    while True:
        with lock:
            last = rows[-1][0].header.stamp.to_sec() if rows else None
        if last is not None:
            t0 = last if t0 is None else t0
            if last - t0 >= seconds:
                break
        cmd.publish(Twist(linear=Vector3(x=SPEED)))
        time.sleep(0.01)                             # the command stream's pace
    cmd.publish(Twist())
    for sub in subs:
        sub.unregister()
    with lock:
        first_odom, first_truth = pose(rows[0][0]), pose(rows[0][1])
        return [[round(o.header.stamp.to_sec() - rows[0][0].header.stamp.to_sec(), 4),
                 *(round(v, 6) for v in relative(pose(o), first_odom)),
                 *(round(v, 6) for v in relative(pose(g), first_truth))]
                for o, g in rows]


def main() -> int:
    DATA.mkdir(exist_ok=True)
    with RosHarness() as ros, tempfile.TemporaryDirectory() as tmp:
        world = Path(tmp) / "world.yaml"
        world.write_text(WORLD)
        ros.init_rospy("record_odometry")
        ros.set_param("/use_sim_time", True)
        for fault, seconds in SCENARIOS.items():
            checkpoint = ros.checkpoint()
            sim = ros.rosrun("turtlebot_sim", "sim", f"_world:={world}", "_real_time_factor:=1")
            injector = ros.rosrun("kobuki_fault_injector", "fault_injector", ns="/faulty")
            ros.wait_for_service("/faulty/fault_injector", watch=[sim, injector])
            ros.wait_for_topic("/faulty/odom", watch=[sim, injector])
            rows = record(fault, seconds, rospy.ServiceProxy("/faulty/fault_injector", FaultInjector))
            ros.rollback(checkpoint)
            path = DATA / f"odom_{fault}.csv"
            with open(path, "w", newline="", encoding="utf-8") as f:
                writer = csv.writer(f)
                writer.writerow(["t", "x", "y", "yaw", "gt_x", "gt_y", "gt_yaw"])
                writer.writerows(rows)
            print(f"{path}: {len(rows)} rows, odom end {rows[-1][1:4]}, truth end {rows[-1][4:]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
