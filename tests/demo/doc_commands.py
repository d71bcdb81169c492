"""The fenced blocks of README.md and docs/*.md, for the tests that run their commands as written.

Most command lines run one at a time (test_readme_commands.py); the blocks of :data:`SEQUENCES`
are one scenario each, their lines run in order by a test of their own.
"""

from __future__ import annotations

import re
import shlex
from dataclasses import dataclass
from pathlib import Path

from polling import wait_until

from rason.process.harness import Process, RosHarness

#: The repository (the pages' commands run from its root).
REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
#: Every page whose fenced command lines must work as written.
PAGES = (README, *sorted((REPO / "docs").glob("*.md")))
#: A page's first agent (test_first_agent.py) and the case study by hand (test_manual.py).
FIRST_AGENT = (README, "## Ten lines of `.asl` that move a robot")
BY_HAND = (REPO / "docs" / "case-study.md", "## The same scenario by hand")
SEQUENCES = (FIRST_AGENT, BY_HAND)
#: Pages whose every block is one scenario, run in order by a test of their own
#: (test_real_robot_doc.py runs the bring-up of two real TurtleBots against the stock profile).
WHOLE_PAGES = (REPO / "docs" / "real-robot.md",)
#: How long a node may take to register before it counts as not coming up.
NODE_START_S = 30.0


@dataclass(frozen=True)
class Block:
    """A fenced block: the page, the heading above it, its label (the text after the opening
    fence, e.g. ``robot:faulty``) and its lines, each ``\\``-continued line joined into one."""

    page: Path
    heading: str
    label: str
    lines: tuple[str, ...]

    def commands(self) -> list[str]:
        """Its non-empty lines, stripped."""
        return [line.strip() for line in self.lines if line.strip()]


def blocks(page: Path) -> list[Block]:
    """Every fenced block of `page`, in order, with the heading it stands under."""
    heading, label, out, block = "", "", [], None
    for line in page.read_text().splitlines():
        if block is None and line.startswith("#"):
            heading = line
        if line.startswith("```"):
            if block is None:
                label, block = line[3:].strip(), []
            else:
                joined = "\n".join(block).replace("\\\n", " ").splitlines()
                out.append(Block(page, heading, label, tuple(joined)))
                block = None
        elif block is not None:
            block.append(line)
    return out


def in_sequence(block: Block) -> bool:
    """Whether the block is one of :data:`SEQUENCES` or :data:`WHOLE_PAGES` (its lines run in
    order elsewhere)."""
    return block.page in WHOLE_PAGES or any(block.page == page and block.heading.startswith(heading)
               for page, heading in SEQUENCES)


def section_blocks(page: Path, heading: str) -> list[Block]:
    """The fenced blocks under `heading` of `page` (at least one)."""
    found = [b for b in blocks(page) if b.heading.startswith(heading)]
    assert found, f"{page.name}: no fenced block under {heading!r}"
    return found


def start_node(ros: RosHarness, command: str, label: str) -> Process:
    """Run `command` through bash from the repository root; wait until it registers a node."""
    before = ros.nodes()
    proc = ros.run(["bash", "-c", f"exec {command}"], label=label, cwd=REPO)
    wait_until(lambda: ros.nodes() != before, f"a node registered by {command}",
               timeout=NODE_START_S, watch=[proc], period=0.2)
    return proc


def run_in_order(ros: RosHarness, commands: list[str],
                 topics: dict[str, str] | None = None) -> list[Process]:
    """Run a scenario's lines after its ``roscore`` (the harness's) as a user would type them.

    One-shot tools (``rosparam``, ``rosservice``) run to completion (a ``rosservice call`` after
    its service appears); every other line is a node, started and waited for. ``topics`` maps
    an executable to a topic to wait for after starting it (the simulator's ``/clock`` always).
    Returns the nodes in the order of their lines.
    """
    assert commands[0] == "roscore", commands
    waits = {"sim": "/clock", **(topics or {})}
    nodes: list[Process] = []
    for line in commands[1:]:
        argv = shlex.split(line)
        if argv[0] in ("rosparam", "rosservice"):
            if argv[:2] == ["rosservice", "call"]:
                ros.wait_for_service(argv[2], timeout=60)
            ros.check_output(argv, timeout=60)
            continue
        nodes.append(start_node(ros, line, " ".join(argv[1:4])))
        if argv[2] in waits:
            ros.wait_for_topic(waits[argv[2]], timeout=60)
    return nodes


def without_comment(line: str) -> str:
    """The line without a trailing ``# comment``."""
    return re.sub(r"\s+#\s.*$", "", line).strip()
