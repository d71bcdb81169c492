"""``rosrun rason_vision_tools record_bags`` writes bags Debian's ``rosbag`` reads, with ground truth."""

from __future__ import annotations

import subprocess

import pytest

from rason_vision_tools.bagio import read_bag


# bz2 (about 10-30 s of CPU for three frames) is left out of ./run.sh test --fast; lz4 stays in
@pytest.mark.parametrize("compression", [pytest.param("bz2", marks=pytest.mark.slow), "lz4"])
def test_record_bags_cli_writes_readable_bags(tmp_path, compression):
    out = tmp_path / "bags"
    done = subprocess.run(
        ["rosrun", "rason_vision_tools", "record_bags", "--seed", "4", "--out", str(out),
         "--frames", "3", "--compression", compression],
        capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    bag = out / "vision_seed4.bag"
    info = subprocess.run(["rosbag", "info", str(bag)], capture_output=True, text=True,
                          timeout=60)
    assert info.returncode == 0, info.stderr
    assert compression in info.stdout
    for topic in ("/helper/camera/rgb/image_raw", "/helper/camera/depth_registered/points",
                  "/ground_truth/faulty_relative"):
        assert topic in info.stdout
    assert "3 msgs" in info.stdout
    # ROS 1's own reader decompresses every chunk (rosbags' raw LZ4 chunks would fail here).
    import rosbag

    with rosbag.Bag(str(bag)) as ros1:
        topics = [topic for topic, _msg, _t in ros1.read_messages()]
    assert len(topics) == 9
    frames = list(read_bag(bag))
    assert [f.truth["index"] for f in frames] == [0, 1, 2]
    assert frames[0].rgb.shape == (480, 640, 3) and frames[0].xyz.shape == (480, 640, 3)
    assert frames[1].stamp_ns - frames[0].stamp_ns == 250_000_000
    assert {"angle", "depth", "yaw", "heading", "expect", "green_px"} <= frames[0].truth.keys()
