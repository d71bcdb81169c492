"""README's first agent (agents/examples/square.asl) drives the simulated robot as README says.

README shows the file and the lines that run it; the file shown must be the file shipped, and the
lines run in order as typed (doc_commands.run_in_order), against a private roscore standing in
for their ``roscore``. The agent must print ``square done`` after its eight actions succeeded,
and the simulator's ground truth must show Faulty drive the square's far corner and come back;
with the wheel README breaks, the agent must print why it stopped.
"""

from __future__ import annotations

import math
import re

import pytest
from doc_commands import FIRST_AGENT, REPO, run_in_order, section_blocks, start_node

from rason.process.harness import RosHarness

pytestmark = [pytest.mark.ros, pytest.mark.demo]

AGENT = REPO / "agents" / "examples" / "square.asl"
#: Faulty's position in the simulator's world frame, and as `rostopic echo` prints it.
POSITION_TOPIC = "/faulty/ground_truth/odom/pose/pose/position"
POSITION = re.compile(r"^x: (\S+)\ny: (\S+)$", re.M)


def test_readme_shows_the_shipped_agent_and_how_to_run_it():
    code, commands = section_blocks(*FIRST_AGENT)[:2]
    assert "\n".join(code.lines) + "\n" == AGENT.read_text()
    assert len(code.commands()) <= 10
    assert commands.commands()[-1].endswith(f"{AGENT.relative_to(REPO).as_posix()} __ns:=/faulty")


def test_the_first_agent_drives_a_square_and_comes_back():
    commands = section_blocks(*FIRST_AGENT)[1].commands()
    with RosHarness() as ros:
        run_in_order(ros, commands[:-1])
        truth = ros.run(["rostopic", "echo", POSITION_TOPIC], label="ground_truth")
        truth.wait_for_line(r"^x: ", timeout=30)
        agent = start_node(ros, commands[-1], "pilot")
        agent.wait_for_line(r"\[pilot\] square done", timeout=180)
        path = [(float(x), float(y)) for x, y in POSITION.findall(truth.output())]
        # where it stopped: a pose published now (the echo above may not have printed it yet)
        end = next((float(x), float(y)) for x, y in POSITION.findall(
            ros.check_output(["rostopic", "echo", "-n", "1", POSITION_TOPIC], timeout=30)))
    start = path[0]
    farthest = max(math.dist(start, p) for p in path)
    assert farthest > 0.6, f"the far corner is 0.71 m from the start, reached {farthest:.2f} m"
    assert math.dist(start, end) < 0.15, f"ended {math.dist(start, end):.2f} m from the start"


def test_with_a_broken_wheel_the_first_agent_says_why_it_stopped():
    commands = section_blocks(*FIRST_AGENT)[1].commands()
    readme = FIRST_AGENT[0].read_text()
    breaking = re.search(r"`(rosservice call /faulty/fault_injector [^`]+)`", readme).group(1)
    stopped = re.search(r"`(\[pilot\] square stopped: \w+)`", readme).group(1)
    with RosHarness() as ros:
        run_in_order(ros, [*commands[:-1], breaking])
        agent = start_node(ros, commands[-1], "pilot")
        agent.wait_for_line(re.escape(stopped), timeout=180)
