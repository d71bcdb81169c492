"""Log lines of rason nodes cost no call to the master (rosnode_kit.rosout works around rospy
asking the master for an unset parameter with every log line)."""

from __future__ import annotations

import textwrap

import pytest

from rason.process.harness import python

pytestmark = pytest.mark.ros

# A node that counts its calls to the master while it logs, then sees a change of the parameter.
NODE = textwrap.dedent("""
    import sys, time
    import rospy, rospy.client
    from rosnode_kit.rosout import ROSOUT_TOPICS_PARAM, cache_rosout_setting
    rospy.init_node("logger", anonymous=True)
    if sys.argv[1] == "cached":
        assert cache_rosout_setting()
    rospy.loginfo("first line")          # rospy's own first call: subscribes to the parameter
    proxy = rospy.client._param_server.target
    calls = []
    class Counting:
        def __getattr__(self, name):
            calls.append(name)
            return getattr(proxy, name)
    rospy.client._param_server.target = Counting()
    for k in range(20):
        rospy.loginfo("line %d", k)
    print("calls", len(calls), flush=True)
    rospy.client._param_server.target = proxy
    rospy.set_param(ROSOUT_TOPICS_PARAM, True)
    deadline = time.monotonic() + 10      # a child process: tests/polling.py is not its to import
    while rospy.get_param_cached(ROSOUT_TOPICS_PARAM, False) is not True:
        assert time.monotonic() < deadline, "the change never reached the node"
        time.sleep(0.05)
    rospy.delete_param(ROSOUT_TOPICS_PARAM)
    print("update seen", flush=True)
""")


def test_log_lines_do_not_call_the_master_and_the_parameter_still_updates(ros):
    plain = ros.check_output([python(), "-c", NODE, "plain"])
    cached = ros.check_output([python(), "-c", NODE, "cached"])
    assert "calls 20" in plain        # rospy alone: one XML-RPC call per log line
    assert "calls 0" in cached and "update seen" in cached
