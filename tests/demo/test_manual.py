"""The case study's "same scenario by hand" (docs/case-study.md) runs as written, line after line.

Each line of the page's block is run exactly as a user would type it (from the project root),
against a private roscore that stands in for the block's first line. Long-running commands
(`rosrun ...`) stay up; one-shot tools (`rosparam`, `rosservice`) run to completion. Then the
page's ways to watch the run are used: `rostopic echo` on Helper's perceptions and the mind
service, which must end up holding Faulty's belief ``diagnosis(left_actuator)``.
"""

from __future__ import annotations

import re

import pytest
from doc_commands import BY_HAND, run_in_order, section_blocks
from polling import wait_until

from rason.process.harness import RosHarness

pytestmark = [pytest.mark.ros, pytest.mark.demo]


def manual_commands() -> list[str]:
    """The command lines of the block under "The same scenario by hand"."""
    return section_blocks(*BY_HAND)[0].commands()


def test_the_page_lists_the_whole_scenario():
    commands = manual_commands()
    assert commands[0] == "roscore"
    assert any(c.startswith("rosservice call /faulty/fault_injector") for c in commands)
    assert [c.split()[3] for c in commands if c.startswith("rosrun rason agent")] == \
        ["helper", "faulty"]


def test_manual_scenario_diagnoses_the_injected_fault():
    commands = manual_commands()
    injected = re.search(r"fault: '(\w+)'", " ".join(commands)).group(1)
    with RosHarness() as ros:          # its roscore is the block's first line
        run_in_order(ros, commands, topics={"robot_synthesizer": "/helper/jason/perception"})
        echoed = ros.check_output(["rostopic", "echo", "-n", "1", "/helper/jason/perception"])
        assert "perception:" in echoed and "source:" in echoed
        ros.wait_for_service("/faulty/jason/faulty/mind", timeout=60)
        def diagnosed() -> str:
            mind = ros.check_output(["rosservice", "call", "/faulty/jason/faulty/mind"])
            return mind if "diagnosis(" in mind else ""
        mind = wait_until(diagnosed, "a diagnosis in Faulty's mind", timeout=240, period=1.0)
        assert f"diagnosis({injected})" in mind, mind[-2000:]
