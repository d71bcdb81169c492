"""Stale percepts expire: a perception source silent for longer than its time to live is
cleared from the agent's beliefs with the usual ``-`` events (real roscore, real nodes)."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
from agent_nodes import connected_from, mind, start_agent, wait_heard
from polling import wait_until

pytestmark = pytest.mark.ros

CASES_BAG = Path(__file__).resolve().parents[2] / "bags" / "vision_cases.bag"

WATCHER = """
    +robot(R, A, D, Y)[source(percept)] <- .print("see ", R).
    -robot(R, A, D, Y)[source(percept)] <- .print("lost ", R).
    +door(S)[source(percept)] <- .print("door ", S).
    -door(S)[source(percept)] <- .print("door gone ", S).
    """


def test_a_silent_source_is_cleared_after_its_ttl_and_a_ttl_of_zero_never_expires(ros, tmp_path):
    """``~perception_ttls`` gives `radar` 1 s; `doors` (no TTL: ~perception_ttl 0) stays."""
    import rospy
    from jason_msgs.msg import Perception

    ros.init_rospy()
    pub = rospy.Publisher("/stale1/jason/perception", Perception, queue_size=10)
    agent = start_agent(ros, tmp_path, "watcher", WATCHER, ns="/stale1",
                        perception_ttls="{radar: 1.0}")
    ros.wait_for_subscriber("/stale1/jason/perception")
    wait_until(lambda: pub.get_num_connections() > 0, "connection to the agent", timeout=10)
    pub.publish(Perception(source="doors", perception=["door(open)"]))
    # radar publishes at 10 Hz for 3 s (3 TTLs): it must never be cleared meanwhile.
    for _ in range(30):
        pub.publish(Perception(source="radar", perception=["robot(faulty,1,2,3)"]))
        stopped = time.monotonic()          # the last message sent: the TTL counts from after it
        time.sleep(0.1)
    assert "lost faulty" not in agent.output()
    agent.wait_for_line(r"\[watcher\] see faulty", timeout=15)
    agent.wait_for_line(r"\[watcher\] lost faulty", timeout=15)
    took = time.monotonic() - stopped
    assert took >= 0.9, f"cleared {took:.2f} s after the last message: before its TTL"
    agent.wait_for_line(r"perception source 'radar' silent for longer than its time to live",
                        timeout=15)
    beliefs = mind(ros, "/stale1", "watcher")["beliefs"]
    assert not any(b.startswith("robot(") for b in beliefs), beliefs
    # The source comes back: its percepts are believed again.
    def lost() -> int:
        return sum("[watcher] lost faulty" in line for line in agent.lines())

    lost_once = lost()
    back = len(agent.lines())   # the lines before the source comes back hold an older "see"
    pub.publish(Perception(source="radar", perception=["robot(faulty,4,5,6)"]))
    agent.wait_for_line(r"\[watcher\] see faulty", timeout=15, start=back)
    # The sentinel: radar's second expiry. By then the door was last heard of more than twice
    # radar's TTL ago: the source without a TTL stays all the same
    wait_until(lambda: lost() > lost_once, "radar's second expiry", timeout=15, watch=[agent])
    beliefs = mind(ros, "/stale1", "watcher")["beliefs"]
    assert "door(open)[source(percept)]" in beliefs, beliefs
    assert "door gone" not in agent.output()
    assert agent.alive()


def test_the_robot_synthesizer_declares_a_ttl_and_a_dead_camera_clears_the_robot(ros, tmp_path):
    """A real synthesizer on a real bag: when the frames stop (camera unplugged), the agent
    forgets ``robot(faulty, ...)`` within the synthesizer's declared 0.5 s, with a ``-`` event."""
    import rospy
    from jason_msgs.msg import Perception

    ros.init_rospy()
    published: list[Perception] = []
    lock = threading.Lock()

    def on_perception(msg: Perception) -> None:
        with lock:
            published.append((time.monotonic(), msg))

    sub = rospy.Subscriber("/stale2/jason/perception", Perception, on_perception)
    try:
        synth = ros.rosrun("rason_vision", "robot_synthesizer", ns="/stale2")
        ros.wait_for_subscriber("/stale2/camera/depth_registered/points", watch=[synth])
        assert ros.get_param("/stale2/jason/perception_ttl/robot_synthesizer_robot") == 0.5
        agent = start_agent(ros, tmp_path, "helper", WATCHER, ns="/stale2")
        wait_until(lambda: connected_from(ros, "/stale2/robot_synthesizer",
                                          "/stale2/jason/perception", "/stale2/jason/helper"),
                   "the agent's connection to the synthesizer", timeout=30, watch=[synth, agent])
        # and ours: the last perception before the camera goes is the one the TTL counts from
        wait_heard(ros, "/stale2/robot_synthesizer", ["/stale2/jason/perception"],
                   timeout=30, watch=[synth])
        # Frames 0 and 1 of the bag (Faulty in view), then nothing: the camera is gone.
        play = ros.run(["rosbag", "play", "--quiet", "--keep-alive", "-u", "0.3", str(CASES_BAG),
                        "/helper/camera/rgb/image_raw:=/stale2/camera/rgb/image_raw",
                        "/helper/camera/depth_registered/points:="
                        "/stale2/camera/depth_registered/points"], label="rosbag_play")
        agent.wait_for_line(r"\[helper\] see faulty", timeout=60)
        agent.wait_for_line(r"source 'robot_synthesizer_robot' silent for longer than its time "
                            r"to live \(0.5 s\)", timeout=10)
        lost_at = time.monotonic()

        def last_robot_event() -> str:
            return [line for line in agent.lines() if "] see faulty" in line
                    or "] lost faulty" in line][-1]
        wait_until(lambda: last_robot_event().endswith("lost faulty"), "the - event", timeout=5)
        play.stop()
    finally:
        sub.unregister()
    with lock:
        messages = list(published)
    assert messages and all(m.perception for _, m in messages), \
        f"the synthesizer itself published an empty list: {[m for _, m in messages]}"
    silence = lost_at - messages[-1][0]
    print(f"robot belief cleared {silence:.2f} s after the last perception (TTL 0.5 s)")
    # Not before the TTL; the upper bound leaves room for a CPU-starved machine.
    assert 0.4 <= silence <= 10.0, silence
    beliefs = mind(ros, "/stale2", "helper")["beliefs"]
    assert not any(b.startswith("robot(") for b in beliefs), beliefs
    assert synth.alive() and agent.alive()


@pytest.mark.parametrize("bad, why", [("-1", "must be at least 0"), ("nan", "must be finite"),
                                      ("soon", "expected a number")])
def test_an_unusable_perception_ttl_is_a_clear_error(ros, tmp_path, bad, why):
    path = tmp_path / "a.asl"
    path.write_text("!g.\n+!g <- .print(hi).\n")
    proc = ros.rosrun("rason", "agent", "a", str(path), ns="/stale3",
                      params={"perception_ttl": bad})
    assert proc.wait(30) == 2
    assert f"bad parameter: ~perception_ttl: {why}" in proc.output()
