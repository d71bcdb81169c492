"""The README's "same scenario by hand" runs as written: its commands, one after the other.

Each line of the README's block is run exactly as a user would type it (from the project root),
against a private roscore that stands in for the block's first line. Long-running commands
(`rosrun ...`) stay up; one-shot tools (`rosparam`, `rosservice`) run to completion. Then the
README's ways to watch the run are used: `rostopic echo` on Helper's perceptions and the mind
service, which must end up holding Faulty's belief ``diagnosis(left_actuator)``.
"""

from __future__ import annotations

import re
import shlex
import time
from pathlib import Path

import pytest

from rason.testing.harness import RosHarness

#: The repository (the README's commands run from its root).
REPO = Path(__file__).resolve().parents[2]

pytestmark = [pytest.mark.ros, pytest.mark.demo]


def manual_commands() -> list[str]:
    """The command lines of the README's block under "The same scenario by hand"."""
    readme = (REPO / "README.md").read_text()
    section = readme.split("### The same scenario by hand", 1)[1]
    block = section.split("```", 2)[1]
    return [line.strip() for line in block.splitlines() if line.strip()]


def test_readme_lists_the_whole_scenario():
    commands = manual_commands()
    assert commands[0] == "roscore"
    assert any(c.startswith("rosservice call /faulty/fault_injector") for c in commands)
    assert [c.split()[3] for c in commands if c.startswith("rosrun rason agent")] == \
        ["helper", "faulty"]


def test_manual_scenario_diagnoses_the_injected_fault():
    commands = manual_commands()
    injected = re.search(r"fault: '(\w+)'", " ".join(commands)).group(1)
    with RosHarness() as ros:          # its roscore is the block's first line
        for line in commands[1:]:
            argv = shlex.split(line)
            if argv[0] in ("rosparam", "rosservice"):
                if argv[:2] == ["rosservice", "call"]:
                    ros.wait_for_service(argv[2], timeout=60)
                ros.check_output(argv, timeout=60)
            else:
                # through bash, as typed: the README uses $(rospack find ...) for files
                ros.run(["bash", "-c", f"exec {line}"], label=" ".join(argv[1:4]), cwd=REPO)
                if "turtlebot_sim" in argv:
                    ros.wait_for_topic("/clock", timeout=60)
                if "robot_synthesizer" in argv:
                    ros.wait_for_topic("/helper/jason/perception", timeout=60)
        echoed = ros.check_output(["rostopic", "echo", "-n", "1", "/helper/jason/perception"])
        assert "perception:" in echoed and "source:" in echoed
        ros.wait_for_service("/faulty/jason/faulty/mind", timeout=60)
        deadline = time.monotonic() + 240
        mind = ""
        while time.monotonic() < deadline:
            mind = ros.check_output(["rosservice", "call", "/faulty/jason/faulty/mind"])
            if "diagnosis(" in mind:
                break
            time.sleep(1.0)
        assert f"diagnosis({injected})" in mind, mind[-2000:]
