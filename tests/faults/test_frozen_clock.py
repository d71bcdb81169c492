"""A node whose ROS clock stops while it waits on time warns by name (#37 item 6).

With ``/use_sim_time`` the agent node's ROS time is ``/clock``, published here by the test as a
simulator would. The agent waits on ROS time twice over: a ``.wait`` and an action no
decomposer answers (its ``~ack_timeout`` runs in ROS time). When ``/clock`` stops (the
simulator stopped), ROS time stands still and nothing would ever end those waits: within a few
seconds of wall time (the one right measure of a clock that stands still) the node warns,
naming the agent and what it waits for; after ``/clock`` runs again the wait ends.
"""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
import rospy
from agent_nodes import start_agent
from rosgraph_msgs.msg import Clock

from rason.process.harness import RosHarness
from rason.ros.node import FROZEN_CLOCK_S

pytestmark = pytest.mark.ros

WAITER = """
    !go.
    +!go <- !!act; .print("waiting"); .wait(3000); .print("waited").
    +!act <- move(1).
    -!act[error(E)] <- .print("act failed: ", E).
    """


def test_a_frozen_clock_is_warned_about_by_name(ros: RosHarness, tmp_path: Path):
    ros.init_rospy()
    ros.set_param("/use_sim_time", True)
    clock = rospy.Publisher("/clock", Clock, queue_size=10)
    sim = {"t": 100.0, "running": True}
    stop = threading.Event()

    def tick() -> None:           # 10 Hz of wall time, 0.1 s of sim time each while running
        while not stop.wait(0.1):
            if sim["running"]:
                sim["t"] += 0.1
            clock.publish(Clock(clock=rospy.Time.from_sec(sim["t"])))
    thread = threading.Thread(target=tick, daemon=True)
    thread.start()
    try:
        agent = start_agent(ros, tmp_path, "waiter", WAITER, ns="/frozen1")
        agent.wait_for_line(r"\[waiter\] waiting", timeout=30)
        sim["running"] = False                       # the simulator stops
        stopped = time.monotonic()
        agent.wait_for_line(r"ROS time has stood still .*\[waiter\] action move\(1\).*"
                            r"\[waiter\] a wait until", timeout=FROZEN_CLOCK_S + 10)
        assert time.monotonic() - stopped >= FROZEN_CLOCK_S - 0.5
        assert "waited" not in agent.output()
        sim["running"] = True                         # it runs again: the waits end
        agent.wait_for_line(r"\[waiter\] waited", timeout=30)
        agent.wait_for_line(r"\[waiter\] act failed: no_decomposer", timeout=30)
        assert agent.output().count("ROS time has stood still") == 1
    finally:
        stop.set()
        thread.join()
        clock.unregister()
        rospy.delete_param("/use_sim_time")     # the session's master is shared with later tests
