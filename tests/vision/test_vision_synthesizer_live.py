"""The synthesizer on the live simulator, and its private parameters, with real processes."""

from __future__ import annotations

import re
import threading

import numpy as np
import pytest
import yaml
from polling import wait_until
from vision_truth import LITERAL

from rason_diagnosis.paths import world_file

pytestmark = pytest.mark.ros


def collect(topic: str, count: int, timeout: float, start=None) -> list:
    """The first ``count`` messages on ``topic`` (jason_msgs/Perception)."""
    import rospy
    from jason_msgs.msg import Perception

    got: list[Perception] = []
    done = threading.Event()

    def on_msg(msg: Perception) -> None:
        got.append(msg)
        if len(got) >= count:
            done.set()

    sub = rospy.Subscriber(topic, Perception, on_msg)
    try:
        # the perception topic is not latched: be connected first
        wait_until(lambda: sub.get_num_connections() >= 1, f"a connection to {topic}",
                   timeout=10, period=0.05)
        if start is not None:
            start()
        done.wait(timeout)
    finally:
        sub.unregister()
    return got


def test_synthesizer_sees_faulty_in_the_case_study_from_the_live_sim(ros, tmp_path):
    """Thesis ch. 7 layout with Helper turned right by 90 deg: Faulty's left flank, centred."""
    world = yaml.safe_load(world_file().read_text())
    for robot in world["robots"]:
        if robot["name"] == "helper":
            robot["yaw"] = -90.0
    path = tmp_path / "case_study_turned.yaml"
    path.write_text(yaml.safe_dump(world))
    ros.set_param("/use_sim_time", True)
    sim = ros.rosrun("turtlebot_sim", "sim", f"_world:={path}", "_camera_rate:=5")
    node = ros.rosrun("rason_vision", "robot_synthesizer", ns="/helper")
    ros.wait_for_topic("/helper/camera/depth_registered/points", watch=[sim], timeout=30)
    ros.wait_for_topic("/helper/jason/perception", watch=[node])
    ros.init_rospy()
    msgs = collect("/helper/jason/perception", 3, 30)
    assert len(msgs) == 3, sim.output()[-2000:] + node.output()[-2000:]
    for msg in msgs:
        assert msg.source == "robot_synthesizer_robot"
        assert len(msg.perception) == 1, list(msg.perception)
        match = LITERAL.match(msg.perception[0])
        assert match and match.group(1) == "faulty"
        angle, depth, yaw = (float(match.group(i)) for i in (2, 3, 4))
        # Faulty 1.5 m from Helper's centre = 1.365 m from the Kinect, facing the image's left
        assert abs(angle) < 1.0 and abs(depth - 1.365) < 0.03 and abs(yaw + 90.0) < 8.0


def test_private_params_name_source_and_colours(ros):
    """``__name`` sets the source, ``~robot_name`` the literal; colour ranges are params."""
    import rospy
    from sensor_msgs.msg import Image, PointCloud2

    from rason_vision_tools.messages import frame_messages
    from rason_vision_tools.synthetic import faulty_scene

    ros.init_rospy()
    rgb, xyz = faulty_scene(2.0, -10.0, 30.0).render(np.random.default_rng(3))
    image, cloud = frame_messages(rgb, xyz)
    image.header.stamp = cloud.header.stamp = rospy.Time(1.0)

    eye = ros.rosrun("rason_vision", "robot_synthesizer", ns="/p1", name="eye",
                     params={"robot_name": "buddy"})
    # a green range that excludes our green: only the orange cylinder is found, a partial sighting
    blind = ros.rosrun("rason_vision", "robot_synthesizer", ns="/p2",
                       params={"green_lower": [90, 90, 40], "green_upper": [100, 255, 255]})
    for ns, proc in (("/p1", eye), ("/p2", blind)):
        ros.wait_for_subscriber(f"{ns}/camera/depth_registered/points", watch=[proc])
        ros.wait_for_topic(f"{ns}/jason/perception", watch=[proc])
    pubs = {ns: (rospy.Publisher(f"{ns}/camera/rgb/image_raw", Image, queue_size=2, latch=True),
                 rospy.Publisher(f"{ns}/camera/depth_registered/points", PointCloud2,
                                 queue_size=2, latch=True)) for ns in ("/p1", "/p2")}
    try:
        for ns, (pub_image, pub_cloud) in pubs.items():
            msgs = collect(f"{ns}/jason/perception", 1, 20,
                           start=lambda a=pub_image, b=pub_cloud: (a.publish(image),
                                                                   b.publish(cloud)))
            assert msgs, f"no perception on {ns}"
            if ns == "/p1":
                assert msgs[0].source == "eye_robot"
                assert len(msgs[0].perception) == 1
                assert msgs[0].perception[0].startswith("robot(buddy,-10.0,")
            else:
                assert msgs[0].source == "robot_synthesizer_robot"
                assert len(msgs[0].perception) == 1, list(msgs[0].perception)
                assert re.match(r"^robot_partial\(faulty,-?\d+\.\d,\d+\.\d\d,orange\)$",
                                msgs[0].perception[0]), list(msgs[0].perception)
    finally:
        for a, b in pubs.values():
            a.unregister()
            b.unregister()
