"""What the two campaigns share (``campaign.py``: demos, ``mission_campaign.py``: missions): one
run in a process of its own, and the skeleton of ``report.md`` (its figures, tables and the
plots that were written)."""

from __future__ import annotations

import json
import statistics
import subprocess
from collections.abc import Iterable, Sequence
from pathlib import Path

from rason.process.harness import processes_left_by
from rason_diagnosis.scenario import FAULTS

#: Wall seconds a run stopped with SIGTERM may take to stop its nodes before it is killed.
STOP_GRACE_S = 60


def run_process(cmd: Sequence[str], run_dir: Path, log: Path, timeout_s: float,
                stand_in: dict) -> dict:
    """Run `cmd` (a demo or a mission writing ``run_dir/result.json``), its output in `log`;
    after `timeout_s` wall seconds SIGTERM (the run stops its nodes), then SIGKILL. Its
    result.json as a dict (else `stand_in`, saying why), with ``orphans``: how many processes
    it left running."""
    with open(log, "w") as out:
        run = subprocess.Popen(list(cmd), stdout=out, stderr=subprocess.STDOUT)
        try:
            run.wait(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            run.terminate()
            try:
                run.wait(timeout=STOP_GRACE_S)
            except subprocess.TimeoutExpired:
                run.kill()
                run.wait()
    try:
        result = json.loads((run_dir / "result.json").read_text())
    except (OSError, ValueError):
        result = stand_in
    result["orphans"] = len(processes_left_by(run.pid))
    return result


def fmt(value: float | None, digits: int = 2) -> str:
    """A report's figure: `digits` decimals, ``-`` for none."""
    return "-" if value is None else f"{value:.{digits}f}"


def mean(values: Iterable[float | None]) -> float | None:
    """The mean of the values that are there; None without any."""
    present = [v for v in values if v is not None]
    return statistics.fmean(present) if present else None


def faults_run(results: list[dict]) -> list[str]:
    """The faults (in :data:`FAULTS` order) that have at least one run in ``results``."""
    return [f for f in FAULTS if any(r["fault"] == f for r in results)]


def orphans(results: list[dict]) -> int:
    """How many processes the runs left running, all told."""
    return sum(r.get("orphans", 0) for r in results)


def table_head(*columns: str) -> list[str]:
    """A Markdown table's first two lines: the column names and the rule under them."""
    return ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]


def image_link(out: Path, relative: str, alt: str) -> list[str]:
    """A report's lines showing the picture ``out/relative``: none when it was not written."""
    return [f"![{alt}]({relative})", ""] if (out / relative).is_file() else []


def plots_dir(out: Path) -> Path:
    """``out/plots``, made if need be."""
    plots = out / "plots"
    plots.mkdir(parents=True, exist_ok=True)
    return plots


def save_report(out: Path, lines: list[str]) -> str:
    """``out/report.md`` made of `lines`; its text."""
    text = "\n".join(lines) + "\n"
    (out / "report.md").write_text(text)
    return text
