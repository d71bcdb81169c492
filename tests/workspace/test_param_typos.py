"""Private parameters against a real roscore: a typo is warned about with the closest known name,
and a rejected value is cleared from the parameter server so the corrected command starts."""

from __future__ import annotations

import pytest
from agent_nodes import start_agent

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

AGENT = "!g.\n+!g <- .print(started).\n"


@pytest.mark.parametrize(("package", "node", "typo", "meant"), [
    ("rason", "agent", "ack_timout", "ack_timeout"),
    ("rason", "echo_decomposer", "dellay", "delay"),
    ("kobuki_fault_injector", "fault_injector", "odom_inptu", "odom_input"),
])
def test_an_unknown_private_parameter_is_warned_with_the_closest_name(
        ros: RosHarness, tmp_path, package, node, typo, meant):
    args = ("a", str(tmp_path / "a.asl")) if node == "agent" else ()
    (tmp_path / "a.asl").write_text(AGENT)
    proc = ros.rosrun(package, node, *args, ns=f"/typo_{node}", params={typo: 3})
    proc.wait_for_line(rf"unknown private parameter ~{typo} \(ignored\); did you mean ~{meant}\?",
                       timeout=60)
    assert proc.alive()                     # a warning, not an error


def test_a_known_parameter_gives_no_warning(ros: RosHarness, tmp_path):
    proc = start_agent(ros, tmp_path, "a", AGENT, ns="/typo_none", ack_timeout=3)
    proc.wait_for_line("started", timeout=60)
    assert "unknown private parameter" not in proc.output()


@pytest.mark.parametrize(("package", "node", "key", "bad"), [
    ("rason", "agent", "perception_ttl", -1),
    ("rason", "echo_decomposer", "delay", "soon"),
])
def test_a_rejected_value_is_cleared_so_the_corrected_command_starts(
        ros: RosHarness, tmp_path, package, node, key, bad):
    (tmp_path / "a.asl").write_text(AGENT)
    args = ("a", str(tmp_path / "a.asl")) if node == "agent" else ()
    ns = f"/cleared_{node}"
    full = f"{ns}/jason/a/{key}" if node == "agent" else f"{ns}/{node}/{key}"
    proc = ros.rosrun(package, node, *args, ns=ns, params={key: bad})
    assert proc.wait(60) == 2
    assert f"~{key}:" in proc.output()
    assert f"({full} was deleted from the parameter server)" in proc.output()
    with pytest.raises(KeyError):
        ros.get_param(full)
    again = ros.rosrun(package, node, *args, ns=ns)      # the command without the parameter
    # the sentinel: a service or subscription it makes after reading its parameters (it is a
    # node of the master before: it reads them after rospy.init_node)
    if node == "agent":
        ros.wait_for_service(f"{ns}/jason/a/mind", timeout=60, watch=[again])
    else:
        ros.wait_for_subscriber(f"{ns}/jason/action", timeout=60, watch=[again])
    assert "bad parameter" not in again.output() and f"~{key}:" not in again.output()
