"""Light, shadow, blur: the camera effects of a world (off by default), the render workers
applying them, and the shipped harsh world with its calibrated colours."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest

from rason_diagnosis.paths import world_file
from rason_vision.colours import load_colours
from rason_vision.detector import DetectorConfig, detect
from rason_vision_tools.scenarios import committed_cases, render
from turtlebot_sim.camera_effects import CameraEffects, expose
from turtlebot_sim.config import DEFAULTS, load, resolve
from turtlebot_sim.render import RenderPool


def test_effects_are_off_by_default():
    camera = resolve({"robots": []})["camera"]
    assert camera["exposure_s"] == 0.0 and camera["auto_exposure"] is False
    assert not CameraEffects.from_config(camera).active
    assert not CameraEffects.from_config({}).active


def test_motion_blur_slides_by_the_turn_over_the_exposure():
    effects = CameraEffects(exposure_s=0.03)
    # Helper's search sweep: 120 deg/s; a Kinect's fx 525
    assert effects.blur_pixels(math.radians(120.0), 525.0) == 33
    rgb = np.zeros((10, 100, 3), np.uint8)
    rgb[:, 50:] = 200
    blurred = effects.apply(rgb, math.radians(120.0), 525.0)
    ramp = blurred[5, :, 0].astype(int)
    assert ramp[30] == 0 and ramp[70] == 200
    assert 0 < ramp[50] < 200 and np.all(np.diff(ramp) >= 0)      # a ramp across the edge
    assert np.array_equal(effects.apply(rgb, 0.0, 525.0), rgb)      # a still camera: sharp


def test_auto_exposure_brings_the_mean_luma_to_its_target():
    dark = np.full((20, 20, 3), 30, np.uint8)
    out = expose(dark, 110.0, 4.0)
    assert out.mean() == pytest.approx(110, abs=2)
    assert expose(np.full((4, 4, 3), 5, np.uint8), 110.0, 4.0).max() == 20   # gain capped at 4


def test_render_workers_blur_a_turning_camera():
    cfg = resolve({"robots": [{"name": "helper", "kind": "helper"},
                              {"name": "faulty", "kind": "faulty", "x": 1.5}]})
    blurred_cfg = copy.deepcopy(cfg)
    blurred_cfg["camera"]["exposure_s"] = 0.03
    frames = {}
    for name, config in (("sharp", cfg), ("blurred", blurred_cfg)):
        with RenderPool(config, workers=1) as pool:
            out = []
            for stamp, yaw in ((0.0, 0.0), (0.1, math.radians(12.0))):   # 120 deg/s
                quat = (0.0, 0.0, math.sin(yaw / 2), math.cos(yaw / 2))
                states = {"helper": ((0.0, 0.0, 0.0), quat),
                          "faulty": ((1.5, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))}
                pool.submit(stamp, "helper", states)
                out += pool.collect(block=True)
            frames[name] = out
    first_sharp, turned_sharp = (f.rgb.astype(int) for f in frames["sharp"])
    first_blurred, turned_blurred = (f.rgb.astype(int) for f in frames["blurred"])
    # the first frame has no turn rate yet; the second was taken turning at 120 deg/s
    assert np.abs(first_blurred - first_sharp).mean() < 1.0
    sharpness = [np.abs(np.diff(img, axis=1)).mean() for img in (turned_sharp, turned_blurred)]
    assert sharpness[1] < 0.6 * sharpness[0], sharpness


def test_the_harsh_world_loads_and_casts_shadows():
    harsh = load(world_file("harsh"))
    cfg = resolve(harsh)
    assert cfg["lighting"]["shadow"] is True and cfg["camera"]["exposure_s"] > 0
    assert cfg["camera"]["auto_exposure"] is True and cfg["camera"]["edge_dropout"] > 0
    assert set(DEFAULTS["camera"]) == set(cfg["camera"])      # only known keys


def test_the_harsh_case_study_frame_is_detected_with_the_calibrated_colours():
    harsh = load(world_file("harsh"))
    ranges = load_colours(world_file("harsh").with_name("harsh_colours.yaml"))
    config = DetectorConfig(green=ranges["green"], orange=ranges["orange"])
    scenario = committed_cases()[1]             # Faulty centred, its left flank: yaw -90
    rgb, xyz, truth = render(scenario, harsh)
    det = detect(rgb, xyz, config).detection
    assert det is not None
    assert abs(det.angle - truth["angle"]) < 1.0 and abs(det.depth - truth["depth"]) < 0.03
    assert abs(det.yaw - truth["yaw"]) < 8.0
