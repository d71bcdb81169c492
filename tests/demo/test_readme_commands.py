"""Every ``rosrun`` and ``./run.sh`` line in README's fenced blocks works as written.

The lines of the block under "The same scenario by hand" run in order in test_manual.py. Every
other line runs here exactly as typed, through bash from the repository root:

* ``./run.sh demo ...`` to the end: exit status 0 (the diagnosis was right);
* ``./run.sh campaign|bench ...``: too long for the suite, so their arguments are checked by
  running the line with ``--help`` appended (argparse parses the given arguments first);
* ``./run.sh test``: this suite itself (not run again);
* ``rosrun ...``: against a private roscore; a one-shot tool must exit 0, a node must come up
  (register with the master and stay up) until it is stopped.

Lines with placeholders (``FILE``, ``NAME``, ``[optional]``, ``a|b``) are templates, not commands,
and are not run.
"""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest

from rason.testing.harness import RosHarness

pytestmark = [pytest.mark.ros, pytest.mark.demo]

REPO = Path(__file__).resolve().parents[2]
MANUAL_SECTION = "### The same scenario by hand"
#: How long a node may take to register before it counts as not coming up.
NODE_START_S = 30.0


def _blocks() -> list[tuple[str, list[str]]]:
    """(heading above, lines) of every fenced block of README."""
    heading, out, block = "", [], None
    for line in (REPO / "README.md").read_text().splitlines():
        if block is None and line.startswith("#"):
            heading = line
        if line.startswith("```"):
            if block is None:
                block = []
            else:
                out.append((heading, block))
                block = None
        elif block is not None:
            block.append(line)
    return out


def _command(line: str) -> str:
    """The line without a trailing ``# comment``."""
    return re.sub(r"\s+#\s.*$", "", line).strip()


def _is_template(command: str) -> bool:
    return bool(re.search(r"\[|\||\b[A-Z]{2,}[A-Z_]*\b(?!=)", command.replace("$(rospack", "")))


def readme_commands() -> list[str]:
    commands = []
    for heading, lines in _blocks():
        if heading.startswith(MANUAL_SECTION):
            continue
        for line in lines:
            command = _command(line)
            if command.startswith(("rosrun ", "./run.sh ")) and not _is_template(command):
                commands.append(command)
    return commands


COMMANDS = readme_commands()


def test_readme_shows_the_two_commands():
    assert "./run.sh demo" in COMMANDS and "./run.sh test" in COMMANDS


@pytest.mark.parametrize("command", COMMANDS)
def test_readme_command_works_as_written(command, tmp_path):
    verb = command.split()[1] if command.startswith("./run.sh") else "rosrun"
    if verb == "test":
        return                              # the suite running this test
    with RosHarness(log_dir=tmp_path / "logs") as ros:
        if verb in ("campaign", "bench"):
            out = ros.check_output(["bash", "-c", f"{command} --help"], timeout=120)
            assert "usage" in out.lower()
        elif verb != "rosrun":
            proc = ros.run(["bash", "-c", command], label=command[:40], cwd=REPO)
            assert proc.wait(timeout=400) == 0, proc.output()[-3000:]
        else:
            before = ros.nodes()
            proc = ros.run(["bash", "-c", f"exec {command}"], label=command[:40], cwd=REPO)
            deadline = time.monotonic() + NODE_START_S
            while time.monotonic() < deadline and proc.alive() and ros.nodes() == before:
                time.sleep(0.2)
            if not proc.alive():
                assert proc.wait(timeout=5) == 0, proc.output()[-3000:]
            else:
                assert ros.nodes() != before, f"{command}: no node registered\n{proc.output()}"
                time.sleep(1.0)
                assert proc.alive(), proc.output()[-3000:]
