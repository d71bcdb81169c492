#!/usr/bin/env python3
"""Jason's own AgentSpeak unit-test suite, run unchanged through ``python -m rason.asl run``.

Takes the path of a checkout of jason-lang/jason (kept outside this repository). Each test file
of ``jason-interpreter/src/test/jason/asl`` runs as a MAS of its own: the file's agent (which
includes Jason's tester agent) and a small ``test_manager`` written here that prints what the
tester tells it. A test plan (a plan labelled ``[test]``) passes when it was launched, reached
``state(achieved)`` and no assertion failed while it ran (and no fatal error was reported).

    python benchmarks/jason_unit_suite.py JASON_CHECKOUT [-k NAME] [-v] [--timeout S] [--jobs N]

Prints one line per file (passed/plans) and the total ``passed/plans``.
"""

from __future__ import annotations

import argparse
import re
import shlex
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

#: The manager the tester agents talk to: it only reports, one line per message.
MANAGER = """
!start.
+!start <- .create_agent({agent}, "{source}").
+!count_plans(Status, Plan, Agent) <- .print("PLAN|", Status, "|", Plan).
+!count_tests(Result, Test, Agent) <- .print("TEST|", Result, "|", Test).
+launching_test_set(A) <- .print("SET|launching").
+launched_test_set(A) <- .print("SET|launched"); .wait(3000); .stopMAS.
+fatal_error[source(A)] <- .print("FATAL|", A).
"""

TEST_LABEL = re.compile(r"@[A-Za-z0-9_]*\[[^\]]*\btest\b")


@dataclass
class FileResult:
    """What happened to the test plans of one file."""

    name: str
    plans: int
    passed: list[str] = field(default_factory=list)
    failed: dict[str, str] = field(default_factory=dict)
    output: str = ""


def count_test_plans(text: str) -> int:
    """Plans whose label has the ``test`` annotation (comments removed first)."""
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    text = re.sub(r"//[^\n]*", "", text)
    return len(TEST_LABEL.findall(text))


def run_file(asl: Path, suite: Path, timeout: float, cmd: str) -> FileResult:
    # as Jason's own test manager does: the tester agent is created from the path of its file
    # relative to jason-interpreter/ (the folder the suite runs in), e.g. ./src/test/jason/asl/x.asl
    interpreter = suite.parents[2]
    source = "./" + str(asl.relative_to(interpreter))
    res = FileResult(str(asl.relative_to(suite / "asl")), count_test_plans(asl.read_text()))
    with tempfile.TemporaryDirectory(prefix="jason_unit_") as tmp:
        Path(tmp, "test_manager.asl").write_text(
            MANAGER.replace("{agent}", asl.stem).replace("{source}", source))
        Path(tmp, "suite.mas2j").write_text(
            "MAS unit {\n  agents:\n    test_manager;\n"
            f'  aslSourcePath: "{tmp}"; "{suite / "inc"}"; "{suite / "asl"}";\n}}\n')
        try:
            argv = shlex.split(cmd.format(mas2j=str(Path(tmp, "suite.mas2j")), timeout=timeout))
            proc = subprocess.run(argv, cwd=interpreter, capture_output=True, text=True,
                                  timeout=timeout + 10)
            out = proc.stdout + proc.stderr
        except subprocess.TimeoutExpired as e:
            out = (e.stdout or b"").decode() if isinstance(e.stdout, bytes) else (e.stdout or "")
            out += "\n(driver: killed after the timeout)"
    res.output = out
    current: str | None = None
    achieved: set[str] = set()
    launched: list[str] = []
    for line in out.splitlines():
        m = re.match(r"\[test_manager\] (PLAN|TEST|FATAL|SET)\|([^|]*)\|?(.*)$", line)
        if not m:
            continue
        kind, a, b = m.groups()
        if kind == "PLAN" and a == "launched":
            current = b
            launched.append(b)
        elif kind == "PLAN" and a == "achieved":
            achieved.add(b)
        elif kind == "TEST" and a == "failed" and current is not None:
            res.failed.setdefault(current, f"assertion failed: {b}")
        elif kind == "FATAL" and current is not None:
            res.failed.setdefault(current, "fatal error reported")
    for p in launched:
        if p not in achieved:
            res.failed.setdefault(p, "not achieved")
        elif p not in res.failed:
            res.passed.append(p)
    return res


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("jason", help="path of a jason-lang/jason checkout")
    ap.add_argument("-k", default=None, help="only files whose path contains this")
    ap.add_argument("-v", action="store_true", help="show the output of failing files")
    ap.add_argument("--timeout", type=float, default=40.0, help="seconds per file")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--cmd", default=f"{sys.executable} -m rason.asl run {{mas2j}} --timeout {{timeout}}",
                    help="command that runs a project ({mas2j}, {timeout} are replaced); "
                         "default: this interpreter")
    args = ap.parse_args()
    suite = Path(args.jason).resolve() / "jason-interpreter" / "src" / "test" / "jason"
    if not (suite / "inc" / "tester_agent.asl").is_file():
        print(f"{suite}: not a Jason checkout (no inc/tester_agent.asl)", file=sys.stderr)
        return 2
    files = sorted(p for p in (suite / "asl").rglob("*.asl") if not args.k or args.k in str(p))
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(lambda f: run_file(f, suite, args.timeout, args.cmd), files))
    total = sum(r.plans for r in results)
    passed = sum(len(r.passed) for r in results)
    for r in results:
        print(f"{len(r.passed):3d}/{r.plans:<3d} {r.name}")
        for plan, why in r.failed.items():
            print(f"        FAIL {plan}: {why}")
        missing = r.plans - len(r.passed) - len(r.failed)
        if missing > 0:
            print(f"        {missing} test plan(s) never launched")
        if args.v and (r.failed or missing > 0):
            print("        | " + "\n        | ".join(r.output.splitlines()[-60:]))
    print(f"passed {passed}/{total} test plans")
    return 0


if __name__ == "__main__":
    sys.exit(main())
