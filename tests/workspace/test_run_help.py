"""``./run.sh --help`` lists every command and every option users have; ``./run.sh bench`` with
no name (or an unknown one) lists the benchmarks and exits 2.

The options are those of the demo's, the campaign's and the mission's own parsers (``--help`` of
``python -m rason_diagnosis``, ``python -m rason_diagnosis.campaign`` and
``python -m rason_diagnosis.mission``), so an option added
there and not to run.sh's help fails here.
"""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
RUN = str(REPO / "run.sh")
COMMANDS = ("demo", "campaign", "mission", "bench", "test", "env")
#: benchmarks/_name.py is code the benchmarks share, not a benchmark
BENCHMARKS = sorted(p.stem for p in (REPO / "benchmarks").glob("*.py") if not p.stem.startswith("_"))


def _run(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([RUN, *args], capture_output=True, text=True, timeout=60, cwd=REPO)


def _options(module: str, *args: str) -> set[str]:
    """The long options of a module's argparse parser, from its --help (after `args`)."""
    out = subprocess.run([sys.executable, "-m", module, *args, "--help"], capture_output=True,
                         text=True, timeout=60, check=True).stdout
    return set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", out)) - {"--help"}


@pytest.mark.parametrize("flag", ["--help", "-h", "help"])
def test_help_lists_every_command_and_nothing_of_the_script(flag):
    done = _run(flag)
    assert done.returncode == 0, done.stderr
    assert "set -eo pipefail" not in done.stdout and "#" not in done.stdout
    for command in COMMANDS:
        assert f"./run.sh {command}" in done.stdout, command


@pytest.mark.parametrize(("module", "args", "own"), [
    ("rason_diagnosis", (), "--hosts"),
    ("rason_diagnosis", ("--real",), "--robots-timeout"),
    ("rason_diagnosis.campaign", (), "--hosts"),
    ("rason_diagnosis.mission", (), "--seed"),
])
def test_help_lists_every_option_of_the_demo_the_campaign_and_the_mission(module, args, own):
    options = _options(module, *args)
    assert {"--out", own} <= options
    shown = set(re.findall(r"(?<![\w-])--[a-z][a-z-]*", _run("--help").stdout))
    assert not options - shown, (f"./run.sh --help misses {sorted(options - shown)} of "
                                 f"{module} {' '.join(args)}")


def test_the_demo_s_help_names_the_real_robots_mode():
    assert "--real" in _options("rason_diagnosis")


def test_the_workstation_mode_watches_as_the_demo_does():
    """``demo --real`` declares the inspector's watch with the demo's own options."""
    watch = {"--inspector", "--no-inspector", "--inspector-port", "--hold"}
    assert watch <= _options("rason_diagnosis", "--real")
    assert watch <= _options("rason_diagnosis")


@pytest.mark.parametrize("args", [(), ("no_such_benchmark",), ("_moving",)])
def test_bench_without_a_known_name_lists_the_benchmarks_and_exits_2(args):
    done = _run("bench", *args)
    assert done.returncode == 2
    assert "usage: ./run.sh bench NAME" in done.stderr or "no benchmark named" in done.stderr
    listed = re.findall(r"^  (\w+) ", done.stderr, flags=re.M)
    assert listed == BENCHMARKS, done.stderr
    assert "unbound variable" not in done.stderr and "parameter null" not in done.stderr
