"""Faulty's diagnosis rule on what the detector sees in the simulator (no ROS).

The case study's view (Helper turned right to face Faulty's left flank); Faulty drives ~0.3 m
healthy, with a slow right wheel (curves to its right) or a slow left wheel. The rule
``Yaw1 - (Yaw + (Deg1 - Deg))`` must stay near 0 / exceed 8 / go below -8.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from rason_diagnosis.paths import world_file
from rason_vision.detector import detect
from turtlebot_model.geometry import wrap_deg


def observe(world) -> tuple[float, float, float]:
    det = detect(*world.render_kinect("helper", rng=np.random.default_rng(1))).detection
    assert det is not None
    return det.angle, det.depth, det.yaw


@pytest.mark.parametrize("left,right,sign", [(1.0, 1.0, 0), (1.0, 0.4, +1), (0.4, 1.0, -1)])
def test_rule_on_simulated_moves(left, right, sign):
    from turtlebot_sim.world import World

    with World.from_yaml(world_file()) as world:
        world.set_pose("helper", 0.0, 0.0, -math.pi / 2)
        deg, _, yaw = observe(world)
        start = world.pose("faulty")
        world.set_wheel_fault("faulty", left=left, right=right)
        world.set_cmd_vel("faulty", 0.2, 0.0)
        while math.dist(world.pose("faulty")[:2], start[:2]) < 0.3 and world.time < 6.0:
            world.step()
        world.set_cmd_vel("faulty", 0.0, 0.0)
        turned = wrap_deg(math.degrees(world.pose("faulty")[2] - start[2]))  # + = left
        deg1, _, yaw1 = observe(world)
    rule = yaw1 - (yaw + (deg1 - deg))
    if sign == 0:
        assert abs(rule) < 3.0, (rule, turned)
        print(f"straight: rule {rule:.1f}")
    else:
        assert sign * rule > 8.0, (rule, turned)
        # the rule measures Faulty's own turn (clockwise positive)
        assert rule == pytest.approx(-turned, abs=3.0)
        print(f"left {left} right {right}: turned {turned:.1f} deg, rule {rule:.1f}")
