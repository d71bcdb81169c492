"""The stock-driver profile's pure parts: bumper switches, Bayer mosaic, depth, camera model,
and the miswiring watch's logic (no ROS master)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rosnode_kit.input_watch import InputWatch, Publication
from turtlebot_sim.base_events import (
    BaseEventScript,
    Bumper,
    BumperChange,
    BumperSwitches,
    ScriptedEvent,
    Side,
    SwitchState,
    bumper_at,
)
from turtlebot_sim.config import resolve
from turtlebot_sim.kinect import Intrinsics
from turtlebot_sim.stock import bayer_grbg, depth_mm, kinect_hfov_deg


@pytest.mark.parametrize(("degrees", "expected"), [
    (0.0, Bumper.CENTER), (29.0, Bumper.CENTER), (-29.0, Bumper.CENTER),
    (45.0, Bumper.LEFT), (89.0, Bumper.LEFT), (-45.0, Bumper.RIGHT), (-89.0, Bumper.RIGHT),
    (120.0, None), (180.0, None), (-150.0, None), (360.0 + 10.0, Bumper.CENTER),
])
def test_bumper_by_contact_bearing(degrees: float, expected: Bumper | None):
    assert bumper_at(math.radians(degrees)) == expected


def test_switches_give_one_event_per_change():
    switches = BumperSwitches()
    assert switches.update([]) == []
    assert switches.update([math.radians(40), math.radians(42)]) == [
        BumperChange(Bumper.LEFT, SwitchState.PRESSED)]
    assert switches.bits == 4
    assert switches.update([math.radians(40)]) == []              # still pressed: no event
    assert switches.update([0.0]) == [BumperChange(Bumper.CENTER, SwitchState.PRESSED),
                                      BumperChange(Bumper.LEFT, SwitchState.RELEASED)]
    assert switches.update([math.radians(170)]) == [            # behind: no bumper there
        BumperChange(Bumper.CENTER, SwitchState.RELEASED)]
    assert switches.bits == 0


def test_bayer_grbg_samples_the_right_channel_at_each_site():
    rgb = np.zeros((4, 6, 3), dtype=np.uint8)
    rgb[..., 0], rgb[..., 1], rgb[..., 2] = 10, 20, 30
    mosaic = bayer_grbg(rgb)
    assert mosaic.shape == (4, 6) and mosaic.dtype == np.uint8
    assert (mosaic[0::2, 0::2] == 20).all() and (mosaic[0::2, 1::2] == 10).all()   # G R
    assert (mosaic[1::2, 0::2] == 30).all() and (mosaic[1::2, 1::2] == 20).all()   # B G


def test_depth_is_millimetres_with_zero_holes():
    z = np.array([[0.5, np.nan], [1.2344, 4.5]], dtype=np.float32)
    assert depth_mm(z).tolist() == [[500, 0], [1234, 4500]]
    assert depth_mm(z).dtype == np.uint16


@pytest.mark.parametrize("width", [640, 320])
def test_kinect_focal_length_is_525_at_vga_scaled(width: int):
    intr = Intrinsics(width, width * 3 // 4, kinect_hfov_deg(width))
    assert intr.fx == pytest.approx(525.0 * width / 640)
    assert intr.fy == intr.fx
    assert (intr.cx, intr.cy) == ((width - 1) / 2, (width * 3 // 4 - 1) / 2)


def _watch(**kw) -> InputWatch:
    return InputWatch(topic="/faulty/mobile_base/odom", msg_type="nav_msgs/Odometry",
                      node="/faulty/fault_injector", namespace="/faulty/", started=0.0,
                      hint="HINT", **kw)


DRIVER_ODOM = Publication("/faulty/odom", "nav_msgs/Odometry",
                          ("/turtlebot_sim", "/faulty/fault_injector"))


def test_silent_input_warns_naming_both_topics_when_another_publisher_flows():
    watch = _watch()
    assert watch.check(2.0, [DRIVER_ODOM]) is None            # not silent long enough yet
    warning = watch.check(3.5, [DRIVER_ODOM])
    assert warning is not None
    assert "/faulty/mobile_base/odom" in warning and "/faulty/odom" in warning
    assert "/turtlebot_sim" in warning and warning.endswith("HINT")
    assert watch.check(4.5, [DRIVER_ODOM]) is None            # repeated only after `repeat`
    assert watch.check(3.5 + watch.repeat, [DRIVER_ODOM]) is not None


def test_no_warning_without_evidence_or_when_heard():
    watch = _watch()
    own_only = Publication("/faulty/odom", "nav_msgs/Odometry", ("/faulty/fault_injector",))
    other_ns = Publication("/helper/odom", "nav_msgs/Odometry", ("/turtlebot_sim",))
    other_type = Publication("/faulty/cmd_vel", "geometry_msgs/Twist", ("/x",))
    assert watch.check(10.0, [own_only, other_ns, other_type]) is None   # robot not up
    watch.heard(9.0)
    assert watch.check(10.0, [DRIVER_ODOM]) is None
    assert watch.check(12.5, [DRIVER_ODOM]) is not None                  # silent again


def test_base_events_of_a_world_file_come_as_edges_in_time():
    cfg = resolve({"robots": [{"name": "bot"}], "base_events": [
        {"robot": "bot", "at": 1.0, "kind": "cliff", "side": "left", "duration": 0.5},
        {"robot": "bot", "at": 1.2, "kind": "wheel_drop", "side": "right", "duration": 2}]})
    script = BaseEventScript(cfg["base_events"])
    assert script.due(0.9) == []
    assert script.due(1.3) == [ScriptedEvent("bot", "cliff", Side.LEFT, True),
                               ScriptedEvent("bot", "wheel_drop", Side.RIGHT, True)]
    assert script.due(1.4) == []
    assert script.due(9.0) == [ScriptedEvent("bot", "cliff", Side.LEFT, False),
                               ScriptedEvent("bot", "wheel_drop", Side.RIGHT, False)]


@pytest.mark.parametrize("event", [
    {"robot": "nobody", "at": 1, "kind": "cliff"},
    {"robot": "bot", "at": 1, "kind": "wheel_drop", "side": "center"},
    {"robot": "bot", "at": 1, "kind": "earthquake"},
    {"robot": "bot", "at": -1, "kind": "cliff"},
])
def test_bad_base_events_are_refused_by_name(event):
    with pytest.raises(ValueError, match="base event"):
        resolve({"robots": [{"name": "bot"}], "base_events": [event]})
