"""One angle convention everywhere: wrapped into (-180, 180] degrees / (-pi, pi] radians."""

from __future__ import annotations

import math

import pytest

from turtlebot_model.geometry import angle_diff_deg, wrap_deg, wrap_rad


@pytest.mark.parametrize("angle,wrapped", [(180.0, 180.0), (-180.0, 180.0), (540.0, 180.0),
                                           (181.0, -179.0), (-181.0, 179.0), (359.5, -0.5),
                                           (-344.8, 15.2), (0.0, 0.0), (720.0, 0.0)])
def test_wrap_deg(angle, wrapped):
    assert wrap_deg(angle) == pytest.approx(wrapped)
    assert wrap_rad(math.radians(angle)) == pytest.approx(math.radians(wrapped))


def test_turn_across_180_is_the_short_one():
    """The issue's case: yaw 178.4 then -167.9 is a 13.7-degree turn to the right."""
    assert angle_diff_deg(-167.9, 178.4) == pytest.approx(13.7)
    assert angle_diff_deg(178.4, -167.9) == pytest.approx(-13.7)
