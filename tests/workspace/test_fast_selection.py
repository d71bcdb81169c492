"""``./run.sh test --fast`` (``-m "not ros and not slow"``) leaves out every test that starts a
roscore: tests using a roscore fixture are marked ``ros`` by tests/conftest.py, and a test file
that starts a harness itself says ``pytestmark = pytest.mark.ros``."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROS_FIXTURES

TESTS = Path(__file__).resolve().parents[1]


def test_every_collected_test_using_a_roscore_fixture_is_marked_ros(request: pytest.FixtureRequest):
    unmarked = [item.nodeid for item in request.session.items
                if ROS_FIXTURES & set(getattr(item, "fixturenames", ()))
                and item.get_closest_marker("ros") is None]
    assert not unmarked, unmarked


def test_a_test_file_starting_its_own_harness_is_marked_ros():
    unmarked = [str(path.relative_to(TESTS)) for path in TESTS.rglob("test_*.py")
                if "RosHarness(" in (text := path.read_text(encoding="utf-8"))
                and "pytest.mark.ros" not in text]
    assert not unmarked, unmarked
