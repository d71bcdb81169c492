"""Ctrl-C while a node starts stops it (rosnode_kit.signals).

Under rospy's own handler, a SIGINT that came while the node's main thread was registering a
publisher with the master left the node hanging until SIGKILL (the shutdown waited for the lock
the interrupted registration held); the suite's tests that end while their node still starts
sat out the harness' whole SIGINT and SIGTERM grace (7 s) each. Here each node gets its SIGINT
right after its first warning, in the middle of its start (its publishers, subscribers and
services are being registered), a few times over, and must exit from the SIGINT alone.
"""

from __future__ import annotations

import signal

import pytest

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

#: starts per node: the SIGINT lands at a slightly different point of the start each time
ROUNDS = 2
#: how long a node may take to exit after its SIGINT (s): a hung node never does
EXIT_WITHIN = 30.0


@pytest.mark.parametrize(("package", "node"), [
    ("rason", "echo_decomposer"),                    # rosnode_kit.params.start_node
    ("rason", "agent"),                              # rason.ros.main
    ("kobuki_fault_injector", "fault_injector"),     # its own main
])
def test_a_node_interrupted_while_it_starts_exits(ros: RosHarness, tmp_path, package, node):
    (tmp_path / "a.asl").write_text("!g.\n+!g <- .print(started).\n")
    args = ("a", str(tmp_path / "a.asl")) if node == "agent" else ()
    for round_ in range(ROUNDS):
        # an unknown parameter: its warning comes right after rospy.init_node
        proc = ros.rosrun(package, node, *args, ns=f"/interrupted_{node}_{round_}",
                          params={"unknown_parameter": 1})
        proc.wait_for_line("unknown private parameter ~unknown_parameter", timeout=60)
        proc.signal_group(signal.SIGINT)
        proc.wait(EXIT_WITHIN)                       # raises TimeoutExpired when it hangs
