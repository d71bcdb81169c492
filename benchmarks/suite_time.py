#!/usr/bin/env python3
"""Where the suite's time goes: a JUnit XML of a whole ``./run.sh test`` run (pytest's
``--junitxml``, whose per-test time is setup + call + teardown) summed by module and by kind of
test, and the two-worker schedules that time allows.

Kinds: ``end-to-end`` (the tests one xdist worker runs in turn: tests/conftest.py's
``is_end_to_end``), ``ros`` (other modules that start a roscore or ROS nodes: ``pytestmark``
names ``ros`` or a test takes a roscore fixture) and ``pure`` (the rest). With ``--durations LOG``
(the output of the same run with ``--durations=0``) each module's setup, call and teardown are
shown apart.

The schedules replay the measured serial times on N workers, each worker taking the next unit of
work when it is idle: ``loadgroup`` (what ``RASON_TEST_WORKERS=2`` runs: the end-to-end tests one
unit, every other test a unit of its own, units with more tests first as xdist's default
``--loadscope-reorder`` orders them), ``longest first`` (the same units by time, longest first)
and the ideal (the total over N). The replay ignores that two workers share two cores, so the
real wall time is longer (runs 7-14 in docs/benchmarks.md: 10-20 % over the replay on a quiet
machine); it shows which schedule can help at all.

The replay is also run with the end-to-end tests shorter than ``--light-out`` seconds taken out
of the group (what splitting a demo module's static checks and single node starts from its demo
runs would give).

Usage: python3 benchmarks/suite_time.py JUNIT.xml [--durations LOG] [--top 30] [--workers 2]
       [--light-out 10]
"""

from __future__ import annotations

import argparse
import heapq
import re
import sys
import xml.etree.ElementTree as ET
from collections import defaultdict
from dataclasses import dataclass, field
from enum import Enum
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests"))

from conftest import ROS_FIXTURES, is_end_to_end, module_marks  # noqa: E402  (tests/ on the path)


class Kind(Enum):
    """What a module's tests start."""

    END_TO_END = "end-to-end"
    ROS = "ros"
    PURE = "pure"


@dataclass(frozen=True)
class TestTime:
    """One test case of the XML."""

    nodeid: str
    module: str
    seconds: float


@dataclass
class ModuleTime:
    """One module's tests, summed."""

    path: str
    kind: Kind
    seconds: float = 0.0
    tests: int = 0
    longest: float = 0.0
    phases: dict[str, float] = field(default_factory=lambda: defaultdict(float))


def module_path(classname: str) -> str:
    """The test file of a JUnit ``classname`` (``tests.x.test_y`` or ``tests.x.test_y.Class``)."""
    parts = classname.split(".")
    for end in range(len(parts), 0, -1):
        path = "/".join(parts[:end]) + ".py"
        if (REPO / path).is_file():
            return path
    return "/".join(parts) + ".py"


def read_junit(xml: Path) -> list[TestTime]:
    """Every test case of the XML with its time (setup + call + teardown)."""
    tests = []
    for case in ET.parse(xml).iter("testcase"):
        path = module_path(case.get("classname", ""))
        tests.append(TestTime(f"{path}::{case.get('name')}", path,
                              float(case.get("time") or 0.0)))
    return tests


_ROS_PARAM = re.compile(r"def test_\w+\([^)]*\b(" + "|".join(sorted(ROS_FIXTURES)) + r")\b")


def kind_of(path: str, nodeid: str) -> Kind:
    """The kind of test ``nodeid`` in the module ``path``."""
    if is_end_to_end(nodeid, REPO):
        return Kind.END_TO_END
    source = REPO / path
    if "ros" in module_marks(source) or (source.is_file()
                                         and _ROS_PARAM.search(source.read_text("utf-8"))):
        return Kind.ROS
    return Kind.PURE


def by_module(tests: list[TestTime]) -> dict[str, ModuleTime]:
    """The tests summed per module (a module's kind: that of its costliest kind of test)."""
    modules: dict[str, ModuleTime] = {}
    for test in tests:
        kind = kind_of(test.module, test.nodeid)
        module = modules.setdefault(test.module, ModuleTime(test.module, kind))
        if kind == Kind.END_TO_END:
            module.kind = kind
        module.seconds += test.seconds
        module.tests += 1
        module.longest = max(module.longest, test.seconds)
    return modules


_DURATION = re.compile(r"^([\d.]+)s (setup|call|teardown)\s+([^:\s]+)::")


def add_phases(modules: dict[str, ModuleTime], log: Path) -> None:
    """Each module's setup, call and teardown seconds from a ``--durations=0`` output."""
    for line in log.read_text("utf-8", errors="replace").splitlines():
        if (match := _DURATION.match(line)) and match.group(3) in modules:
            modules[match.group(3)].phases[match.group(2)] += float(match.group(1))


def makespan(units: list[float], workers: int) -> float:
    """The wall time of ``units`` (in this order) on ``workers``, each taking the next unit
    when idle."""
    ends = [0.0] * workers
    for unit in units:
        heapq.heapreplace(ends, ends[0] + unit)
    return max(ends)


@dataclass(frozen=True)
class Units:
    """The units of work of a run: the end-to-end group's tests and every other test."""

    group: list[float]
    others: list[float]

    def loadgroup(self) -> list[float]:
        """xdist's order: the group (most tests) first, the single tests after it."""
        return [sum(self.group), *self.others]

    def longest_first(self) -> list[float]:
        """The same units, longest first."""
        return sorted(self.loadgroup(), reverse=True)


def units_of(tests: list[TestTime], light: float = 0.0) -> Units:
    """The run's units of work; end-to-end tests that took under ``light`` seconds (a demo
    module's static checks and single node starts) out of the group when ``light`` > 0."""
    units = Units([], [])
    for test in tests:
        grouped = is_end_to_end(test.nodeid, REPO) and test.seconds >= light
        (units.group if grouped else units.others).append(test.seconds)
    return units


def main(argv: list[str] | None = None) -> int:
    """Print the module table, the kinds and the schedules."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("junit", type=Path, help="pytest --junitxml output of a whole run")
    parser.add_argument("--durations", type=Path, help="the run's output with --durations=0")
    parser.add_argument("--top", type=int, default=30, help="modules to list (default 30)")
    parser.add_argument("--workers", type=int, default=2, help="workers to replay (default 2)")
    parser.add_argument("--light-out", type=float, default=10.0, metavar="SECONDS",
                        help="also replay with the end-to-end tests shorter than this out of "
                             "their group (default 10)")
    args = parser.parse_args(argv)
    tests = read_junit(args.junit)
    modules = by_module(tests)
    if args.durations:
        add_phases(modules, args.durations)
    total = sum(t.seconds for t in tests)
    print(f"{len(tests)} tests, {total:.0f} s in test phases\n")
    print("| module | kind | tests | seconds | longest test | setup / call / teardown |")
    print("| --- | --- | --- | --- | --- | --- |")
    for module in sorted(modules.values(), key=lambda m: -m.seconds)[:args.top]:
        phases = " / ".join(f"{module.phases.get(p, 0.0):.1f}"
                            for p in ("setup", "call", "teardown")) if module.phases else "-"
        print(f"| {module.path} | {module.kind.value} | {module.tests} | {module.seconds:.1f} "
              f"| {module.longest:.1f} | {phases} |")
    print("\n| kind | modules | tests | seconds |\n| --- | --- | --- | --- |")
    for kind in Kind:
        of_kind = [m for m in modules.values() if m.kind == kind]
        print(f"| {kind.value} | {len(of_kind)} | {sum(m.tests for m in of_kind)} "
              f"| {sum(m.seconds for m in of_kind):.0f} |")
    if args.durations:
        phases = {p: sum(m.phases.get(p, 0.0) for m in modules.values())
                  for p in ("setup", "call", "teardown")}
        print("\nphases: " + ", ".join(f"{p} {s:.0f} s" for p, s in phases.items()))
    print(f"\nreplay on {args.workers} workers (serial times, no sharing of cores):")
    for label, units in (("as grouped", units_of(tests)),
                         (f"tests under {args.light_out:g} s out of the group",
                          units_of(tests, args.light_out))):
        print(f"  {label}: end-to-end group {len(units.group)} tests, {sum(units.group):.0f} s;"
              f" the rest {len(units.others)} tests, {sum(units.others):.0f} s")
        print(f"    loadgroup (as run): {makespan(units.loadgroup(), args.workers):.0f} s;"
              f" longest first: {makespan(units.longest_first(), args.workers):.0f} s")
    print(f"  ideal (total / {args.workers}): {total / args.workers:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
