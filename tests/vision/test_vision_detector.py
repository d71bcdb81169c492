"""The cylinder detector on synthetic frames drawn with numpy (no simulator, no ROS)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from rason_vision.convert import cloud_fields, cloud_to_xyz, image_fields, image_to_rgb
from rason_vision.detector import DetectorConfig, detect
from rason_vision.geometry import (
    Intrinsics,
    cylinder_axes_in_camera,
    format_literal,
    format_partial_literal,
    relative_from_axes,
    thesis_angle_deg,
)
from rason_vision_tools.synthetic import Cylinder, Scene, faulty_scene, world_scene
from turtlebot_model.geometry import wrap_deg


def truth_of(scene: Scene):
    green, orange = scene.cylinders[1], scene.cylinders[2]
    return relative_from_axes((green.x, green.z), (orange.x, orange.z))


def angle_diff(a: float, b: float) -> float:
    return abs(wrap_deg(a - b))


@pytest.mark.parametrize("distance,bearing,heading", [
    (0.8, 0, 0), (0.8, -12, 60), (1.5, 0, -90), (1.5, 20, 180), (2.0, -20, -45),
    (2.5, 5, 135), (3.0, 15, -150), (3.5, -20, 30), (3.5, 0, -90), (1.2, 24, -120)])
def test_measures_angle_depth_yaw(distance, bearing, heading):
    scene = faulty_scene(distance, bearing, heading)
    rgb, xyz = scene.render(np.random.default_rng(1))
    det = detect(rgb, xyz).detection
    truth = truth_of(scene)
    assert det is not None
    assert abs(det.angle - truth.angle) < 0.5
    assert abs(det.depth - truth.depth) < 0.02
    assert angle_diff(det.yaw, truth.yaw) < 5.0
    assert 0.22 <= det.spacing <= 0.25
    assert all(math.isfinite(v) for v in (det.angle, det.depth, det.yaw, det.depth_thesis))


def test_pinhole_angle_is_exact_and_thesis_angle_is_linear():
    k = Intrinsics.from_fov()
    assert k.fx == pytest.approx(589.4, abs=0.1)
    # Both agree at the centre and at the image edges; in between the linear map is off by ~1 deg.
    assert thesis_angle_deg(320, 640) == 0.0
    assert thesis_angle_deg(640, 640) == pytest.approx(28.5)
    assert math.degrees(math.atan(320 / k.fx)) == pytest.approx(28.5, abs=0.01)
    assert k.pinhole_angle_deg(k.cx + 160) - thesis_angle_deg(k.cx + 160, 640) == \
        pytest.approx(0.94, abs=0.05)


def test_no_robot_gives_no_detection():
    rgb, xyz = Scene().render()
    assert detect(rgb, xyz).detection is None


def test_distractors_far_from_the_right_spacing_are_ignored():
    scene = faulty_scene(2.0, 5, -30)
    truth = truth_of(scene)
    scene.cylinders += [Cylinder(-0.6, 1.6, 0.04, 0.0, 0.5, (240, 120, 20)),
                        Cylinder(0.9, 2.6, 0.05, 0.0, 0.7, (40, 170, 60)),
                        Cylinder(-0.2, 3.0, 0.05, 0.0, 0.3, (240, 120, 20))]
    result = detect(*scene.render())
    assert len(result.blobs["orange"]) >= 2 and len(result.blobs["green"]) >= 2
    assert result.detection is not None
    assert abs(result.detection.angle - truth.angle) < 0.5
    assert abs(result.detection.depth - truth.depth) < 0.02


def test_distractor_pair_alone_at_wrong_spacing_is_not_a_robot():
    scene = Scene(cylinders=[Cylinder(0.0, 2.0, 0.03, 0.0, 0.5, (40, 170, 60)),
                             Cylinder(0.4, 2.0, 0.03, 0.0, 0.6, (240, 120, 20))])
    assert detect(*scene.render()).detection is None


def test_shadowed_cylinder_is_out_of_colour_range():
    scene = faulty_scene(1.5, 0, 10)
    scene.cylinders[2] = Cylinder(scene.cylinders[2].x, scene.cylinders[2].z, 0.03, 0.4, 0.6,
                                  (45, 25, 10))
    result = detect(*scene.render())
    assert result.blobs["orange"] == [] and result.detection is None


def test_right_flank_hides_green_behind_orange():
    """Seen from Faulty's right the tall orange cylinder hides the short green one (7.3)."""
    result = detect(*faulty_scene(1.5, 0, 90).render())
    assert result.blobs["green"] == [] and result.detection is None


@pytest.mark.parametrize("distance,bearing", [(0.8, 0.0), (1.5, 12.0), (2.5, -15.0), (3.8, 5.0)])
def test_right_flank_is_a_partial_sighting_of_the_orange_cylinder(distance, bearing):
    """Self-occlusion: no pair, but the one cylinder seen is reported with its bearing and depth
    (Faulty's heading unknown), so Helper knows Faulty is there."""
    scene = faulty_scene(distance, bearing, 90 + bearing)  # flank along the line of sight
    result = detect(*scene.render(np.random.default_rng(2)))
    assert result.detection is None and result.partial is not None
    orange = scene.cylinders[2]
    assert result.partial.colour == "orange"
    assert abs(result.partial.angle - math.degrees(math.atan2(orange.x, orange.z))) < 1.0
    assert abs(result.partial.depth - orange.z) < 0.04


def test_no_partial_when_the_pair_is_seen():
    result = detect(*faulty_scene(1.5, 0, -90).render())
    assert result.detection is not None and result.partial is None


def test_one_green_cylinder_alone_is_a_partial_sighting():
    scene = faulty_scene(2.0, -8, 30)
    scene.cylinders.pop(2)                      # the orange one is gone (e.g. lost to lighting)
    result = detect(*scene.render())
    assert result.detection is None and result.partial is not None
    assert result.partial.colour == "green"


@pytest.mark.parametrize("cylinder", [
    Cylinder(0.1, 2.0, 0.03, 0.0, 0.12, (240, 120, 20)),    # on the floor: below Faulty's plate
    Cylinder(0.1, 2.0, 0.03, 1.0, 1.4, (240, 120, 20)),     # far above the camera
    Cylinder(0.1, 2.0, 0.20, 0.40, 0.60, (240, 120, 20)),   # far too wide for a cylinder
])
def test_objects_unlike_a_cylinder_are_no_partial_sighting(cylinder):
    result = detect(*Scene(cylinders=[cylinder]).render())
    assert result.blobs["orange"], "the object is seen"
    assert result.detection is None and result.partial is None


def test_partial_literal_format():
    assert format_partial_literal("faulty", -3.21, 1.5, "orange") == \
        "robot_partial(faulty,-3.2,1.50,orange)"
    assert format_partial_literal("faulty", -0.04, 2.0, "green") == \
        "robot_partial(faulty,0.0,2.00,green)"


def test_left_flank_far_orange_shows_above_near_green():
    """The case study's view: Faulty's left flank; the far orange shows above the green."""
    scene = faulty_scene(1.5, 0, -90)
    result = detect(*scene.render())
    det = result.detection
    assert det is not None
    assert det.orange.v < det.green.v  # orange centroid higher in the image
    assert angle_diff(det.yaw, -90.0) < 4.0


def test_nan_depth_at_the_centroid_uses_the_blobs_valid_points():
    scene = faulty_scene(1.5, 0, 0)
    rgb, xyz = scene.render()
    first = detect(rgb, xyz).detection
    assert first is not None
    u, v = round(first.green.u), round(first.green.v)
    xyz[v - 5:v + 6, u - 4:u + 5] = np.nan
    det = detect(rgb, xyz).detection
    assert det is not None
    assert all(math.isfinite(x) for x in (det.angle, det.depth, det.yaw, det.depth_thesis))
    assert abs(det.depth - first.depth) < 0.01


def test_no_depth_on_a_blob_drops_the_detection():
    scene = faulty_scene(1.5, 0, 0)
    rgb, xyz = scene.render()
    det = detect(rgb, xyz).detection
    x0, y0, w, h = det.green.bbox
    xyz[y0:y0 + h, x0:x0 + w] = np.nan
    assert detect(rgb, xyz).detection is None


def test_partially_out_of_frame_pair_is_still_paired():
    scene = faulty_scene(1.2, 24.0, 0)
    result = detect(*scene.render())
    assert result.detection is not None
    assert abs(result.detection.depth - truth_of(scene).depth) < 0.03


def test_bgr_input_with_bgr_config():
    rgb, xyz = faulty_scene(2.0, 3, 20).render()
    assert detect(rgb[..., ::-1].copy(), xyz, DetectorConfig(bgr=True)).detection is not None
    assert detect(rgb[..., ::-1].copy(), xyz).detection is None


def test_literal_format():
    assert format_literal("faulty", -3.2449, 1.5051, -88.04) == "robot(faulty,-3.2,1.51,-88.0)"
    assert format_literal("faulty", -0.04, 1.0, -0.01) == "robot(faulty,0.0,1.00,0.0)"


# -- the yaw sign convention against Faulty's rule Yaw1 - (Yaw + (Deg1 - Deg)) -----------------

HELPER = (0.0, 0.0, -math.pi / 2)  # case study: Helper turned right to face Faulty
STARTS = [(0.0, -1.5, 0.0), (0.4, -1.6, 0.3), (-0.3, -2.2, -0.5), (0.2, -1.1, 2.5)]


def arc(pose: tuple[float, float, float], length: float, turn_deg: float):
    """Faulty's pose after driving an arc of ``length`` m turning ``turn_deg`` (+ = left)."""
    x, y, th = pose
    turn = math.radians(turn_deg)
    if abs(turn) < 1e-12:
        return (x + length * math.cos(th), y + length * math.sin(th), th)
    r = length / turn
    return (x + r * (math.sin(th + turn) - math.sin(th)),
            y - r * (math.cos(th + turn) - math.cos(th)), th + turn)


def rule(before, after) -> float:
    """Faulty's diagnosis expression: > 8 right actuator, < -8 left actuator."""
    return wrap_deg(after.yaw - (before.yaw + (after.angle - before.angle)))


def true_relative(faulty):
    return relative_from_axes(*cylinder_axes_in_camera(*HELPER, *faulty))


@pytest.mark.parametrize("start", STARTS)
def test_rule_on_true_poses(start):
    before = true_relative(start)
    assert rule(before, true_relative(arc(start, 0.3, 0.0))) == pytest.approx(0.0, abs=1e-9)
    # A curve to Faulty's right (clockwise) is a right-actuator fault: rule > 8.
    assert rule(before, true_relative(arc(start, 0.3, -20.0))) == pytest.approx(20.0)
    assert rule(before, true_relative(arc(start, 0.3, +20.0))) == pytest.approx(-20.0)


@pytest.mark.parametrize("start", STARTS[:3])
def test_rule_on_detected_frames(start):
    def seen(pose):
        det = detect(*world_scene(HELPER, pose).render(np.random.default_rng(7))).detection
        assert det is not None
        return det

    before = seen(start)
    assert abs(rule(before, seen(arc(start, 0.3, 0.0)))) < 4.0
    assert rule(before, seen(arc(start, 0.3, -20.0))) > 8.0
    assert rule(before, seen(arc(start, 0.3, +20.0))) < -8.0


def test_case_study_view_is_the_left_flank():
    truth = true_relative((0.0, -1.5, 0.0))
    assert truth.angle == pytest.approx(0.0, abs=1e-9)
    assert truth.depth == pytest.approx(1.5)
    assert truth.yaw == pytest.approx(-90.0)


# -- message conversion ----------------------------------------------------------------------

def test_image_and_cloud_round_trip_through_message_fields():
    rgb, xyz = faulty_scene(2.0, 0, 0).render()
    img = SimpleNamespace(**image_fields(rgb))
    img.data = img.data.tobytes()  # rospy gives bytes
    assert np.array_equal(image_to_rgb(img), rgb)
    values = cloud_fields(xyz, rgb)
    values["fields"] = [SimpleNamespace(name=n, offset=o, datatype=d, count=c)
                        for n, o, d, c in values["fields"]]
    cloud = SimpleNamespace(**values)
    cloud.data = cloud.data.tobytes()
    assert np.array_equal(cloud_to_xyz(cloud), xyz, equal_nan=True)
    bgr = SimpleNamespace(**image_fields(rgb))
    bgr.encoding, bgr.data = "bgr8", rgb[..., ::-1].tobytes()
    assert np.array_equal(image_to_rgb(bgr), rgb)
