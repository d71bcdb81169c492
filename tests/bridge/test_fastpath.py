"""rason.ros.fastpath: the rospy internals it replaces are those of the rospy installed, and the
switch back to stock rospy gives working agent nodes."""

from __future__ import annotations

import os

import pytest
import rospkg
from agent_nodes import start_agent

from rason.ros import fastpath

STOCK = {fastpath.STOCK_ENV: "1"}


def test_the_installed_rospy_is_the_one_the_fast_paths_were_written_for():
    installed = rospkg.RosPack().get_manifest("rospy").version
    assert installed == fastpath.ROSPY_VERSION, (
        f"rospy is {installed}, but rason.ros.fastpath (frames, fanout, accept) replaces "
        f"internals of rospy {fastpath.ROSPY_VERSION}: compare rospy's impl/tcpros_base.py and "
        f"impl/topics.py of both versions, run tests/bridge/test_frames.py and "
        f"test_fanout.py, then set fastpath.ROSPY_VERSION (or run with "
        f"{fastpath.STOCK_ENV}=1 meanwhile)")


def test_the_switch_reads_one_as_stock(monkeypatch):
    for value, stock in (("1", True), ("0", False), ("", False)):
        monkeypatch.setenv(fastpath.STOCK_ENV, value)
        assert fastpath.stock() is stock, value
    monkeypatch.delenv(fastpath.STOCK_ENV)
    assert not fastpath.stock()


@pytest.mark.ros
def test_the_switch_gives_rospys_own_publishers_and_subscribers(ros, monkeypatch):
    from std_msgs.msg import String

    ros.init_rospy()
    monkeypatch.delenv(fastpath.STOCK_ENV, raising=False)
    assert getattr(fastpath.publisher("/fp/fast", String, queue_size=5).impl, "direct_writes", False)
    assert getattr(fastpath.subscriber("/fp/fast_in", String, print).impl, "framed_reads", False)
    monkeypatch.setenv(fastpath.STOCK_ENV, "1")
    assert not getattr(fastpath.publisher("/fp/stock", String, queue_size=5).impl,
                       "direct_writes", False)
    assert not getattr(fastpath.subscriber("/fp/stock_in", String, print).impl,
                       "framed_reads", False)


ALICE = """
    !start.
    +!start : .all_names(L) & .member(bob, L) <- move(1); .print("moved"); .send(bob, tell, hello(alice)).
    +!start <- .wait(200); !start.
    +seen(X)[source(percept)] <- .print("seen ", X).
    """
BOB = """
    +hello(X)[source(S)] <- .print("hello from ", S).
    """


def _thread_nices(pid: int) -> set[int]:
    return {os.getpriority(os.PRIO_PROCESS, int(tid)) for tid in os.listdir(f"/proc/{pid}/task")}


@pytest.mark.ros
def test_an_agent_node_on_stock_rospy_acts_perceives_and_talks(ros, tmp_path):
    import rospy
    from jason_msgs.msg import Perception

    ros.rosrun("rason", "echo_decomposer", ns="/s1", env=STOCK)
    ros.wait_for_subscriber("/s1/jason/action")
    bob = start_agent(ros, tmp_path, "bob", BOB, ns="/s2", env=STOCK)
    alice = start_agent(ros, tmp_path, "alice", ALICE, ns="/s1", env=STOCK, receive_nice=7)
    alice.wait_for_line(r"\[alice\] moved", timeout=60)                 # action and feedback
    bob.wait_for_line(r"\[bob\] hello from alice", timeout=60)          # a message
    ros.init_rospy()
    pub = rospy.Publisher("/s1/jason/perception", Perception, queue_size=10, latch=True)
    ros.wait_for_subscriber("/s1/jason/perception")
    pub.publish(Perception(source="test_cam", perception=["seen(3)"]))
    alice.wait_for_line(r"\[alice\] seen 3", timeout=30)                 # a perception
    for proc in (alice, bob):
        assert fastpath.STOCK_ENV in proc.output()                      # said so at start
    # alice heard bob's presence on /jason/messages: no frame reader lowered that thread
    assert _thread_nices(alice.pid) == {os.getpriority(os.PRIO_PROCESS, 0)}
