"""RenderPool order check, run by test_render.py in a fresh process."""

import math

import numpy as np

from turtlebot_sim.render import RenderPool
from turtlebot_sim.world import World


def check_pool_order() -> None:
    with World.from_yaml("case_study.yaml") as world, \
            RenderPool(world.config, workers=2) as pool:
        world.set_pose("helper", 0.0, 0.0, -math.pi / 2)     # looking at Faulty
        facing = world.base_states()
        world.set_pose("helper", 0.0, 0.0, math.pi / 2)      # looking away
        away = world.base_states()
        frames = []
        for i, states in enumerate((facing, away, facing)):
            if pool.busy():
                frames += pool.collect(block=True)
            pool.submit(i * 0.1, "helper", states)
        while len(frames) < 3:
            frames += pool.collect(block=True)
        assert [f.stamp for f in frames] == [0.0, 0.1, 0.2]
        for frame in frames:
            assert frame.rgb.shape == (480, 640, 3) and frame.cloud.shape == (480, 640, 4)
            assert frame.cloud.dtype == np.float32 and frame.render_ms > 0

        def orange(rgb: np.ndarray) -> int:
            r, g, b = (rgb[:, :, i].astype(int) for i in range(3))
            return int(((r > 150) & (r > g + 60) & (r > b + 120)).sum())

        assert orange(frames[0].rgb) > 100 and orange(frames[2].rgb) > 100
        assert orange(frames[1].rgb) == 0
        assert not pool.collect()


if __name__ == "__main__":
    check_pool_order()
    print("pool order ok")
