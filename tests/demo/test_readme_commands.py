"""Every ``rosrun`` and ``./run.sh`` line in the fenced blocks of README and docs/*.md works as written.

The blocks that are one scenario each (doc_commands.SEQUENCES: README's first agent, the case
study by hand) run line after line in test_first_agent.py and test_manual.py. Every other line
runs here exactly as typed, through bash from the repository root:

* ``./run.sh demo ...`` to the end: exit status 0 (the diagnosis was right);
* ``./run.sh campaign|bench|mission ...``: too long for the suite (a mission takes minutes and
  test_mission.py runs it end to end), so their arguments are checked by running the line with
  ``--help`` appended (argparse parses the given arguments first);
* ``./run.sh test``: this suite itself (not run again);
* ``rosrun ...``: against a private roscore; a one-shot tool must exit 0, a node must come up
  (register with the master and stay up) until it is stopped. A node failing on start (a bad
  parameter, a missing file) fails before it registers its own topics and services (the
  nodes here read and check their parameters and files first): those registrations are the
  sentinel after which it must still run.

Lines with placeholders (``FILE``, ``NAME``, ``[optional]``, ``a|b``) are templates, not commands,
and are not run.
"""

from __future__ import annotations

import re

import pytest
from doc_commands import NODE_START_S, PAGES, README, REPO, blocks, in_sequence, without_comment
from polling import wait_until

from rason.process.harness import RosHarness

pytestmark = [pytest.mark.ros, pytest.mark.demo]
#: the services ``init_node`` gives every node (rospy and roscpp), under its name
INIT_SERVICES = ("get_loggers", "set_logger_level")


def _is_template(command: str) -> bool:
    return bool(re.search(r"\[|\||\b[A-Z]{2,}[A-Z_]*\b(?!=)", command.replace("$(rospack", "")))


def own_registrations(ros: RosHarness, node: str) -> set[str]:
    """What ``node`` registered beyond what every node's ``init_node`` does (rospy's and
    roscpp's: the ``/rosout`` publisher and the ``~get_loggers``, ``~set_logger_level``
    services), i.e. what it registers once its own start has read its parameters."""
    return {name for name in ros.registrations(node)
            if name != "/rosout" and name not in (f"{node}/{s}" for s in INIT_SERVICES)}


def page_commands() -> list[tuple[str, str]]:
    """(page, command) of every command line to run here."""
    commands = []
    for page in PAGES:
        for block in blocks(page):
            if in_sequence(block):
                continue
            for line in block.lines:
                command = without_comment(line)
                if command.startswith(("rosrun ", "./run.sh ")) and not _is_template(command):
                    commands.append((page.relative_to(REPO).as_posix(), command))
    return commands


COMMANDS = page_commands()


def test_readme_shows_the_two_commands():
    readme = README.relative_to(REPO).as_posix()
    assert (readme, "./run.sh demo") in COMMANDS and (readme, "./run.sh test") in COMMANDS


@pytest.mark.parametrize(("page", "command"), COMMANDS)
def test_page_command_works_as_written(page, command, tmp_path):
    verb = command.split()[1] if command.startswith("./run.sh") else "rosrun"
    if verb == "test":
        return                              # the suite running this test
    with RosHarness(log_dir=tmp_path / "logs") as ros:
        if verb in ("campaign", "bench", "mission"):
            out = ros.check_output(["bash", "-c", f"{command} --help"], timeout=120)
            assert "usage" in out.lower()
        elif verb != "rosrun":
            proc = ros.run(["bash", "-c", command], label=command[:40], cwd=REPO)
            assert proc.wait(timeout=400) == 0, proc.output()[-3000:]
        else:
            before = ros.nodes()

            def started() -> bool:
                return any(own_registrations(ros, node) for node in ros.nodes() - before)
            proc = ros.run(["bash", "-c", f"exec {command}"], label=command[:40], cwd=REPO)
            wait_until(lambda: not proc.alive() or started(),
                       f"{command}: a node's own topics or services (or the command done)",
                       timeout=NODE_START_S, period=0.2)
            if not proc.alive():                # a one-shot tool, done (or a node that failed)
                assert proc.wait(timeout=5) == 0, proc.output()[-3000:]
