"""``./run.sh test --fast`` (``-m "not ros and not slow"``) leaves out every test that starts a
roscore: tests using a roscore fixture are marked ``ros`` by tests/conftest.py, and a test file
that starts a harness itself says ``pytestmark = pytest.mark.ros``."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROS_FIXTURES
from draws import FAST, examples

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


def test_the_inner_loop_draws_a_share_of_the_property_tests_examples(monkeypatch):
    monkeypatch.delenv(FAST, raising=False)
    assert [examples(n) for n in (20, 60, 1500)] == [20, 60, 1500]     # the full suite
    monkeypatch.setenv(FAST, "1")
    assert [examples(n) for n in (20, 60, 1500)] == [20, 40, 300]      # --fast: a fifth, >= 40
