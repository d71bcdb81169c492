"""The command line's quick reading of ``run FILE [options]`` (:func:`rason.asl.cli.quick_run_args`,
which spares a lone agent's start argparse) gives what argparse gives, or leaves the words to it."""

from __future__ import annotations

import itertools
import subprocess
import sys

import pytest

from rason.asl.cli import arg_parser, quick_run_args

OPTIONS = [[], ["--timeout", "2.5"], ["--timeout=1e3"], ["--seed", "7"], ["--seed=-3"], ["--no-tro"],
           ["--max-intention-depth", "40"], ["--internal-actions", "my.acts"],
           ["--internal-actions=a", "--internal-actions", "b"], ["--source-path", "some dir"],
           ["--source-path="], ["--seed", "1", "--seed", "2"]]


def parsed(argv: list[str]) -> dict:
    """What argparse makes of ``argv``."""
    return vars(arg_parser().parse_args(argv))


@pytest.mark.parametrize("first,second", list(itertools.combinations(OPTIONS, 2)))
def test_plain_run_words_read_as_argparse_reads_them(first: list[str], second: list[str]) -> None:
    for argv in (["run", "a.asl", *first, *second], ["run", *first, "b.mas2j", *second],
                 ["run", *second, *first, "c d.asl"]):
        quick = quick_run_args(argv)
        assert quick is not None, argv
        assert vars(quick) == parsed(argv), argv


@pytest.mark.parametrize("argv", [
    [], ["run"], ["run", "-h"], ["run", "a.asl", "--help"], ["native", "status"],
    ["run", "a.asl", "b.asl"], ["run", "--time", "3", "a.asl"], ["run", "a.asl", "--seed", "x"],
    ["run", "a.asl", "--seed", "-1"], ["run", "--", "a.asl"], ["run", "-", "a.asl"],
    ["run", "a.asl", "--timeout"], ["run", "a.asl", "--no-tro=1"], ["run", "a.asl", "--timeout="]])
def test_other_words_are_left_to_argparse(argv: list[str]) -> None:
    assert quick_run_args(argv) is None


def test_a_lone_agent_starts_without_argparse(tmp_path) -> None:
    agent = tmp_path / "lone.asl"
    agent.write_text("!start.\n+!start <- .print(done).\n", encoding="utf-8")
    done = subprocess.run([sys.executable, "-c", "import sys\nfrom rason.asl.cli import main\n"
                           "code = main(['run', sys.argv[1], '--timeout', '30'])\n"
                           "print(code, 'argparse' in sys.modules)", str(agent)],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-3:] == ["done", "0", "False"], done.stdout
