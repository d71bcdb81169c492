"""turtlebot_sim.world without ROS: drive, odometry, faults, Kinect rendering, determinism."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rason_diagnosis.paths import world_file
from turtlebot_model.cloud import pack_cloud, unpack_rgb
from turtlebot_sim import config, kinect, kobuki
from turtlebot_sim.world import World

CASE = world_file()


def run(world: World, seconds: float) -> None:
    end = world.time + seconds
    while world.time < end - 1e-9:
        world.step()


def drive(world: World, robot: str, v: float, w: float, seconds: float,
          settle: float = 1.0) -> None:
    """Command (v, w) for ``seconds``, then stop and let the robot come to rest."""
    world.set_cmd_vel(robot, v, w)
    run(world, seconds)
    world.set_cmd_vel(robot, 0.0, 0.0)
    run(world, settle)


def angle_diff(a: float, b: float) -> float:
    return math.atan2(math.sin(a - b), math.cos(a - b))


@pytest.fixture
def world():
    with World.from_yaml(CASE) as w:
        yield w


def test_case_study_layout(world):
    assert world.names == ["helper", "faulty"]
    assert world.cameras == ["helper"]
    assert world.pose("helper") == pytest.approx((0.0, 0.0, 0.0), abs=1e-3)
    assert world.pose("faulty") == pytest.approx((0.0, -1.5, 0.0), abs=1e-3)


def test_at_rest_the_robots_do_not_creep(world):
    before = world.pose("faulty")
    run(world, 2.0)
    assert world.pose("faulty") == pytest.approx(before, abs=1e-3)
    assert world.odometry("faulty") == pytest.approx((0, 0, 0, 0, 0), abs=1e-6)


def test_drive_straight_one_metre_pose_and_wheel_odometry_agree(world):
    x0, y0, _ = world.pose("faulty")
    # 0.2 m/s for 5 s: the ramps (0.2 s up, 0.2 s down at 1 m/s^2) lose and gain 2 cm.
    drive(world, "faulty", 0.2, 0.0, 5.0)
    x, y, yaw = world.pose("faulty")
    ox, oy, _oyaw, ov, ow = world.odometry("faulty")
    assert x - x0 == pytest.approx(1.0, abs=0.03)
    assert abs(y - y0) < 0.02 and abs(yaw) < math.radians(1)
    assert ox == pytest.approx(x - x0, abs=0.02)
    assert oy == pytest.approx(y - y0, abs=0.02)
    assert abs(ov) < 1e-3 and abs(ow) < 1e-3


def test_speed_and_acceleration_limits(world):
    world.set_cmd_vel("faulty", 5.0, 0.0)
    run(world, 0.1)
    assert world.velocity("faulty")[0] == pytest.approx(0.1, abs=0.02)   # 1 m/s^2
    run(world, 1.5)
    assert world.velocity("faulty")[0] == pytest.approx(kobuki.MAX_V, abs=0.02)


def test_turn_in_place_ninety_degrees(world):
    x0, y0, _ = world.pose("helper")
    drive(world, "helper", 0.0, 0.5, math.pi / 2 / 0.5)   # ramps lose what they gain
    x, y, yaw = world.pose("helper")
    assert math.degrees(yaw) == pytest.approx(90.0, abs=3.0)
    assert math.hypot(x - x0, y - y0) < 0.02
    assert math.degrees(angle_diff(world.odometry("helper")[2], yaw)) == pytest.approx(0, abs=2)


def test_stuck_left_wheel_curves_left_and_shows_in_odometry(world):
    world.set_wheel_fault("faulty", left=0.0)
    drive(world, "faulty", 0.2, 0.0, 2.0)
    _x, y, yaw = world.pose("faulty")
    assert yaw > math.radians(60)               # pivoting about the blocked left wheel
    assert y > -1.5 + 0.05                      # moved to its left (+y)
    _ox, oy, oyaw, _, _ = world.odometry("faulty")
    assert math.degrees(angle_diff(oyaw, yaw)) == pytest.approx(0, abs=5)
    assert oy > 0.05


def test_set_pose_teleports_and_keeps_odometry(world):
    world.set_pose("faulty", 1.0, 2.0, math.radians(30))
    run(world, 0.5)
    assert world.pose("faulty") == pytest.approx((1.0, 2.0, math.radians(30)), abs=2e-3)
    assert world.odometry("faulty")[:3] == pytest.approx((0, 0, 0), abs=1e-3)


def _masks(rgb: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    r, g, b = (rgb[:, :, i].astype(int) for i in range(3))
    green = (g > r + 50) & (g > b + 40)
    orange = (r > 150) & (r > g + 60) & (r > b + 120)
    return green, orange


def test_kinect_sees_the_cylinders_at_the_expected_columns_and_depths(world):
    # Faulty 1.5 m ahead of Helper, facing it: its left (green) is on the image's right.
    world.set_pose("faulty", 1.5, 0.0, math.pi)
    rgb, xyz = world.render_kinect("helper")
    assert rgb.shape == (480, 640, 3) and rgb.dtype == np.uint8
    assert xyz.shape == (480, 640, 3) and xyz.dtype == np.float32
    intr = world.intrinsics
    assert intr.fx == pytest.approx(589.4, abs=0.1)
    assert intr.vfov_deg == pytest.approx(44.31, abs=0.01)
    distance = 1.5 - kobuki.KINECT_OPTICAL[0]
    offset = intr.fx * kobuki.CYLINDER_Y / distance
    green, orange = _masks(rgb)
    assert green.sum() > 300 and orange.sum() > 300
    assert np.nonzero(green)[1].mean() == pytest.approx(intr.cx + offset, abs=3)
    assert np.nonzero(orange)[1].mean() == pytest.approx(intr.cx - offset, abs=3)
    assert np.nanmedian(xyz[green][:, 2]) == pytest.approx(distance - 0.02, abs=0.03)
    assert np.nanmedian(xyz[orange][:, 0]) == pytest.approx(-kobuki.CYLINDER_Y, abs=0.02)
    # orange is taller: its top is higher in the image (smaller row)
    assert np.nonzero(orange)[0].min() < np.nonzero(green)[0].min() - 20


def test_kinect_flank_view_depth_at_the_centre_and_far_cylinder_visible(world):
    # The case study: Helper turned right towards Faulty's left flank.
    world.set_pose("helper", 0.0, 0.0, -math.pi / 2)
    rgb, xyz = world.render_kinect("helper")
    near = 1.5 - kobuki.CYLINDER_Y - kobuki.CYLINDER_RADIUS - kobuki.KINECT_OPTICAL[0]
    assert xyz[240, 320, 2] == pytest.approx(near, abs=0.03)
    green, orange = _masks(rgb)
    assert green.sum() > 300
    assert orange.sum() > 100                      # the far one shows above the near one
    assert np.nonzero(orange)[0].max() < np.nonzero(green)[0].min() + 3


def test_kinect_range_and_no_depth_is_nan(world):
    _, xyz = world.render_kinect("helper")   # facing the wall 4.86 m away: beyond 4.5 m
    z = xyz[:, :, 2]
    assert np.isnan(z[200, 320])
    valid = z[~np.isnan(z)]
    assert valid.min() >= 0.5 and valid.max() <= 4.5
    assert np.isnan(xyz[200, 320]).all()


def test_sense_geometry_on_a_synthetic_depth_image():
    intr = kinect.Intrinsics()
    noise = kinect.NoiseModel(a=0, b=0, quantize=False, color_noise=0)
    z_true = 2.0
    z = np.full((480, 640), z_true, dtype=np.float32)
    z[:10] = np.inf                                    # nothing there
    z[10:20] = 5.0                                     # beyond the range
    _rgb, xyz = kinect.sense(np.zeros((480, 640, 3), np.uint8), z, intr, noise,
                             np.random.default_rng(0))
    assert np.isnan(xyz[:20]).all()
    assert xyz[300, 600] == pytest.approx(
        [(600 - intr.cx) * z_true / intr.fx, (300 - intr.cy) * z_true / intr.fy, z_true],
        rel=1e-4)
    buffer = np.array([(kinect.FAR - kinect.FAR * kinect.NEAR / z_true)
                       / (kinect.FAR - kinect.NEAR), 1.0], dtype=np.float32)
    assert kinect.linear_depth(buffer) == pytest.approx([z_true, np.inf], rel=1e-4)


def test_depth_noise_grows_with_distance():
    noise = kinect.NoiseModel()
    assert noise.sigma(np.array(1.0)) == pytest.approx(0.0012 + 0.0019 * 0.36)
    assert noise.sigma(np.array(4.0)) > 10 * noise.sigma(np.array(1.0))


def test_cloud_packing_round_trip():
    rng = np.random.default_rng(1)
    rgb = rng.integers(0, 256, (4, 5, 3), dtype=np.uint8)
    xyz = rng.normal(size=(4, 5, 3)).astype(np.float32)
    packed = pack_cloud(xyz, rgb)
    assert packed.dtype == np.float32 and packed.shape == (4, 5, 4)
    assert np.array_equal(packed[:, :, :3], xyz)
    assert np.array_equal(unpack_rgb(packed[:, :, 3]), rgb)
    assert packed[0, 0, 3].view(np.uint32) == (int(rgb[0, 0, 0]) << 16 | int(rgb[0, 0, 1]) << 8
                                              | int(rgb[0, 0, 2]))


def test_same_seed_same_world_and_frames():
    def scene(seed: int) -> tuple[dict, tuple, np.ndarray, np.ndarray]:
        with World.from_yaml(CASE, seed=seed) as w:
            drive(w, "faulty", 0.3, 0.2, 1.0, settle=0.2)
            rgb, xyz = w.render_kinect("helper")
            return w.config, w.pose("faulty"), rgb, xyz

    a, b, c = scene(7), scene(7), scene(8)
    assert a[0] == b[0] and a[1] == b[1]
    assert np.array_equal(a[2], b[2]) and np.array_equal(a[3], b[3], equal_nan=True)
    assert a[0]["robots"] != c[0]["robots"] and a[0]["lighting"] != c[0]["lighting"]


def test_randomisation_stays_within_its_bounds():
    base = config.resolve(CASE)
    for seed in range(5):
        cfg = config.resolve(CASE, seed=seed)
        for r0, r in zip(base["robots"], cfg["robots"], strict=True):
            assert abs(r["x"] - r0["x"]) <= 0.02 and abs(r["y"] - r0["y"]) <= 0.02
            assert abs(r["yaw"] - r0["yaw"]) <= 2.0
        for key in ("green", "orange"):
            assert np.abs(np.subtract(cfg["cylinders"][key], base["cylinders"][key])).max() <= 0.04


def test_world_from_a_dict_with_distractors():
    cfg = {"robots": [{"name": "h", "kind": "helper"}],
           "objects": [{"shape": "box", "size": [0.3, 0.3, 0.8], "color": [0.1, 0.7, 0.2],
                        "x": 2.0, "y": 0.0},
                       {"shape": "cylinder", "radius": 0.1, "height": 0.5,
                        "color": [0.2, 0.2, 0.9], "x": 2.0, "y": 1.0}]}
    with World.from_yaml(cfg) as w:
        rgb, xyz = w.render_kinect("h")
        green, _ = _masks(rgb)
        assert green.sum() > 1000                      # the distractor box is green
        assert np.nanmedian(xyz[green][:, 2]) == pytest.approx(2.0 - 0.15 - 0.135, abs=0.05)
    with pytest.raises(ValueError):
        World.from_yaml({"robots": [{"name": "a", "kind": "tank"}]})
