"""The detector on the committed bag's frames, read offline with rosbags, against ground truth."""

from __future__ import annotations

import math

import pytest
from vision_truth import CASES_BAG, COMPRESSED_BAG, KINECT_BAG, SWEEP_BAG, check

from rason_vision.detector import detect
from rason_vision_tools.bagio import read_bag

pytestmark = pytest.mark.slow          # reads every frame of the committed bags


@pytest.fixture(scope="module")
def frames():
    for bag in (SWEEP_BAG, CASES_BAG):
        assert bag.exists(), "record: rosrun rason_vision_tools record_bags --committed --out bags"
    return [*read_bag(SWEEP_BAG), *read_bag(CASES_BAG)]


def test_committed_bag_covers_every_case(frames):
    truths = [f.truth for f in frames]
    assert {t["case"] for t in truths} >= {"sweep", "flank", "distractors", "off_colour",
                                            "partly_out", "no_robot", "case_study",
                                            "self_occlusion"}
    headings = sorted(t["heading"] for t in truths if t["faulty"])
    bins = {round(h / 15.0) % 24 for h in headings}
    assert bins == set(range(24)), "Faulty's heading all round in 15 deg steps"
    distances = [t["distance"] for t in truths if t["faulty"]]
    assert min(distances) <= 0.8 and max(distances) >= 3.5
    angles = [t["angle"] for t in truths if t["faulty"]]
    assert min(angles) < -20 and max(angles) > 20
    # the self-occlusion case (green hidden behind orange) and the case study's flank view
    assert any(t["green_px"] == 0 and t["orange_px"] > 0 for t in truths)
    assert any(abs(t["yaw"] + 90) < 5 for t in truths if t["faulty"] and t["expect"] == "robot")
    assert any(t["expect"] == "none" and not t["faulty"] for t in truths)


def test_detector_agrees_with_ground_truth(frames):
    problems = []
    for frame in frames:
        det = detect(frame.rgb, frame.xyz).detection
        found = None if det is None else (det.angle, det.depth, det.yaw)
        if found is not None:
            assert all(math.isfinite(v) for v in found)
        problem = check(found, frame.truth)
        if problem:
            problems.append(f"frame {frame.truth['index']} ({frame.truth['case']}): {problem}")
    assert sum(f.truth["expect"] == "robot" for f in frames) >= 25
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("bag", [KINECT_BAG, COMPRESSED_BAG], ids=["kinect", "compressed"])
def test_kinect_and_compressed_bags_give_the_raw_detections(bag):
    """The cases in a Kinect driver's form and compressed: ROS 1's rosbag reads them, the
    depth is stamped 0.055 s before the colour, and the detector agrees with the truth."""
    import rosbag

    with rosbag.Bag(str(bag)) as ros1:
        messages = list(ros1.read_messages())
    first = messages[0][2]     # one frame's messages share a bag time
    stamps = {topic: msg.header.stamp.to_sec() for topic, msg, t in messages
              if t == first and hasattr(msg, "header")}
    colour = next(v for k, v in stamps.items() if k.startswith("/helper/camera/rgb/image_raw"))
    depth = next(v for k, v in stamps.items() if "depth_registered/image_raw" in k)
    assert colour - depth == pytest.approx(0.055, abs=1e-6)
    if bag == KINECT_BAG:
        assert {m.encoding for t, m, _ in messages if t.endswith("image_raw")} == \
            {"bayer_grbg8", "16UC1"}
    problems = []
    for frame in read_bag(bag):
        det = detect(frame.rgb, frame.xyz).detection
        problem = check(None if det is None else (det.angle, det.depth, det.yaw), frame.truth)
        if problem:
            problems.append(f"frame {frame.truth['index']}: {problem}")
    assert not problems, "\n".join(problems)
