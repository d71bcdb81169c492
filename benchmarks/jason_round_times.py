#!/usr/bin/env python3
"""Jason's ``demos/current-intention`` on Jason and on rason: how many rounds each runs in the
same time, and what a round costs beyond its ``.wait``.

Each of the demo's four goals ``!start(X)`` goes round printing ``X``, waiting 1-2 s (a random
``.wait``), inspecting its intention (``!inspect``, which prints the other goals' states, their
waits among them) and starting again. A run goes on for ``--time`` seconds from the first line
its agent prints (the time base of ``jason_demos.py``); every line is stamped as it arrives.
A round of goal X runs from one print of ``X`` to the next; its wait is read from the demo's
own lines (``another goal is start(X)[source(self)] in state
waiting[reason(wait(N)[time(T)])]``, printed by another goal meanwhile), and what the round
took beyond it is the cost of its deeds and of the reasoning cycles around them.

    python benchmarks/jason_round_times.py JASON_TREE --classpath CP [--runs 3] [--time 15]

Prints one row per run (Jason and rason alternate): rounds begun, lines printed, and a round's
cost beyond its wait (median, mean, most, in ms, over the rounds whose wait was seen).
"""

from __future__ import annotations

import argparse
import itertools
import os
import re
import shutil
import statistics
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from jason_demos import LOG_CONF, run_for

#: the demo's folder in a Jason source tree, and its project
DEMO = Path("demos/current-intention")
MAS2J = "current_intention.mas2j"
#: seconds a run may take to print its first line
START_LIMIT = 30.0
#: the line a round starts with, and the line showing another goal's wait
ROUND = re.compile(r"^\[sample_agent\] ([a-z])$")
WAIT = re.compile(r"another goal is start\(([a-z])\)\[source\(self\)\] in state "
                  r"waiting\[reason\(wait\(\d+\)\[time\((\d+)\)\]\)\]")


@dataclass
class Rounds:
    """What a run's lines tell of its rounds."""

    begun: int                  # rounds begun (prints of a goal's name)
    lines: int                  # agent lines printed
    beyond_wait: list[float]    # ms each round took beyond its wait (rounds whose wait was seen)


def rounds(stamped: list[tuple[float, str]], seconds: float) -> Rounds:
    """The rounds of the lines ``stamped`` (seconds from the first agent line, text) printed
    within ``seconds``."""
    starts: dict[str, list[list]] = {}      # goal -> [start time, wait ms or None] per round
    shown = [(t, line) for t, line in stamped if t <= seconds]
    for t, line in shown:
        m = ROUND.match(line)
        if m:
            starts.setdefault(m.group(1), []).append([t, None])
            continue
        m = WAIT.search(line)
        if m and starts.get(m.group(1)):
            starts[m.group(1)][-1][1] = int(m.group(2))
    beyond = [(t2 - t1) * 1000.0 - wait
              for goal in starts.values() for (t1, wait), (t2, _) in itertools.pairwise(goal)
              if wait is not None]
    return Rounds(sum(len(goal) for goal in starts.values()),
                  sum(1 for _, line in shown if line.startswith("[sample_agent]")), beyond)


def stamped_lines(cmd: list[str], cwd: Path, seconds: float,
                  env: dict[str, str] | None = None) -> list[tuple[float, str]]:
    """The demo agent's lines ``cmd`` prints, each with its time from the first one, until
    ``seconds`` after the first (or 30 s without any)."""
    run = run_for(cmd, cwd, seconds, START_LIMIT, env)
    return [(t, f"[{agent}] {text}") for t, agent, text in run.agent_lines(seconds)
            if agent == "sample_agent"]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tree", type=Path, help="a Jason source tree (jason-lang/jason checkout)")
    ap.add_argument("--classpath", required=True, help="class path of a Jason build (java -cp)")
    ap.add_argument("--runs", type=int, default=3, help="runs of each side")
    ap.add_argument("--time", type=float, default=15.0, help="seconds from the first line")
    args = ap.parse_args()
    java = ["java", "-cp", args.classpath, "jason.infra.local.RunLocalMAS", MAS2J,
            "--log-conf", str(args.tree.resolve() / LOG_CONF)]
    rason = [sys.executable, "-m", "rason.asl", "run", MAS2J]
    unbuffered = {**os.environ, "PYTHONUNBUFFERED": "1"}
    print("side  | rounds | lines | beyond the wait, ms: median | mean | most")
    with tempfile.TemporaryDirectory(prefix="jason-rounds-") as tmp:
        work = Path(tmp) / "demo"
        shutil.copytree(args.tree / DEMO, work)
        for _ in range(args.runs):
            for side, cmd, env in (("jason", java, None), ("rason", rason, unbuffered)):
                seen = rounds(stamped_lines(cmd, work, args.time + 0.5, env), args.time)
                b = seen.beyond_wait or [float("nan")]
                print(f"{side} | {seen.begun} | {seen.lines} | {statistics.median(b):.1f} | "
                      f"{statistics.mean(b):.1f} | {max(b):.1f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
