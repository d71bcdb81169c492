"""The robot synthesizer's odometry headings by time (``~odom_bearings``: ``seen_at``)."""

from __future__ import annotations

import pytest

from rason_vision.synthesizer import HeadingHistory


def test_heading_at_a_frame_stamp_is_interpolated_across_plus_minus_180():
    history = HeadingHistory()
    history.add(10.00, 170.0)
    history.add(10.02, -170.0)       # 20 degrees clockwise, across +-180
    assert history.at(10.01) == pytest.approx(180.0)
    assert history.at(10.015) == pytest.approx(-175.0)
    assert history.at(10.00) == pytest.approx(170.0)
    assert history.at(10.05) == pytest.approx(-170.0)      # after the last sample, within 0.1 s


def test_no_heading_far_from_every_sample_and_old_samples_are_dropped():
    history = HeadingHistory(seconds=1.0)
    assert history.at(1.0) is None
    history.add(1.0, 5.0)
    assert history.at(1.5) is None and history.at(0.5) is None
    history.add(3.0, 7.0)            # 1.0 is now older than a second
    assert history.at(1.0) is None
    assert history.at(3.0) == pytest.approx(7.0)


def test_time_going_back_starts_afresh():
    history = HeadingHistory()
    history.add(50.0, 30.0)
    history.add(0.5, -40.0)          # the simulation restarted
    assert history.at(50.0) is None
    assert history.at(0.5) == pytest.approx(-40.0)
