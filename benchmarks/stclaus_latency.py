#!/usr/bin/env python3
"""Jason's ``examples/st-claus`` on Jason, on rason, and on rason with Jason's message latency:
how often santa prints ``waiting to proceed with ...``.

Santa works with one group at a time (20 rounds); a group the secretaries form while santa
works is told ``waiting to proceed with G`` and suspended until a round ends. A round is two
message hops (santa's ``proceed`` to the group, each worker's ``done`` back) and the workers
come back 10-30 ms after their ``done``: the slower a hop, the longer santa works and the more
groups find it busy. This benchmark stamps every agent line as it arrives and measures, per
round, the hop out (santa's ``Working with G`` to the first line of a member of G) and the hop
back (the last member's line to ``Group G ... has finished``). It runs Jason and rason
(alternately, ``--runs`` times each), then rason again with every message delayed by half the
difference of the two sides' median rounds (a round is two hops; or by each ``--latency-ms``
given), through an
``agentArchClass`` of rason's (``_latency_arch.delayed``) added to every agent of a copy of the
project. Nothing in rason itself is slowed down.

    python benchmarks/stclaus_latency.py JASON_TREE --classpath CP [--runs 5] [--time 3]
        [--latency-ms MS ...]

Prints one row per run (side, santa's ``waiting`` lines, its ``Working with`` lines, median
round and hop in ms) and a summary per side: ``waiting`` lines (min-max, median), round, hop,
and the p-value of the demos checker's permutation test of that side's runs against Jason's
(every agent's lines, loosened and copies merged as the checker's third verdict counts them).
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import statistics
import sys
import tempfile
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from jason_demos import LOG_CONF, copied_agents, counted_as_varying, permutation_p, run_for

#: the example's folder in a Jason source tree, and its project
EXAMPLE = Path("examples/st-claus")
MAS2J = "jason_stclaus.mas2j"
WORKING = re.compile(r"^Working with \w+: (\[[^\]]*\]) \(\d+\)$")
FINISHED = re.compile(r"^Group (\[[^\]]*\]) of \w+ has finished$")
#: an agent line of the project's ``agents:`` section: name, file and options, ``#N`` copies
AGENT_DEF = re.compile(r"^(\s+\w+\b[^;#]*?)\s*(#\s*\d+)?\s*;", re.M)
HERE = Path(__file__).resolve().parent


@dataclass
class Stamped:
    """One run's agent lines, each as (seconds from the first agent line, agent, text)."""

    lines: list[tuple[float, str, str]]


@dataclass
class RunFigures:
    """What a run's lines tell: santa's counts and the time of its rounds."""

    side: str
    waiting: int
    working: int
    round_ms: list[float] = field(default_factory=list)
    hop_ms: list[float] = field(default_factory=list)
    #: every agent's lines as the demos checker's third verdict counts them (loosened, the
    #: copies of an agent as one), for the permutation test against Jason's runs
    lines: dict[str, Counter] = field(default_factory=dict)


def run_stamped(cmd: list[str], cwd: Path, seconds: float, env: dict[str, str] | None = None,
                start_limit: float = 30.0) -> Stamped:
    """Run ``cmd`` until it ends or ``seconds`` after its first agent line (``start_limit``
    seconds without any), its agent lines stamped as they arrived."""
    return Stamped(run_for(cmd, cwd, seconds, start_limit, env).agent_lines(seconds))


def figures(side: str, run: Stamped, families: list[str]) -> RunFigures:
    """Santa's ``waiting`` and ``Working with`` lines, per round its length and hops, and every
    agent's lines (``families``: the agents the project copies with ``#N``)."""
    santa = [(t, text) for t, agent, text in run.lines if agent == "santa"]
    printed = "".join(f"[{agent}] {text}\n" for _, agent, text in run.lines)
    out = RunFigures(side, sum(1 for _, text in santa if text.startswith("waiting to proceed")),
                     sum(1 for _, text in santa if WORKING.match(text)),
                     lines=counted_as_varying(printed, families))
    began: dict[str, float] = {}
    for t, text in santa:
        m = WORKING.match(text)
        if m:
            began[m.group(1)] = t
            continue
        m = FINISHED.match(text)
        if m and m.group(1) in began:
            t0 = began.pop(m.group(1))
            members = set(m.group(1).strip("[]").split(","))
            said = [tw for tw, agent, _ in run.lines if agent in members and t0 <= tw <= t]
            out.round_ms.append((t - t0) * 1000.0)
            if said:
                out.hop_ms += [(min(said) - t0) * 1000.0, (t - max(said)) * 1000.0]
    return out


def with_latency(mas_text: str, ms: float) -> str:
    """The project with ``agentArchClass _latency_arch.delayed("ms")`` on every agent."""
    return AGENT_DEF.sub(lambda m: f'{m.group(1)} agentArchClass _latency_arch.delayed("{ms:.3f}")'
                         f'{" " + m.group(2) if m.group(2) else ""};', mas_text)


def med(values: list[float]) -> float:
    return statistics.median(values) if values else float("nan")


def row(f: RunFigures, label: str) -> str:
    return (f"| {label} | {f.waiting} | {f.working} | {med(f.round_ms):.2f} | "
            f"{med(f.hop_ms):.2f} |")


def summary(label: str, runs: list[RunFigures], jason: list[RunFigures] | None = None) -> str:
    """A side's row; with ``jason``, the permutation test's p of ``runs`` against those."""
    waits = [f.waiting for f in runs]
    rounds = [r for f in runs for r in f.round_ms]
    hops = [h for f in runs for h in f.hop_ms]
    p = "" if jason is None else f"{permutation_p([f.lines for f in jason], [f.lines for f in runs]):.3f}"
    return (f"| {label} | {len(runs)} | {min(waits)}-{max(waits)} | {med(waits):g} | "
            f"{med(rounds):.2f} | {med(hops):.2f} | {p} |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tree", type=Path, help="a Jason source tree")
    ap.add_argument("--classpath", required=True, help="the class path of a Jason build")
    ap.add_argument("--runs", type=int, default=5, help="runs of each side")
    ap.add_argument("--time", type=float, default=3.0,
                    help="seconds from a run's first agent line (the 20 rounds take < 1 s)")
    ap.add_argument("--latency-ms", type=float, action="append",
                    help="delay rason's messages by this (repeatable); default: the difference "
                         "of the median rounds measured here, halved")
    args = ap.parse_args()
    folder = args.tree / EXAMPLE
    java = ["java", "-cp", args.classpath, "jason.infra.local.RunLocalMAS", MAS2J,
            "--log-conf", str(args.tree / LOG_CONF)]
    rason = [sys.executable, "-m", "rason.asl", "run", "--timeout", str(args.time + 30), MAS2J]
    env = dict(os.environ, PYTHONUNBUFFERED="1",
               PYTHONPATH=os.pathsep.join(filter(None, [str(HERE), os.environ.get("PYTHONPATH")])))
    jason_runs: list[RunFigures] = []
    plain_runs: list[RunFigures] = []
    delayed_runs: dict[float, list[RunFigures]] = {}
    with tempfile.TemporaryDirectory(prefix="stclaus-") as tmp:
        work = Path(tmp) / "st-claus"
        shutil.copytree(folder, work)
        original = (work / MAS2J).read_text()
        families = copied_agents(original)
        print("| run | santa's `waiting` lines | `Working with` lines | median round (ms) | "
              "median hop (ms) |")
        print("|---|---|---|---|---|")
        for n in range(args.runs):
            jason_runs.append(figures("jason", run_stamped(java, work, args.time), families))
            print(row(jason_runs[-1], f"jason {n}"), flush=True)
            plain_runs.append(figures("rason", run_stamped(rason, work, args.time, env), families))
            print(row(plain_runs[-1], f"rason {n}"), flush=True)
        # a round is two hops (proceed out, done back): half the rounds' difference a message
        measured = max(0.0, (med([r for f in jason_runs for r in f.round_ms])
                             - med([r for f in plain_runs for r in f.round_ms])) / 2.0)
        latencies = args.latency_ms or [measured]
        for ms in latencies:
            (work / MAS2J).write_text(with_latency(original, ms))
            delayed_runs[ms] = []
            for n in range(args.runs):
                delayed_runs[ms].append(figures("rason", run_stamped(rason, work, args.time, env), families))
                print(row(delayed_runs[ms][-1], f"rason +{ms:.2f} ms {n}"), flush=True)
    print(f"\nmeasured: half of Jason's median round minus rason's = {measured:.2f} ms a message")
    print("\n| side | runs | santa's `waiting` lines | median | median round (ms) | median hop (ms) "
          "| p, its runs drawn as Jason's |")
    print("|---|---|---|---|---|---|---|")
    print(summary("Jason", jason_runs))
    print(summary("rason", plain_runs, jason_runs))
    for ms, runs in delayed_runs.items():
        print(summary(f"rason, messages +{ms:.2f} ms", runs, jason_runs))
    return 0


if __name__ == "__main__":
    sys.exit(main())
