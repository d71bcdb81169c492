"""Kinect rendering: the ray-cast room matches TinyRenderer's, the cache, the worker pool."""

from __future__ import annotations

import math
import socket

import numpy as np
import pytest

from rason_diagnosis.paths import world_file
from turtlebot_sim import config
from turtlebot_sim.render import RenderPool
from turtlebot_sim.world import World


def _world(analytic: bool) -> World:
    cfg = config.resolve(world_file())
    cfg["camera"]["analytic_room"] = analytic
    return World(cfg)


@pytest.mark.parametrize("pose", [(0.0, 0.0, -math.pi / 2 + 0.2), (3.5, 3.0, 0.8),
                                  (-4.0, -4.5, -2.5)])
def test_ray_cast_room_looks_like_tinyrenderer_room(pose):
    with _world(True) as fast, _world(False) as full:
        assert fast.room is not None and full.room is None
        pictures = []
        for world in (fast, full):
            world.set_pose("helper", *pose)
            pictures.append(world.render_raw("helper"))
        (rgb_a, z_a), (rgb_b, z_b) = pictures
        colour_off = np.abs(rgb_a.astype(int) - rgb_b).max(axis=2) > 3
        assert colour_off.mean() < 0.005                    # edges only
        assert (np.isfinite(z_a) != np.isfinite(z_b)).mean() < 0.001
        both = np.isfinite(z_a) & np.isfinite(z_b)
        assert np.median(np.abs(z_a[both] - z_b[both])) < 0.005


def test_a_still_scene_is_not_rendered_again_but_gets_fresh_noise():
    with World.from_yaml(world_file()) as world:
        rgb1, xyz1 = world.render_kinect("helper")
        rgb2, xyz2 = world.render_kinect("helper")
        assert world.renders == 1
        assert not np.array_equal(rgb1, rgb2)
        assert np.abs(rgb1.astype(int) - rgb2).mean() < 5
        assert not np.array_equal(xyz1, xyz2, equal_nan=True)
        assert np.nanmedian(np.abs(xyz1[:, :, 2] - xyz2[:, :, 2])) < 0.02
        world.set_cmd_vel("faulty", 0.3, 0.0)
        for _ in range(20):
            world.step()
        world.render_kinect("helper")
        assert world.renders == 2


@pytest.mark.parametrize("default_timeout", [None, 60.0])
def test_render_pool_returns_frames_in_order_for_the_given_poses(default_timeout):
    # 60.0: what rospy sets with socket.setdefaulttimeout() once its node runs; new sockets are
    # then non-blocking, which made the workers quit at their first read (the sim died mid-demo).
    previous = socket.getdefaulttimeout()
    socket.setdefaulttimeout(default_timeout)
    try:
        _check_pool_order()
    finally:
        socket.setdefaulttimeout(previous)


def _check_pool_order() -> None:
    with World.from_yaml(world_file()) as world, \
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

