"""The tutorial "Write your own decomposer and synthesizer" (docs/tutorial.md) works as written.

The page's files (code blocks whose first line names them: ``# beep.py``, ``// pilot.asl``)
are written to a fresh directory outside the project and its commands run there in order,
against a private roscore (the harness's, standing in for the ``roscore`` line); then what the
page promises is checked: the agent's lines, the buzzer going on and off, and the NaN message
refused with a warning.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from polling import wait_until

from rason.process.harness import Process, RosHarness

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]
PAGE = REPO / "docs" / "tutorial.md"
TITLE = "# Write your own decomposer and synthesizer"
NAMED = re.compile(r"^(?:#|//)\s*(\w+\.(?:py|asl))\s*$")


def tutorial() -> tuple[str, dict[str, str], list[str]]:
    """The page's text, its files and its command lines."""
    section = PAGE.read_text()
    assert section.startswith(TITLE)
    files: dict[str, str] = {}
    commands: list[str] = []
    for block in re.findall(r"^```[a-z]*\n(.*?)^```", section, flags=re.M | re.S):
        lines = block.splitlines()
        named = NAMED.match(lines[0]) if lines else None
        if named:
            files[named.group(1)] = block
        elif lines and lines[0] == "roscore":
            commands = lines
    return section, files, commands


def test_the_tutorial_has_its_files_and_commands():
    section, files, commands = tutorial()
    assert set(files) == {"beep.py", "battery.py", "power.py", "pilot.asl"}
    assert commands[0] == "roscore" and any(c.startswith("rostopic pub") for c in commands)
    assert "[pilot] battery at 15%: 7.5 minutes left" in section


def start_node(ros: RosHarness, command: str, cwd: Path) -> Process:
    """Run `command` in `cwd` and wait until it registers a node with the master."""
    before = ros.nodes()
    proc = ros.run(["bash", "-c", f"exec {command}"], label=command.split()[1][:30], cwd=cwd)
    wait_until(lambda: ros.nodes() != before, f"a node registered by {command}", timeout=30,
               watch=[proc], period=0.2)
    return proc


def test_tutorial_runs_as_written(ros: RosHarness, tmp_path: Path):
    section, files, commands = tutorial()
    for name, body in files.items():
        (tmp_path / name).write_text(body)
    procs: dict[str, Process] = {}
    for command in commands:
        if command == "roscore":
            continue                          # the harness's roscore
        if command.startswith("rostopic pub"):
            # as a reader would, once the nodes started before are up: `-1` latches the message
            # for 3 s only, so a subscriber must be there to take it
            topic = next(word for word in command.split()[2:] if word.startswith("/"))
            ros.wait_for_subscriber(topic, timeout=30)
            done = ros.run(["bash", "-c", command], label="rostopic_pub", cwd=tmp_path)
            assert done.wait(timeout=30) == 0, done.output()
            continue
        procs[command.split()[1]] = start_node(ros, command, tmp_path)
    agent = next(p for c, p in procs.items() if c == "rason")
    agent.wait_for_line(r"\[pilot\] battery at 15%: 7\.5 minutes left", timeout=20)
    agent.wait_for_line(r"\[pilot\] warned", timeout=20)
    echo = procs["echo"]
    echo.wait_for_line(r"data: False", timeout=10)
    assert re.search(r"data: True.*data: False", echo.output(), flags=re.S), echo.output()
    # the NaN message of the prose: refused with a warning, nothing else happens
    nan = re.search(r"`(rostopic pub -1 /robot/battery\s+sensor_msgs/BatteryState "
                    r"\"\{percentage: \.nan\}\")`", section)
    assert nan, "the NaN example is gone from the tutorial"
    done = ros.run(["bash", "-c", " ".join(nan.group(1).split())], label="rostopic_pub_nan",
                   cwd=tmp_path)
    assert done.wait(timeout=30) == 0, done.output()
    battery = procs["battery.py"]
    battery.wait_for_line(r"frame rejected \(bad frame: charge nan is not in \[0, 1\]\)",
                          timeout=10)
    assert all(p.alive() for p in procs.values())
    assert agent.output().count("[pilot] warned") == 1
