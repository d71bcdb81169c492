"""``rosrun rason_vision calibrate``: colour ranges fitted from named pixels of recorded frames
make the detector see cylinders whose colours the default ranges miss (a real robot's)."""

from __future__ import annotations

import dataclasses
import subprocess
import threading

import cv2
import numpy as np
import pytest
from polling import wait_until
from vision_truth import LITERAL

from rason_vision.colours import Region, fit_range, load_colours, save_colours, to_hsv
from rason_vision.detector import DetectorConfig, HsvRange, detect
from rason_vision.geometry import KINECT_VGA, relative_from_axes
from rason_vision_tools.bagio import Form, Frame, read_bag, write_bag
from rason_vision_tools.synthetic import faulty_scene

#: Cylinder colours the default ranges miss: a red orange (hue ~1, across the hue wrap) and a
#: blue-ish green (hue ~86).
GREEN_RGB, ORANGE_RGB = (30, 140, 125), (215, 45, 40)
#: Faulty's poses of the recorded frames: (distance, bearing, heading).
POSES = [(1.6, 4.0, -70.0), (2.2, -10.0, 40.0), (1.2, 12.0, -120.0), (2.8, 0.0, 160.0)]


def scene_of(distance: float, bearing: float, heading: float):
    scene = faulty_scene(distance, bearing, heading, intrinsics=KINECT_VGA)
    scene.cylinders[1] = dataclasses.replace(scene.cylinders[1], rgb=GREEN_RGB)
    scene.cylinders[2] = dataclasses.replace(scene.cylinders[2], rgb=ORANGE_RGB)
    return scene


def truth_of(scene) -> dict:
    green, orange = scene.cylinders[1], scene.cylinders[2]
    rel = relative_from_axes((green.x, green.z), (orange.x, orange.z))
    return {"angle": rel.angle, "depth": rel.depth, "yaw": rel.yaw}


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    """A Kinect-form bag (Bayer + 16UC1 + camera_info) of the off-colour frames, and the
    labels image of its first frame."""
    folder = tmp_path_factory.mktemp("calibration")
    scenes = [scene_of(*pose) for pose in POSES]
    frames = []
    for index, scene in enumerate(scenes):
        rgb, xyz = scene.render(np.random.default_rng(index))
        frames.append(Frame(10**18 + index * 250_000_000, rgb, xyz, truth_of(scene)))
    bag = folder / "off_colour_kinect.bag"
    write_bag(bag, frames, form=Form.KINECT)
    # the first pose alone, four frames, for a live calibration with the first pose's labels
    still = [Frame(10**18 + i * 250_000_000, *scenes[0].render(np.random.default_rng(10 + i)),
                   truth_of(scenes[0])) for i in range(4)]
    write_bag(folder / "first_pose_kinect.bag", still, form=Form.KINECT)
    labels = folder / "labels.png"
    cv2.imwrite(str(labels), np.clip(scenes[0].labels(), 0, 255).astype(np.uint8))
    return folder, bag, labels, scenes


def test_fit_range_finds_a_hue_across_the_wrap_and_ignores_background():
    rgb, _ = scene_of(*POSES[0]).render(np.random.default_rng(0))
    labels = scene_of(*POSES[0]).labels()
    hsv = to_hsv(rgb)
    orange = fit_range(hsv[labels == 2])
    assert orange.lower[0] > orange.upper[0], orange        # wraps past 0
    # a loose box around the cylinder (floor and wall around it) gives nearly the same range
    ys, xs = np.nonzero(labels == 2)
    box = Region(int(xs.min()) - 4, int(ys.min()) - 4, int(np.ptp(xs)) + 9, int(np.ptp(ys)) + 9)
    loose = fit_range(hsv[box.mask(labels.shape)])
    assert abs(int(loose.lower[0]) - int(orange.lower[0])) <= 3
    with pytest.raises(ValueError, match="coloured pixels"):
        fit_range(np.zeros((100, 3), np.uint8))
    assert Region.parse("100,50") == Region(97, 47, 7, 7)
    with pytest.raises(ValueError, match="outside"):
        Region(700, 10, 5, 5).mask((480, 640))


def test_colours_file_round_trip_and_errors(tmp_path):
    ranges = {"green": HsvRange((80, 134, 42), (92, 255, 255)),
              "orange": HsvRange((175, 142, 59), (6, 255, 255))}
    path = tmp_path / "colours.yaml"
    save_colours(path, ranges, "a note")
    assert path.read_text().startswith("# a note\n")
    assert load_colours(path) == ranges
    path.write_text("green: {lower: [80, 134, 42], upper: [92, 255, 300]}\norange: {}\n")
    with pytest.raises(ValueError, match=r"green\.upper"):
        load_colours(path)


def test_calibrate_on_a_recorded_bag_makes_the_detector_see_the_cylinders(recorded):
    folder, bag, labels, scenes = recorded
    frames = list(read_bag(bag))
    default = DetectorConfig(intrinsics=KINECT_VGA)
    assert all(detect(f.rgb, f.xyz, default).detection is None for f in frames)

    snapshot = folder / "frame.png"
    done = subprocess.run(["rosrun", "rason_vision", "calibrate", f"_bag:={bag}",
                           f"_snapshot:={snapshot}"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert cv2.imread(str(snapshot)).shape == (480, 640, 3)     # the frame to read pixels from
    out = folder / "from_labels.yaml"
    done = subprocess.run(["rosrun", "rason_vision", "calibrate", f"_bag:={bag}",
                           f"_labels:={labels}", f"_out:={out}"],
                          capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "of the named pixels inside" in done.stdout
    # the regions way: boxes around each cylinder of the first frame, over one frame
    boxes = {}
    for index, name in ((1, "green"), (2, "orange")):
        ys, xs = np.nonzero(scenes[0].labels() == index)
        boxes[name] = f"{xs.min()},{ys.min()},{np.ptp(xs) + 1},{np.ptp(ys) + 1}"
    out_regions = folder / "from_regions.yaml"
    done = subprocess.run(["rosrun", "rason_vision", "calibrate", f"_bag:={bag}",
                           f"_green:={boxes['green']}", f"_orange:={boxes['orange']}",
                           f"_out:={out_regions}"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr

    for path in (out, out_regions):
        ranges = load_colours(path)
        config = DetectorConfig(green=ranges["green"], orange=ranges["orange"],
                                intrinsics=KINECT_VGA)
        for frame in frames:
            det = detect(frame.rgb, frame.xyz, config).detection
            assert det is not None, (path.name, frame.truth)
            assert abs(det.angle - frame.truth["angle"]) < 1.0
            assert abs(det.depth - frame.truth["depth"]) < 0.03


def test_calibrate_refuses_bad_parameters(recorded):
    folder, bag, _, _ = recorded
    done = subprocess.run(["rosrun", "rason_vision", "calibrate", f"_bag:={bag}",
                           f"_out:={folder / 'x.yaml'}"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and "name where the green cylinder is" in done.stderr
    done = subprocess.run(["rosrun", "rason_vision", "calibrate", f"_bag:={bag}",
                           "_green:=5,5,4,4", "_orange:=600,400,4,4",
                           f"_out:={folder / 'x.yaml'}"], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 2 and "coloured pixels" in done.stderr


def test_calibrate_names_a_misspelt_parameter(tmp_path):
    # a bag that does not exist: the run stops at once, after the warning
    done = subprocess.run(["rosrun", "rason_vision", "calibrate", f"_bag:={tmp_path / 'no.bag'}",
                           "_ouut:=colours.yaml"], capture_output=True, text=True, timeout=120)
    assert done.returncode == 2, done.stderr
    assert "unknown private parameter ~ouut (ignored); did you mean ~out?" in done.stderr


@pytest.mark.ros
def test_live_calibration_then_the_synthesizer_with_the_file(ros, recorded):
    """Calibrate on the live topic while ``rosbag play`` replays the bag, then run the
    synthesizer with ``_colours:=`` on the same replay: robot(...) for every frame."""
    import rospy
    from jason_msgs.msg import Perception

    folder, bag, labels, _ = recorded
    out = folder / "live.yaml"
    play = ros.run(["rosbag", "play", "--quiet", "--loop", str(folder / "first_pose_kinect.bag")],
                   label="rosbag_play")
    calib = ros.rosrun("rason_vision", "calibrate", ns="/helper",
                       params={"labels": str(labels), "out": str(out), "frames": 2})
    assert calib.wait(60) == 0, calib.output()
    assert out.exists()
    play.stop()

    ros.init_rospy()
    got: list[list[str]] = []
    lock = threading.Lock()

    def on_perception(msg: Perception) -> None:
        with lock:
            got.append(list(msg.perception))

    sub = rospy.Subscriber("/helper/jason/perception", Perception, on_perception)
    try:
        # a node name of its own: its private ~colours stays on the parameter server after
        # the test, and must not reach other tests' /helper/robot_synthesizer
        node = ros.rosrun("rason_vision", "robot_synthesizer", ns="/helper",
                          name="calibrated_synthesizer",
                          params={"colours": str(out), "depth_input": "image",
                                  "colour_transport": "raw"})
        ros.wait_for_subscriber("/helper/camera/depth_registered/image_raw", watch=[node])
        ros.wait_for_topic("/helper/jason/perception", watch=[node])
        wait_until(lambda: sub.get_num_connections() > 0, "our subscriber's connection to the "
                   "node's perceptions", timeout=20, watch=[node], period=0.05)
        replay = ros.run(["rosbag", "play", "--quiet", "--keep-alive", str(bag)],
                         label="rosbag_replay")
        def all_poses() -> bool:
            with lock:
                return len(got) >= len(POSES)
        wait_until(all_poses, f"{len(POSES)} perceptions", timeout=40, watch=[node],
                   period=0.1)
        replay.stop()
    finally:
        sub.unregister()
    assert node.alive(), node.output()
    assert len(got) >= len(POSES), f"{got}\n{node.output()}"
    assert all(len(p) == 1 and LITERAL.match(p[0]) for p in got), got
