"""The workspace's kobuki_msgs types are the real Kobuki base's, byte for byte on the wire.

Debian 12 ships no Kobuki packages, so the workspace defines the few kobuki_msgs types rason
uses. A ROS 1 message type interoperates with real nodes and bags when its name and md5sum are
the same; the sums below are what ``rosmsg md5`` prints for kobuki_msgs 0.7.0, the version
kobuki_node publishes on a TurtleBot 2.
"""

from __future__ import annotations

import importlib
from io import BytesIO

import pytest
from kobuki_msgs.msg import BumperEvent

#: md5sums of the real kobuki_msgs 0.7.0 definitions
REAL_MD5SUMS = {
    "BumperEvent": "ffe360cd50f14f9251d9844083e72ac5",
    "CliffEvent": "c5b106efbb1427a94f517c5e05f06295",
    "WheelDropEvent": "e102837d89384d67669a0df86b63f33b",
    "ButtonEvent": "49eca512765dbdec759a79083ffcec8d",
    "SensorState": "430a4bfd78449c8740bfef32b26613a6",
}


@pytest.mark.parametrize("name", sorted(REAL_MD5SUMS))
def test_each_type_has_the_real_md5sum(name: str) -> None:
    msg_class = getattr(importlib.import_module("kobuki_msgs.msg"), name)
    assert msg_class._md5sum == REAL_MD5SUMS[name]
    assert msg_class._type == f"kobuki_msgs/{name}"


def test_a_bumper_press_round_trips_through_its_wire_form() -> None:
    buffer = BytesIO()
    BumperEvent(bumper=BumperEvent.CENTER, state=BumperEvent.PRESSED).serialize(buffer)
    back = BumperEvent().deserialize(buffer.getvalue())
    assert (back.bumper, back.state) == (1, 1)
    assert len(buffer.getvalue()) == 2
