"""The Jason conformance suite (copied from ../shared/conformance): every case must match."""

from __future__ import annotations

import io
import os
import subprocess
import sys

import pytest
from asl_helpers import CONFORMANCE, load_compare, subprocess_env

from rason.asl import LocalMas, load_mas2j

compare = load_compare()
CASES = compare.find_cases(CONFORMANCE)
KNOWN_DIFFERENCES: dict[str, str] = {}


def run_case_in_process(case_dir: str) -> str:
    out = io.StringIO()
    mas = LocalMas(out=out)
    entry = compare.find_entry(case_dir)
    if entry.endswith(".mas2j"):
        mas.load_project(load_mas2j(entry))
    else:
        with open(entry, encoding="utf-8") as f:
            mas.add_agent("main", f.read(), entry)
    assert mas.run(timeout=20), "timeout"
    return out.getvalue()


def test_suite_is_present() -> None:
    assert len(CASES) >= 32


@pytest.mark.parametrize("case_dir", CASES, ids=[os.path.basename(c) for c in CASES])
def test_case(case_dir: str) -> None:
    name = os.path.basename(case_dir)
    if name in KNOWN_DIFFERENCES:
        pytest.xfail(KNOWN_DIFFERENCES[name])
    actual = run_case_in_process(case_dir)
    expected = compare.read(os.path.join(case_dir, "expected.txt"))
    ok, diff = compare.compare_text(expected, actual)
    assert ok, "\n".join(diff)


@pytest.mark.parametrize("case", ["03_print_multi_args", "31_comm_broadcast_merge_self"])
def test_cli_matches(case: str) -> None:
    """The command line (what compare.py --suite runs) gives the same output."""
    case_dir = os.path.join(CONFORMANCE, case)
    entry = compare.find_entry(case_dir)
    proc = subprocess.run([sys.executable, "-m", "rason.asl", "run", entry, "--timeout", "20"],
                          cwd=case_dir, capture_output=True, text=True, timeout=60, env=subprocess_env())
    assert proc.returncode == 0, proc.stderr
    ok, diff = compare.compare_text(compare.read(os.path.join(case_dir, "expected.txt")), proc.stdout)
    assert ok, "\n".join(diff)


def test_cli_syntax_error(tmp_path) -> None:
    bad = tmp_path / "bad.asl"
    bad.write_text("!start.\n+!start <- .print(\"x\" .\n")
    proc = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(bad)],
                          capture_output=True, text=True, timeout=60, env=subprocess_env())
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"{bad}:2:")


def test_cli_timeout(tmp_path) -> None:
    loop = tmp_path / "loop.asl"
    loop.write_text("!g.\n+!g <- !g.\n")
    proc = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(loop), "--timeout", "0.5"],
                          capture_output=True, text=True, timeout=60, env=subprocess_env())
    assert proc.returncode == 1
