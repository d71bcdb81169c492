#!/usr/bin/env python3
"""The projects that ship with Jason, run on Jason and on rason, what each agent prints compared.

Takes the path of a Jason source tree (a checkout of jason-lang/jason, kept outside this
repository) and the class path of a Jason build. Every ``.mas2j`` project of ``demos/``,
``examples/`` and ``doc/tutorials/`` that needs no Java class of its own (no ``.java`` file in
its folder, no ``environment:``, no agent, architecture or belief-base class, no CArtAgO)
runs for a fixed time on Jason (``--jason-runs`` times: Jason's own scheduling varies from run
to run) and once on rason (``python -m rason.asl run``), each in a copy of its folder. Both run
every agent in one process: Jason's ``RunLocalMAS`` so runs a project written for JADE
(``demos/distributed-jade/case1``), and rason notes the infrastructure and the hosts ignored.

A project is the same (the strict verdict) when, for every agent, the lines it printed
(``[agent] text``; variable numbers such as ``_32`` made alike) form the same multiset on rason
as on one of Jason's runs. Jason's own runs of a project may differ from each other (random
offers, milliseconds, scheduling): the table says whether they agreed, and gives a second,
looser verdict, "same up to numbers and list order": every number of a line made ``#`` and the
items of each innermost ``[...]`` list sorted, then compared as before. A third verdict,
"within Jason's variation", takes also the copies that ``#N`` makes of an agent as one (``p2``
is ``p#``, in the lines and as the agent who printed them) and asks, for every agent and every
line so loosened, that rason print it at least as often as the Jason run that printed it least
and at most as often as the one that printed it most (a line every Jason run printed must be
there, one no Jason run printed must not). That test fails a run of Jason itself too, often,
when a program is random (which goal's wait ends first): a fourth column ranks rason's run
among Jason's, each run's lines outside the range of all the other runs counted alike, and
gives how many of Jason's runs are at least as far off as rason's (0: rason's run is the least
typical of all, as a run of Jason itself would be once in ``--jason-runs`` + 1). The strict
verdict stays the one counted first. With ``--rason-runs N`` rason runs N times (the verdicts
are the first run's) and a further column gives the p-value of an exact permutation test of
"rason's runs are drawn as Jason's are" (:func:`permutation_p`, on the loosened lines with
copies merged): a p below ``SIGNIFICANCE`` tells the two sides apart, beyond Jason's own
variation. It needs enough runs to say so (:func:`smallest_p`: 1/126 for 5 and 5).
A project whose Jason runs all show a defect of Jason documented in KNOWN_JASON_DEFECTS (and
docs/jason-compatibility.md), and whose rason output is Jason's plus exactly the lines the
defect keeps Jason from printing, is still "no" in every column; the table names the defect.

    python benchmarks/jason_demos.py JASON_TREE --classpath CP [--time S] [--jason-runs N]
        [--rason-runs N] [-k NAME] [--keep DIR] [--start-limit S]

The time base: each run goes on for ``--time`` seconds from the first line an agent prints,
so that neither side's start-up counts (Jason's JVM and MAS take about a second before the
first line, rason about a tenth); a run that prints no agent line within ``--start-limit``
seconds goes on for ``--time`` seconds from then. The summary gives each side's median
time to its first line. ``--keep DIR`` keeps every run's output (``DIR/PROJECT/RUN/all.txt``,
one ``AGENT.txt`` per agent with its lines as printed).

Prints the Jason version the tree names (``jasonVersion`` of its ``gradle.properties``), then a
table: project | agents | Jason's runs agree? | same? | same up to numbers and list order? |
within Jason's variation? | Jason's runs as far off as rason's | p, rason's runs drawn as
Jason's | first difference (strict).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from itertools import combinations
from pathlib import Path

#: folders of the source tree whose projects are run
PROJECT_FOLDERS = ("demos", "examples", "doc/tutorials")
#: what in a ``.mas2j`` file (comments removed) names a Java class that is not Jason's own, or
#: CArtAgO. An infrastructure (``Jade(...)``, agents ``at "host"``) needs none: Jason's
#: ``RunLocalMAS`` runs such a project in one JVM, as rason runs it in one process
NEEDS_JAVA = re.compile(r"(\benvironment\s*:|agentClass|agentArchClass|beliefBaseClass)\s*(?![\s]|jason\.)"
                        r"|cartago", re.I)
COMMENT = re.compile(r"/\*.*?\*/|//[^\n]*", re.S)
#: the console logging set-up of Jason (inside the source tree)
LOG_CONF = "jason-interpreter/src/main/resources/templates/console-info-logging.properties"
#: the file of a Jason source tree that names its version, and that line (``jasonVersion=3.2.2``)
VERSION_FILE = "gradle.properties"
VERSION_LINE = re.compile(r"^\s*jasonVersion\s*=\s*(\S+)", re.M)
#: a line an agent printed (agent names are atoms: ``[TextPersistentBB]`` is a Java logger's)
AGENT_LINE = re.compile(r"^\[([a-z][^\]\s]*)\] (.*)$")
VAR_NUMBER = re.compile(r"\b_\d+")
#: a number in a printed line (for the loose verdict), not inside a word such as ``p2``
NUMBER = re.compile(r"(?<![\w.])-?\d+(\.\d+)?([eE][-+]?\d+)?(?![\w.])")
#: an innermost list in a printed line: ``[a,b,c]`` holding no other list
INNER_LIST = re.compile(r"\[([^\[\]]*)\]")
#: the permutation test's level: p below it tells rason's runs apart from Jason's
SIGNIFICANCE = 0.05
#: an agent line of a ``.mas2j`` (one ``;``-separated item) that makes copies: ``p #3``
COPIES = re.compile(r"\b([a-z]\w*)\b[^#:]*#\s*(\d+)\s*$")


@dataclass(frozen=True)
class JasonDefect:
    """A defect of Jason 3.3 that changes what a project prints (see docs/jason-compatibility.md)."""

    #: text in Jason's output (stdout and stderr) that shows the defect happened
    sign: str
    #: agent lines (``[agent] text``) the project documents and the defect keeps Jason from printing
    missing: tuple[str, ...]
    #: the table's note
    note: str


#: per project (path in the tree): the Jason defect its differences come from
KNOWN_JASON_DEFECTS = {
    "demos/hard_deadline/hard_deadline.mas2j": JasonDefect(
        sign='Cannot invoke "jason.asSemantics.IntendedMeans.getPlan()"',
        missing=("[bob] failed, deadline_reached for g(9)",),
        note="Jason 3.3 defect: NullPointerException failing a goal at the bottom of its "
             "intention (TransitionSystem.getPLForIM); rason prints the demo's documented line"),
}


@dataclass
class StartUp:
    """Seconds from launch to the first agent line, of Jason's runs and of rason's."""

    jason: list[float]
    rason: list[float]


@dataclass
class Outcome:
    """One project's comparison."""

    project: str
    agents: int
    same: bool
    difference: str
    #: the loose verdict: the same with numbers made ``#`` and list items sorted
    same_loosely: bool = False
    #: Jason's runs of the project printed the same (strictly)
    jason_agrees: bool = True
    #: every loosened line printed as often as between the fewest and most times of Jason's runs
    within_variation: bool = False
    #: when each side's first agent line came
    start_up: StartUp = field(default_factory=lambda: StartUp([], []))
    #: the note of a documented Jason defect that explains every difference ("" if none)
    jason_defect: str = ""
    #: :func:`as_atypical`: Jason's runs at least as far outside the others' variation as
    #: rason's (all of them when rason printed the same as one, up to numbers and list order)
    typical: int = 0
    #: :func:`permutation_p` of all rason's runs against Jason's (1.0 with one run of each)
    p_value: float = 1.0


def find_projects(tree: Path) -> list[Path]:
    """The ``.mas2j`` files of the tree's project folders that need no Java class of their own."""
    found = []
    for folder in PROJECT_FOLDERS:
        for mas in sorted((tree / folder).rglob("*.mas2j")):
            if any(mas.parent.rglob("*.java")):
                continue
            if NEEDS_JAVA.search(COMMENT.sub("", mas.read_text(errors="replace"))):
                continue
            found.append(mas)
    return found


@dataclass
class Run:
    """What one run printed, and when its first agent line came."""

    output: str
    #: seconds from the launch to the first agent line (None: no agent line)
    first_line: float | None
    #: each line printed (newline removed), with the seconds from the launch it arrived at
    stamped: list[tuple[float, str]] = field(default_factory=list)

    def agent_lines(self, seconds: float | None = None) -> list[tuple[float, str, str]]:
        """The agent lines as (seconds from the first agent line, agent, text); with
        ``seconds``, only those that came within that time of the first."""
        found = [(t, m.group(1), m.group(2)) for t, line in self.stamped
                 if (m := AGENT_LINE.match(line))]
        first = found[0][0] if found else 0.0
        return [(t - first, agent, text) for t, agent, text in found
                if seconds is None or t - first <= seconds]


def run_for(cmd: list[str], cwd: Path, seconds: float, start_limit: float,
            env: dict[str, str] | None = None) -> Run:
    """Run ``cmd`` in ``cwd`` for ``seconds`` from its first agent line (the time base both
    sides share: Jason's JVM and MAS start-up is not counted, nor rason's); when no agent line
    comes within ``start_limit`` seconds, for ``seconds`` from then. Returns what it printed
    (stdout and stderr) and when its first agent line came."""
    start = time.monotonic()
    chunks: list[str] = []
    stamped: list[tuple[float, str]] = []
    first: list[float] = []
    with subprocess.Popen(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          stdin=subprocess.DEVNULL, start_new_session=True, env=env) as proc:
        def read() -> None:
            assert proc.stdout is not None
            for raw in proc.stdout:
                now, line = time.monotonic(), raw.decode(errors="replace")
                if not first and AGENT_LINE.match(line.rstrip()):
                    first.append(now)
                chunks.append(line)
                stamped.append((now - start, line.rstrip("\n")))
        reader = threading.Thread(target=read, daemon=True)
        reader.start()
        try:
            while proc.poll() is None:
                now = time.monotonic()
                if first and first[0] - start <= start_limit:
                    anchor = first[0]
                elif now - start < start_limit:
                    anchor = now                       # no agent line yet: still starting
                else:
                    anchor = start + start_limit
                if now >= anchor + seconds:
                    break
                time.sleep(0.02)
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
                try:
                    proc.wait(timeout=5)
                except subprocess.TimeoutExpired:
                    os.killpg(proc.pid, signal.SIGKILL)
            reader.join(timeout=10)
        finally:   # this script stopped (Ctrl-C): the run must not outlive it
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
    return Run("".join(chunks), first[0] - start if first else None, stamped)


def keep_run(keep: Path | None, project: str, run: str, output: str) -> None:
    """With ``--keep``: the run's whole output as ``KEEP/PROJECT/RUN/all.txt`` and each agent's
    lines, as printed, as ``KEEP/PROJECT/RUN/AGENT.txt``."""
    if keep is None:
        return
    folder = keep / project.replace("/", "__").removesuffix(".mas2j") / run
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "all.txt").write_text(output)
    for agent, said in agent_lines(output).items():
        (folder / f"{agent}.txt").write_text("".join(line + "\n" for line in said))


def agent_lines(output: str) -> dict[str, list[str]]:
    """The lines each agent printed (``[agent] text``: the text), in order."""
    agents: dict[str, list[str]] = {}
    for line in output.splitlines():
        m = AGENT_LINE.match(line.rstrip())
        if m:
            agents.setdefault(m.group(1), []).append(m.group(2))
    return agents


def per_agent(output: str) -> dict[str, Counter]:
    """The lines each agent printed, as multisets (variable numbers made alike)."""
    return {agent: Counter(VAR_NUMBER.sub("_", line) for line in said)
            for agent, said in agent_lines(output).items()}


def loosened(line: str) -> str:
    """``line`` with every number made ``#`` and the items of each innermost list sorted."""
    line = NUMBER.sub("#", line)
    return INNER_LIST.sub(lambda m: "[" + ",".join(sorted(top_level_items(m.group(1)))) + "]", line)


def top_level_items(text: str) -> list[str]:
    """The comma-separated items of ``text``, commas inside parentheses or quotes kept."""
    items, depth, quoted, start = [], 0, False, 0
    for k, ch in enumerate(text):
        if ch == '"':
            quoted = not quoted
        elif not quoted and ch == "(":
            depth += 1
        elif not quoted and ch == ")":
            depth -= 1
        elif not quoted and depth == 0 and ch == ",":
            items.append(text[start:k])
            start = k + 1
    items.append(text[start:])
    return items


def loosen(agents: dict[str, Counter]) -> dict[str, Counter]:
    """Each agent's lines loosened (:func:`loosened`)."""
    out: dict[str, Counter] = {}
    for agent, counted in agents.items():
        c: Counter = Counter()
        for line, n in counted.items():
            c[loosened(line)] += n
        out[agent] = c
    return out


def copied_agents(mas_text: str) -> list[str]:
    """The names of the agents a ``.mas2j`` makes copies of with ``#N`` (``p`` for ``p #3``)."""
    names = []
    for item in COMMENT.sub("", mas_text).split(";"):
        m = COPIES.search(item)
        if m:
            names.append(m.group(1))
    return names


def merge_copies(agents: dict[str, Counter], families: list[str]) -> dict[str, Counter]:
    """``agents`` with each copy's number made ``#`` (``p2`` is ``p#``), as agent and in lines."""
    if not families:
        return agents
    copy = re.compile(r"\b(" + "|".join(re.escape(f) for f in families) + r")\d+\b")
    out: dict[str, Counter] = {}
    for agent, counted in agents.items():
        c = out.setdefault(copy.sub(r"\1#", agent), Counter())
        for line, n in counted.items():
            c[copy.sub(r"\1#", line)] += n
    return out


def counted_as_varying(output: str, families: list[str]) -> dict[str, Counter]:
    """What a run printed as the third verdict and the permutation test count it: each agent's
    lines loosened, the copies ``#N`` makes of an agent (``families``) as one."""
    return merge_copies(loosen(per_agent(output)), families)


def within_variation(runs: list[dict[str, Counter]], ours: dict[str, Counter]) -> bool:
    """Does every agent print each line as often as between the fewest and the most times of
    Jason's ``runs``?  (Each side already loosened and its copies merged.)"""
    return lines_outside(ours, runs) == 0


def lines_outside(run: dict[str, Counter], others: list[dict[str, Counter]]) -> int:
    """How many of ``run``'s lines fall outside the range ``others`` span: for every agent and
    line, the count below the fewest or above the most of ``others`` (0: within their variation)."""
    keys = {(a, line) for side in (*others, run) for a, c in side.items() for line in c}
    outside = 0
    for agent, line in keys:
        counts = [o.get(agent, Counter())[line] for o in others]
        n = run.get(agent, Counter())[line]
        outside += max(0, min(counts) - n, n - max(counts))
    return outside


def as_atypical(runs: list[dict[str, Counter]], ours: dict[str, Counter]) -> int:
    """How many of Jason's ``runs`` are at least as far outside the others' variation as rason's
    run is (:func:`lines_outside`, each run scored against all the other runs, Jason's and
    rason's alike). 0: rason's run is the least typical of all, which a run of Jason itself
    would be once in ``len(runs) + 1`` (a rank test; each side already loosened and its
    copies merged)."""
    every = [*runs, ours]
    scores = [lines_outside(r, every[:i] + every[i + 1:]) for i, r in enumerate(every)]
    return sum(s >= scores[-1] for s in scores[:-1])


def distance(a: dict[str, Counter], b: dict[str, Counter]) -> int:
    """How many line printings separate two runs: for every agent and line, the difference of
    the times each run printed it."""
    total = 0
    for agent in set(a) | set(b):
        x, y = a.get(agent, Counter()), b.get(agent, Counter())
        total += sum(abs(x[line] - y[line]) for line in set(x) | set(y))
    return total


def permutation_p(jason: list[dict[str, Counter]], rason: list[dict[str, Counter]]) -> float:
    """The p-value of an exact permutation test of "rason's runs are drawn as Jason's are".

    The statistic is the energy distance of the two groups of runs (:func:`distance`): twice
    the mean distance between a run of one and a run of the other, less the mean distance
    within each group. Under the hypothesis every split of the pooled runs into groups of these
    sizes is as likely, so p is the share of the splits whose statistic is at least the
    observed one, at least :func:`smallest_p`; a project Jason and rason print alike gets 1.0."""
    runs = [*jason, *rason]
    far = [[distance(a, b) for b in runs] for a in runs]

    def mean(pairs: list[tuple[int, int]]) -> float:
        return sum(far[i][j] for i, j in pairs) / len(pairs) if pairs else 0.0

    def energy(group: tuple[int, ...]) -> float:
        chosen = set(group)
        other = [k for k in range(len(runs)) if k not in chosen]
        return (2 * mean([(i, j) for i in group for j in other])
                - mean(list(combinations(group, 2))) - mean(list(combinations(other, 2))))

    observed = energy(tuple(range(len(jason), len(runs))))
    splits = [energy(group) for group in combinations(range(len(runs)), len(rason))]
    return sum(e >= observed - 1e-9 for e in splits) / len(splits)


def smallest_p(jason_runs: int, rason_runs: int) -> float:
    """The smallest p :func:`permutation_p` can give: the observed split alone, with its mirror
    image when both groups have the same size (the statistic is symmetric in them)."""
    mirrored = 2 if jason_runs == rason_runs else 1
    return mirrored / math.comb(jason_runs + rason_runs, rason_runs)


def same_lines(a: dict[str, Counter], b: dict[str, Counter]) -> bool:
    """Did every agent print the same multiset of lines in both?"""
    return all(a.get(x, Counter()) == b.get(x, Counter()) for x in set(a) | set(b))


def first_difference(jason: dict[str, Counter], rason: dict[str, Counter]) -> str:
    """The first agent line that one side printed more often than the other, shortened."""
    for agent in sorted(set(jason) | set(rason)):
        j, r = jason.get(agent, Counter()), rason.get(agent, Counter())
        if j == r:
            continue
        extra, missing = r - j, j - r
        if missing:
            text = f"{agent}: rason lacks {next(iter(missing))!r}"
        else:
            text = f"{agent}: rason adds {next(iter(extra))!r}"
        return text if len(text) <= 110 else text[:107] + "..."
    return ""


def compare(mas: Path, tree: Path, args: argparse.Namespace) -> Outcome:
    """Run one project on both and compare what its agents print."""
    name = str(mas.relative_to(tree))
    java = ["java", "-cp", args.classpath, "jason.infra.local.RunLocalMAS", mas.name,
            "--log-conf", str(tree / LOG_CONF)]
    rason = [sys.executable, "-m", "rason.asl", "run", mas.name]
    # rason's lines reach the pipe as printed, as Jason's do (its first line times the run)
    unbuffered = {**os.environ, "PYTHONUNBUFFERED": "1"}
    starts: list[float | None] = []
    with tempfile.TemporaryDirectory(prefix="jason-demo-") as tmp:
        runs = []
        outputs: list[str] = []
        for _ in range(args.jason_runs):
            work = Path(tmp) / f"jason{len(runs)}"
            shutil.copytree(mas.parent, work)
            run = run_for(java, work, args.time, args.start_limit)
            keep_run(args.keep, name, work.name, run.output)
            starts.append(run.first_line)
            outputs.append(run.output)
            runs.append(per_agent(run.output))
        ours_all: list[Run] = []
        for k in range(args.rason_runs):
            work = Path(tmp) / ("rason" if k == 0 else f"rason{k}")
            shutil.copytree(mas.parent, work)
            ours_all.append(run_for(rason, work, args.time, args.start_limit, unbuffered))
            keep_run(args.keep, name, work.name, ours_all[-1].output)
    run = ours_all[0]        # the verdicts' run; the others count in the permutation test
    ours = per_agent(run.output)
    agents = len(set().union(*runs, ours))
    jason_start = [t for t in starts if t is not None]
    timing = StartUp(jason_start, [r.first_line for r in ours_all if r.first_line is not None])
    agree = all(same_lines(runs[0], r) for r in runs[1:])
    families = copied_agents(mas.read_text(errors="replace"))
    merged = [counted_as_varying(out, families) for out in outputs]
    p_value = permutation_p(merged, [counted_as_varying(r.output, families) for r in ours_all])
    if any(same_lines(theirs, ours) for theirs in runs):
        return Outcome(name, agents, True, "", True, agree, True, timing,
                       typical=len(runs), p_value=p_value)
    loose = any(same_lines(loosen(theirs), loosen(ours)) for theirs in runs)
    merged_ours = counted_as_varying(run.output, families)
    varied = loose or within_variation(merged, merged_ours)
    typical = len(runs) if loose else as_atypical(merged, merged_ours)
    defect = KNOWN_JASON_DEFECTS.get(name)
    note = defect.note if defect and defect_explains(defect, outputs, run.output) else ""
    return Outcome(name, agents, False, first_difference(runs[0], ours), loose, agree, varied,
                   timing, note, typical, p_value)


def defect_explains(defect: JasonDefect | None, jason_outputs: list[str], ours: str) -> bool:
    """Every Jason run shows ``defect`` and rason printed what the first one printed plus exactly
    the lines the defect keeps Jason from printing."""
    if defect is None or not all(defect.sign in out for out in jason_outputs):
        return False
    fixed = per_agent(jason_outputs[0] + "".join(line + "\n" for line in defect.missing))
    return same_lines(fixed, per_agent(ours))


def jason_version(tree: Path) -> str:
    """The Jason version the source tree names (its ``gradle.properties``), else ``unknown``."""
    try:
        found = VERSION_LINE.search((tree / VERSION_FILE).read_text(errors="replace"))
    except OSError:
        return "unknown"
    return found.group(1) if found else "unknown"


def select_projects(projects: list[Path], tree: Path, filters: list[str]) -> list[Path]:
    """The projects whose path in the tree contains any of the filters (all without one)."""
    return [m for m in projects
            if not filters or any(f in str(m.relative_to(tree)) for f in filters)]


def yes_no(flag: bool) -> str:
    return "yes" if flag else "no"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("tree", type=Path, help="a Jason source tree (jason-lang/jason checkout)")
    ap.add_argument("--classpath", required=True, help="class path of a Jason build (java -cp)")
    ap.add_argument("--time", type=float, default=10.0,
                    help="seconds each run goes on from its first agent line")
    ap.add_argument("--start-limit", type=float, default=10.0,
                    help="seconds a run may take to print its first agent line before its "
                         "--time counts anyway")
    ap.add_argument("--keep", type=Path, default=None,
                    help="keep every run's output: KEEP/PROJECT/RUN/all.txt and AGENT.txt")
    ap.add_argument("--jason-runs", type=int, default=3, help="runs of Jason per project")
    ap.add_argument("--rason-runs", type=int, default=1,
                    help="runs of rason per project: the first gives the verdicts, all of them "
                         "the permutation test's p")
    ap.add_argument("-k", action="append", default=[],
                    help="only projects whose path contains this text (repeat for several)")
    args = ap.parse_args()
    if args.jason_runs < 1 or args.rason_runs < 1:
        ap.error("--jason-runs and --rason-runs need at least one run each")
    projects = select_projects(find_projects(args.tree), args.tree, args.k)
    if not projects:
        print(f"no project found under {args.tree}", file=sys.stderr)
        return 1
    version = jason_version(args.tree)
    print(f"Jason {version} (the tree's {VERSION_FILE}; --classpath should be its build) "
          f"against rason\n")
    print("| project | agents | Jason's runs agree? | same? | same up to numbers and list order? "
          "| within Jason's variation? | Jason's runs as far off as rason's | p, rason's runs "
          "drawn as Jason's | first difference (strict) |")
    print("|---|---|---|---|---|---|---|---|---|")
    same = loose = varied = typical = varying = defects = alike = 0
    jason_starts: list[float] = []
    rason_starts: list[float] = []
    for mas in projects:
        o = compare(mas, args.tree, args)
        jason_starts += o.start_up.jason
        rason_starts += o.start_up.rason
        same += o.same
        loose += o.same_loosely
        varied += o.within_variation
        typical += o.typical > 0
        alike += o.p_value >= SIGNIFICANCE
        varying += not o.jason_agrees
        defects += bool(o.jason_defect)
        diff = o.difference.replace("|", "\\|")
        if o.jason_defect:
            diff = f"{diff} ({o.jason_defect})"
        print(f"| {o.project} | {o.agents} | {yes_no(o.jason_agrees)} | {yes_no(o.same)} | "
              f"{yes_no(o.same_loosely)} | {yes_no(o.within_variation)} | "
              f"{o.typical} of {args.jason_runs} | {o.p_value:.3f} | {diff} |", flush=True)
    print(f"\n{same} of {len(projects)} projects print the same; {loose} of {len(projects)} the "
          f"same up to numbers and list order; {varied} of {len(projects)} within Jason's variation; "
          f"{typical} of {len(projects)} no further off than some Jason run; Jason's own runs "
          f"differed for {varying}; {defects} differ only by a documented Jason defect "
          f"(Jason {version})")
    smallest = smallest_p(args.jason_runs, args.rason_runs)
    if smallest < SIGNIFICANCE:
        print(f"{alike} of {len(projects)} with p >= {SIGNIFICANCE}: rason's {args.rason_runs} "
              f"runs not told apart from Jason's {args.jason_runs} (exact permutation test, "
              f"smallest p {smallest:.4f})")
    else:
        print(f"(the permutation test cannot reach p < {SIGNIFICANCE} with {args.rason_runs} "
              f"and {args.jason_runs} runs: its smallest p is {smallest:.3f})")
    for side, starts in (("Jason", jason_starts), ("rason", rason_starts)):
        if starts:
            print(f"{side}'s first agent line came {statistics.median(starts):.2f} s after the "
                  f"launch (median of {len(starts)} runs; {min(starts):.2f}-{max(starts):.2f} s), "
                  f"not counted in --time")
    return 0


if __name__ == "__main__":
    sys.exit(main())
