"""`rosrun turtlebot_sim sim _drivers:=stock` against docs/drivers.md's table, and bumper events.

The topic set, the types and md5sums on the wire (read from the connection headers), the
encodings, frame ids, camera model and stamps are checked against the table of the real drivers'
topics in docs/drivers.md; there is no /clock. A robot driven into a wall raises a bumper event,
in both profiles. (The kobuki_msgs md5sums are the real package's: tests/workspace/test_kobuki_msgs.)
"""

from __future__ import annotations

import re
import threading
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
from polling import wait_until

from rason_diagnosis.paths import world_file

pytestmark = pytest.mark.ros

DOC = Path(__file__).resolve().parents[2] / "docs" / "drivers.md"
ROBOTS = {"faulty": False, "helper": True}       # name -> has a Kinect (case_study.yaml)


@dataclass(frozen=True)
class Row:
    topic: str
    msg_type: str
    published: bool


def stock_table() -> list[Row]:
    """The rows of docs/drivers.md's "Stock profile: topics" table."""
    text = DOC.read_text(encoding="utf-8")
    section = text.split("## Stock profile: topics", 1)[1].split("\n## ", 1)[0]
    rows = []
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        match = re.fullmatch(r"`([^`]+)`", cells[0]) if len(cells) >= 3 else None
        if match:
            rows.append(Row(match.group(1), cells[1], cells[2] == "pub"))
    assert len(rows) >= 10, f"no topic table found in {DOC}"
    return rows


def expected_topics(ns: str) -> dict[str, Row]:
    out = {}
    for row in stock_table():
        if row.topic.startswith("/"):
            out[row.topic] = row
            continue
        for robot, camera in ROBOTS.items():
            if camera or not row.topic.startswith("camera/"):
                out[f"{ns}/{robot}/{row.topic}"] = row
    return out


class Collect:
    """Messages of one topic (typed, or rospy.AnyMsg for the connection header)."""

    def __init__(self, topic: str, msg_type: type) -> None:
        import rospy

        self.msgs: list = []
        self.cond = threading.Condition()
        self.sub = rospy.Subscriber(topic, msg_type, self._on, queue_size=100,
                                    buff_size=2 ** 24)

    def _on(self, msg) -> None:
        with self.cond:
            self.msgs.append(msg)
            self.cond.notify_all()

    def wait(self, count: int = 1, timeout: float = 30.0) -> list:
        with self.cond:
            assert self.cond.wait_for(lambda: len(self.msgs) >= count, timeout), \
                f"{self.sub.name}: {len(self.msgs)} of {count} messages in {timeout} s"
            return list(self.msgs)


def test_stock_profile_matches_the_table_and_has_no_clock(ros):
    import rosgraph
    import rospy
    from roslib.message import get_message_class
    from sensor_msgs.msg import CameraInfo, Image

    ns = "/stock"
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns,
                     params={"world": str(world_file()), "drivers": "stock"})
    ros.wait_for_topic(f"{ns}/helper/camera/depth_registered/image_raw", timeout=60, watch=[sim])
    ros.init_rospy()
    expected = expected_topics(ns)

    # -- the topic set and types on the master ----------------------------------------------
    master = rosgraph.Master("/stock_test")
    sim_node = f"{ns}/turtlebot_sim"
    want_ours = {t for t, r in expected.items() if r.published}
    want_theirs = {t for t, r in expected.items() if not r.published}

    def registered() -> tuple[set[str], set[str]] | None:
        """The sim's published and subscribed topics once it has registered all it should
        (the camera topic waited for above is not its last registration)."""
        published, subscribed, _ = master.getSystemState()
        ours = {t for t, nodes in published if sim_node in nodes}
        theirs = {t for t, nodes in subscribed if sim_node in nodes}
        return (ours, theirs) if ours >= want_ours and theirs >= want_theirs else None

    ours, theirs = wait_until(registered, "the sim's registrations", timeout=30, watch=[sim])
    types = dict(master.getTopicTypes())     # after: it holds every topic registered above
    assert ours - {"/rosout"} == want_ours
    assert theirs == want_theirs
    for topic, row in expected.items():
        assert types[topic] == row.msg_type, topic
    # (the suite's master may still list a /clock of an earlier test's killed simulator)
    assert "/clock" not in ours, "the stock profile publishes no /clock"

    # -- md5sums and types on the wire (connection headers), for what flows ----------------------
    flowing = {t: r for t, r in expected.items() if r.published and "/events/" not in t}
    raw = {t: Collect(t, rospy.AnyMsg) for t in flowing}
    for topic, row in flowing.items():
        header = raw[topic].wait()[0]._connection_header
        assert header["type"] == row.msg_type, topic
        assert header["md5sum"] == get_message_class(row.msg_type)._md5sum, topic
    for topic in (t for t in expected if "/events/" in t):      # events: md5 from the master
        assert get_message_class(types[topic])._md5sum == \
            get_message_class(expected[topic].msg_type)._md5sum
    for sub in raw.values():
        sub.sub.unregister()

    # -- the Kinect: encodings, frames, camera model, stamps apart by the depth offset --------
    cam = f"{ns}/helper/camera"
    images = Collect(f"{cam}/rgb/image_raw", Image)
    depths = Collect(f"{cam}/depth_registered/image_raw", Image)
    infos = Collect(f"{cam}/rgb/camera_info", CameraInfo)
    depth_infos = Collect(f"{cam}/depth_registered/camera_info", CameraInfo)
    image, depth = images.wait(5)[-1], depths.wait(5)[-1]
    assert (image.encoding, image.width, image.height, image.step) == \
        ("bayer_grbg8", 640, 480, 640)
    assert (depth.encoding, depth.step, depth.is_bigendian) == ("16UC1", 1280, 0)
    assert image.header.frame_id == depth.header.frame_id == "camera_rgb_optical_frame"
    mm = np.frombuffer(depth.data, dtype="<u2")
    assert (mm == 0).any() and mm[mm > 0].min() >= 500 and mm.max() <= 4500   # holes are 0
    info = infos.wait()[-1]
    assert list(info.K) == [525.0, 0.0, 319.5, 0.0, 525.0, 239.5, 0.0, 0.0, 1.0]
    assert (info.width, info.height, info.distortion_model) == (640, 480, "plumb_bob")
    assert list(depth_infos.wait()[-1].K) == list(info.K)
    rgb_stamps = {round(m.header.stamp.to_sec(), 3) for m in images.wait(5)}
    depth_stamps = {round(m.header.stamp.to_sec(), 3) for m in depths.wait(5)}
    pairs = {round(t + (-0.055), 3) for t in rgb_stamps} & depth_stamps
    assert pairs, (sorted(rgb_stamps), sorted(depth_stamps))
    assert not rgb_stamps & depth_stamps                      # stamped apart
    # wall-clock stamps (no sim time): within a few seconds of now, however loaded the machine
    assert abs(image.header.stamp.to_sec() - time.time()) < 10.0

    # -- odometry as kobuki_node's ------------------------------------------------------------
    from nav_msgs.msg import Odometry

    odom = Collect(f"{ns}/faulty/odom", Odometry).wait()[-1]
    assert (odom.header.frame_id, odom.child_frame_id) == ("odom", "base_footprint")
    cov = odom.pose.covariance
    assert (cov[0], cov[7], cov[35], cov[14], cov[21], cov[28]) == \
        (0.1, 0.1, 0.05, 1e10, 1e10, 1e10)
    assert not any(odom.twist.covariance)


WALL_WORLD = """\
# One robot 0.4 m in front of the +x wall of a 3 x 3 m room, facing it.
room: {size: [3.0, 3.0]}
robots:
  - {name: bot, kind: plain, x: 0.9, y: 0.0, yaw: 0.0}
"""


@pytest.mark.parametrize("drivers", ["sim", "stock"])
def test_driving_into_a_wall_presses_the_centre_bumper_then_releases_it(
        ros, tmp_path: Path, drivers: str):
    from geometry_msgs.msg import Twist
    from kobuki_msgs.msg import BumperEvent

    ns = f"/wall_{drivers}"
    world = tmp_path / "wall.yaml"
    world.write_text(WALL_WORLD)
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns,
                     params={"world": str(world), "drivers": drivers})
    ros.wait_for_topic(f"{ns}/bot/mobile_base/events/bumper", timeout=60, watch=[sim])
    ros.init_rospy()
    import rospy

    events = Collect(f"{ns}/bot/mobile_base/events/bumper", BumperEvent)
    cmd = rospy.Publisher(f"{ns}/bot/mobile_base/commands/velocity", Twist, queue_size=1)
    ros.wait_for_subscriber(f"{ns}/bot/mobile_base/commands/velocity", watch=[sim])

    def drive_until(v: float, done, timeout: float = 60.0) -> None:
        twist = Twist()
        twist.linear.x = v
        deadline = time.monotonic() + timeout
        while not done() and time.monotonic() < deadline:
            cmd.publish(twist)
            time.sleep(0.1)                     # the command stream's pace (10 Hz)
        cmd.publish(Twist())

    pressed = lambda: any(e.state == BumperEvent.PRESSED for e in events.msgs)  # noqa: E731
    drive_until(0.2, pressed)
    assert pressed(), "no bumper press driving into the wall"
    first = events.msgs[0]
    assert (first.bumper, first.state) == (BumperEvent.CENTER, BumperEvent.PRESSED)
    released = lambda: events.msgs[-1].state == BumperEvent.RELEASED  # noqa: E731
    drive_until(-0.2, released)
    assert released(), [(e.bumper, e.state) for e in events.msgs]
    assert events.msgs[-1].bumper == BumperEvent.CENTER


def test_a_world_base_event_raises_a_cliff_then_clears_it(ros, tmp_path: Path):
    from kobuki_msgs.msg import CliffEvent, SensorState, WheelDropEvent

    ns = "/cliff"
    world = tmp_path / "cliff.yaml"
    world.write_text(WALL_WORLD + "base_events:\n"
                     "  - {robot: bot, at: 4.0, kind: cliff, side: right, duration: 1.0}\n"
                     "  - {robot: bot, at: 4.0, kind: wheel_drop, side: left, duration: 1.0}\n")
    sim = ros.rosrun("turtlebot_sim", "sim", ns=ns,
                     params={"world": str(world), "drivers": "stock"})
    ros.wait_for_topic(f"{ns}/bot/mobile_base/events/cliff", timeout=60, watch=[sim])
    ros.init_rospy()
    cliffs = Collect(f"{ns}/bot/mobile_base/events/cliff", CliffEvent)
    drops = Collect(f"{ns}/bot/mobile_base/events/wheel_drop", WheelDropEvent)
    core = Collect(f"{ns}/bot/mobile_base/sensors/core", SensorState)
    cliff_on, cliff_off = cliffs.wait(2, timeout=60)
    assert (cliff_on.sensor, cliff_on.state) == (CliffEvent.RIGHT, CliffEvent.CLIFF)
    assert (cliff_off.sensor, cliff_off.state) == (CliffEvent.RIGHT, CliffEvent.FLOOR)
    drop_on, drop_off = drops.wait(2)
    assert (drop_on.wheel, drop_on.state) == (WheelDropEvent.LEFT, WheelDropEvent.DROPPED)
    assert drop_off.state == WheelDropEvent.RAISED
    after = core.wait(len(core.msgs) + 5)[-1]                  # a state sent after the events
    bits = {(m.cliff, m.wheel_drop) for m in core.msgs}
    assert (SensorState.CLIFF_RIGHT, SensorState.WHEEL_DROP_LEFT) in bits   # while it lasted
    assert (after.cliff, after.wheel_drop) == (0, 0)
