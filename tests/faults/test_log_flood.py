"""Log floods (#37 item 2): warnings are limited per process as well as per sender, no log
line carries unbounded input, and the fault injector neither logs nor echoes a huge name.

The issue's probe: messages with unreadable content under ever new sender names wrote 28,413
warning lines in 30 s (each name its own rate-limit group).
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
import rospy
from agent_nodes import connected_to, start_agent
from jason_msgs.msg import AgentMessage
from polling import wait_until

from kobuki_fault_injector.srv import FaultInjector
from rason.execution.decomposer import Goal
from rason.process.harness import RosHarness
from rosnode_kit.badinput import GLOBAL_BURST, GLOBAL_RATE, MAX_LINE, BadInputLog, GlobalLimit

LONGEST_LINE = MAX_LINE + 400      # a shortened text, its marker, the node's prefix, counts


def test_a_decomposers_log_of_a_goal_is_short_whatever_its_action_carries():
    goal = Goal("x" * 1_000_000, 7, "move", ["1" * 1_000_000, "2"], 1.0, 0.0)
    line = str(goal)
    assert len(line) < 600 and "(action 7)" in line and "1000000 characters" in line


def test_new_group_names_cannot_pass_the_process_limit():
    clock = [0.0]
    limit = GlobalLimit(rate=2.0, burst=20, now=lambda: clock[0])
    logged: list[str] = []
    a = BadInputLog(logged.append, lambda: clock[0], limit=limit)
    b = BadInputLog(logged.append, lambda: clock[0], limit=limit)     # another of the process
    for k in range(10_000):                     # 10,000 new senders in 10 s
        clock[0] = k / 1000
        (a if k % 2 else b).warn(f"sender_{k}", None, f"bad message from sender_{k}")
    assert len(logged) == 20 + 2 * 10 - 1        # the burst, then 2 a second
    assert "other warnings held back: too many at once" in logged[20]
    clock[0] = 100.0
    assert a.warn("late", None, "x" * 100_000)
    assert logged[-1].endswith("held back: too many at once)") and len(logged[-1]) < 700
    assert len(a._groups) <= a.remember and all(len(g) <= 65 for g in a._groups)


@pytest.mark.ros
def test_a_flood_under_new_sender_names_writes_few_short_warnings(ros: RosHarness,
                                                                   tmp_path: Path):
    agent = start_agent(ros, tmp_path, "calm", "+hello[source(A)] <- .print(hi).\n", ns="/flood")
    ros.init_rospy()
    pub = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10_000)
    wait_until(lambda: connected_to(pub, "/flood/jason/calm"), "the connection to calm's node")
    start = time.monotonic()
    sent = 0
    while time.monotonic() - start < 6.0:        # unreadable content from new names
        for _ in range(50):
            pub.publish(AgentMessage(sender=f"flood_{sent}", receiver="calm",
                                     performative="tell", content=f"broken({sent}"))
            sent += 1
        time.sleep(0.01)                         # the flood's pace
    huge = "h" * 1_000_000                       # and one huge name with huge content
    pub.publish(AgentMessage(sender=huge, receiver="calm", performative="tell", content=huge))
    time.sleep(3.0)                              # the rate limit's window passes (under test)
    pub.publish(AgentMessage(sender="last", receiver="calm", performative="tell",
                             content="broken("))
    elapsed = time.monotonic() - start

    def dropped() -> list[str]:
        return [line for line in agent.lines() if "dropped message from" in line]

    wait_until(lambda: any("from last" in line for line in dropped()), "the warning of the last",
               timeout=30, watch=[agent], period=0.3)
    lines = dropped()
    assert any("from last" in line and "other warnings held back" in line for line in lines), \
        lines[-3:]
    assert len(lines) <= GLOBAL_BURST + GLOBAL_RATE * (elapsed + 35), (sent, len(lines))
    assert sent >= 1000 and len(lines) < sent / 10
    assert max(len(line) for line in agent.lines()) < LONGEST_LINE
    assert agent.alive()
    pub.unregister()


@pytest.mark.ros
def test_the_fault_injector_refuses_a_huge_fault_name_briefly(ros: RosHarness):
    ns = "/floodfi"
    node = ros.rosrun("kobuki_fault_injector", "fault_injector", ns=ns)
    ros.wait_for_service(f"{ns}/fault_injector", watch=[node])
    ros.init_rospy()
    call = rospy.ServiceProxy(f"{ns}/fault_injector", FaultInjector)
    reply = call("left_" * 200_000).return_message        # 1 MB
    assert reply.startswith("error: fault name too long (1,000,000 characters, at most 64)")
    assert len(reply) < 300 and "left_left_" not in reply
    assert "fault 'odometry' injected" in call("odometry").return_message
    unknown = call("x" * 64).return_message
    assert unknown.startswith("error: unknown fault 'xxx")
    assert "(active fault unchanged: odometry)" in unknown
    # the node logs each request as it answers it: the last request's line is the last of the
    # three (its output reaches us through a reader thread, after the service's reply)
    node.wait_for_line(r"fault_injector: request 'x+.*unknown fault", 20)
    logged = [line for line in node.lines() if "fault_injector: request" in line]
    assert len(logged) == 3 and max(len(line) for line in node.lines()) < 400, logged
    assert "characters)" in logged[0]            # the name shown shortened, with its length
    assert node.alive()
