"""The robot synthesizer's odometry headings by time (``~odom_bearings``: ``seen_at``)."""

from __future__ import annotations

import pytest

from rason_vision.synthesizer import HeadingHistory, frame_literal, sighting_annotations


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


# -- [moving] and [stamp(Ms)]: frames taken with the camera at rest (issue 15, F10) -------------

def history_of(*samples: tuple[float, float, float]) -> HeadingHistory:
    """A history of (t, heading, x) samples at y = 0."""
    history = HeadingHistory()
    for t, heading, x in samples:
        history.add(t, heading, x, 0.0)
    return history


def at_rest_from(t0: float, t1: float, heading: float = 30.0) -> list[tuple[float, float, float]]:
    """50 Hz samples at rest from t0 to t1."""
    n = round((t1 - t0) * 50)
    return [(t0 + i / 50, heading, 1.0) for i in range(n + 1)]


def test_a_frame_taken_at_rest_is_not_moving_and_carries_its_stamp():
    history = history_of(*at_rest_from(10.0, 11.0))
    assert history.at_rest(10.5, 0.1)
    assert sighting_annotations(10.5, history, 0.1, stamps=True) == "[stamp(10500)]"
    assert sighting_annotations(10.5, history, 0.1, stamps=False) == ""
    assert sighting_annotations(10.5, None, 0.1, stamps=False) == ""   # no odometry: unmarked


def test_a_frame_taken_at_the_end_of_a_turn_is_moving_however_late_it_is_marked():
    # turning at 20 deg/s until 10.5, then at rest up to 12.0 (the frame is marked at 12.0)
    turning = [(10.0 + i / 50, 20.0 * i / 50, 1.0) for i in range(26)]
    rest = [(t, 10.0, 1.0) for t, _, _ in at_rest_from(10.52, 12.0)]
    history = history_of(*turning, *rest)
    assert sighting_annotations(10.48, history, 0.1, stamps=True) == "[moving,stamp(10480)]"
    assert sighting_annotations(10.55, history, 0.1, stamps=False) == "[moving]"  # within margin
    assert sighting_annotations(10.65, history, 0.1, stamps=False) == ""


def test_a_small_turn_or_a_drive_counts_as_moving():
    small = history_of(*at_rest_from(10.0, 10.5), (10.52, 30.5, 1.0), *[
        (t, 30.5, 1.0) for t, _, _ in at_rest_from(10.54, 11.0)])
    assert not small.at_rest(10.45, 0.1)            # 0.5 degrees since the frame
    assert small.at_rest(10.7, 0.1)
    drive = history_of(*at_rest_from(10.0, 10.5), *[
        (t, 30.0, 1.0 + 0.01 * i) for i, (t, _, _) in enumerate(at_rest_from(10.52, 11.0))])
    assert not drive.at_rest(10.3, 0.1)             # it drove off after the frame
    assert not drive.at_rest(10.8, 0.1)


def test_a_frame_the_odometry_has_not_caught_up_with_or_older_than_it_is_moving():
    history = history_of(*at_rest_from(10.0, 11.0))
    assert not history.at_rest(11.2, 0.1)           # newest odometry 0.2 s before the frame
    assert history.at_rest(11.03, 0.1)              # within ODOM_LAG_S
    assert not history.at_rest(10.05, 0.1)          # the history does not reach 9.95
    assert not HeadingHistory().at_rest(10.0, 0.1)  # no odometry at all


def test_every_frame_is_stamped_in_whole_milliseconds():
    assert frame_literal(12.3456) == "frame(12346)"
    assert frame_literal(1795461797.4567) == "frame(1795461797457)"   # wall-clock ROS time
