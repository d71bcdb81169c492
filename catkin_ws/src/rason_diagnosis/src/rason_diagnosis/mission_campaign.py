"""``./run.sh campaign --mission``: the mission (``./run.sh mission``) over faults x seeds, with
recovery, without it (``--no-recovery``, the baseline), or both side by side (``--baseline``).

Each run is a separate mission process (its own roscore, simulator, nodes and agents); its
``result.json`` and logs are kept under ``runs/MODE-FAULT-SEED/``. ``report.md`` gives, per fault
and mode: completion rate, total time against the fault-free mission of the same seed, waypoint
errors (ground truth), the closest approach of the robots (contacts) and who reached the
waypoints; ``runs.csv`` one line per run; ``plots/mission.png`` the same at a glance.
"""

from __future__ import annotations

import csv
import json
import statistics
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from enum import StrEnum
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from rason_diagnosis.campaign_parts import (
    faults_run,
    fmt,
    image_link,
    mean,
    orphans,
    plots_dir,
    run_process,
    save_report,
    table_head,
)
from rason_diagnosis.scenario import FAULTS, NO_FAULT
from turtlebot_model.kobuki import BODY_RADIUS

#: The issue's bar: a waypoint counts as reached within this distance (ground truth, m).
REACHED_WITHIN_M = 0.3
#: The robots' bodies touch when their centres come this close (m; ground truth is rounded to
#: the millimetre, and a bumper that fired came at 0.354).
CONTACT_M = 2 * BODY_RADIUS
#: Wall seconds a mission process may take before the campaign stops it.
RUN_WALL_TIMEOUT_S = 1200
FIELDS = ("mode", "fault", "seed", "completed", "reason", "diagnosis", "recovery", "at_s",
          "injected_at_s", "total_s", "relative_time", "by_faulty", "by_helper", "not_reached",
          "max_error_m", "within_bar", "min_robot_distance_m", "contact", "wall_s", "orphans",
          "error")


class Mode(StrEnum):
    """With the agents' recovery, or the baseline without it."""

    RECOVERY = "recovery"
    BASELINE = "baseline"


def run_dir(out: Path, mode: Mode, fault: str, seed: int) -> Path:
    """Where one run's result.json and logs are kept."""
    return out / "runs" / f"{mode.value}-{fault}-{seed}"


def run_one(mode: Mode, fault: str, seed: int, out: Path, extra: Sequence[str] = ()) -> dict:
    """One mission in its own process; its result.json as a dict (a stand-in saying why when
    the process wrote none), with ``mode`` and ``orphans`` added."""
    where = run_dir(out, mode, fault, seed)
    cmd = [sys.executable, "-m", "rason_diagnosis.mission", "--fault", fault, "--seed", str(seed),
           "--quiet", "--no-inspector", "--out", str(where), *extra,
           *(["--no-recovery"] if mode == Mode.BASELINE else [])]
    where.parent.mkdir(parents=True, exist_ok=True)
    # on SIGTERM the mission stops its nodes
    result = run_process(cmd, where, where.parent / f"{where.name}.log", RUN_WALL_TIMEOUT_S,
                         {"fault": fault, "seed": seed, "completed": False, "waypoints": [],
                          "error": "no result.json", "reason": "error: no result.json"})
    result["mode"] = mode.value
    return result


def load_runs(out: Path) -> list[dict]:
    """Every run's result.json under ``out/runs`` (for ``--report-only``), mode from its folder,
    orphans from ``out/runs.csv`` when it lists the run."""
    orphans: dict[str, int] = {}
    if (out / "runs.csv").is_file():
        with open(out / "runs.csv", newline="") as f:
            orphans = {f"{row['mode']}-{row['fault']}-{row['seed']}": int(row["orphans"] or 0)
                       for row in csv.DictReader(f)}
    results = []
    for path in sorted((out / "runs").glob("*/result.json")):
        result = json.loads(path.read_text())
        result["mode"] = path.parent.name.split("-", 1)[0]
        result["orphans"] = orphans.get(path.parent.name, 0)
        results.append(result)
    return results


@dataclass
class RunFigures:
    """What the report reads of one run."""

    completed: bool
    total_s: float | None
    relative_time: float | None         # total / the fault-free mission's (same seed, or mean)
    by_faulty: int
    by_helper: int
    not_reached: int
    errors: list[float]
    max_error_m: float | None
    within_bar: bool                    # every waypoint reached within REACHED_WITHIN_M
    min_distance_m: float | None
    contact: bool


def fault_free_times(results: list[dict]) -> dict[int, float]:
    """The total time of each seed's fault-free mission with recovery that was completed."""
    return {r["seed"]: r["total_s"] for r in results
            if r["fault"] == NO_FAULT and r.get("mode") == Mode.RECOVERY.value
            and r.get("completed") and r.get("total_s")}


def figures(result: dict, reference: dict[int, float]) -> RunFigures:
    """One run's figures; its time relative to the same seed's fault-free mission (else to the
    mean of the fault-free missions; None without any)."""
    points = result.get("waypoints") or []
    by = [p.get("reached_by") for p in points]
    errors = [p["error_m"] for p in points if p.get("reached_by") and p.get("error_m") is not None]
    base = reference.get(result["seed"])
    if base is None and reference:
        base = statistics.fmean(reference.values())
    total = result.get("total_s")
    distance = result.get("min_robot_distance_m")
    completed = bool(result.get("completed"))
    return RunFigures(
        completed=completed, total_s=total,
        relative_time=round(total / base, 2) if total and base else None,
        by_faulty=by.count("faulty"), by_helper=by.count("helper"),
        not_reached=sum(1 for b in by if not b), errors=errors,
        max_error_m=max(errors, default=None),
        within_bar=completed and bool(points) and len(errors) == len(points)
        and all(e <= REACHED_WITHIN_M for e in errors),
        min_distance_m=distance, contact=distance is not None and distance <= CONTACT_M)


def rows(results: list[dict]) -> list[dict]:
    """runs.csv's lines."""
    reference = fault_free_times(results)
    out = []
    for r in results:
        f = figures(r, reference)
        out.append({**{k: r.get(k) for k in FIELDS}, "relative_time": f.relative_time,
                    "by_faulty": f.by_faulty, "by_helper": f.by_helper,
                    "not_reached": f.not_reached, "max_error_m": f.max_error_m,
                    "within_bar": f.within_bar, "contact": f.contact})
    return out


def write_csv(results: list[dict], out: Path) -> None:
    with open(out / "runs.csv", "w", newline="") as f:
        writer = csv.DictWriter(f, FIELDS, extrasaction="ignore")
        writer.writeheader()
        writer.writerows(rows(results))


def _groups(results: list[dict]) -> list[tuple[str, Mode, list[dict]]]:
    """(fault, mode, runs) for every fault and mode that ran, faults in FAULTS order."""
    out = []
    for fault in FAULTS:
        for mode in Mode:
            mine = [r for r in results if r["fault"] == fault and r.get("mode") == mode.value]
            if mine:
                out.append((fault, mode, mine))
    return out


def write_report(results: list[dict], out: Path) -> str:
    """report.md: the table per fault and mode, then every run."""
    reference = fault_free_times(results)
    seeds = sorted({r["seed"] for r in results})
    lines = ["# Fault-tolerant mission: campaign", "",
             f"Seeds {', '.join(map(str, seeds))}; times in simulated seconds from Faulty's "
             "first motion; time x: the run's total over the fault-free mission's of the same "
             "seed (with recovery); errors by ground truth at each arrival; within "
             f"{REACHED_WITHIN_M} m: completed with every waypoint that close; contact: the "
             f"robots' centres {CONTACT_M:.3f} m apart or closer (their bodies touch).", "",
             *table_head("fault", "mode", "completed", "within 0.3 m", "time mean (max) s",
                         "time x mean (max)", "error mean (max) m", "closest m", "contacts",
                         "waypoints by faulty / helper / none")]
    for fault, mode, mine in _groups(results):
        figs = [figures(r, reference) for r in mine]
        totals = [f.total_s for f in figs if f.completed and f.total_s is not None]
        ratios = [f.relative_time for f in figs if f.completed and f.relative_time is not None]
        errors = [e for f in figs for e in f.errors]
        closest = [f.min_distance_m for f in figs if f.min_distance_m is not None]
        lines.append(
            f"| {fault} | {mode.value} | {sum(f.completed for f in figs)}/{len(figs)} | "
            f"{sum(f.within_bar for f in figs)}/{len(figs)} | "
            f"{fmt(mean(totals), 1)} ({fmt(max(totals, default=None), 1)}) | "
            f"{fmt(mean(ratios))} ({fmt(max(ratios, default=None))}) | "
            f"{fmt(mean(errors), 3)} ({fmt(max(errors, default=None), 3)}) | "
            f"{fmt(min(closest, default=None), 3)} | "
            f"{sum(f.contact for f in figs)} | {sum(f.by_faulty for f in figs)} / "
            f"{sum(f.by_helper for f in figs)} / {sum(f.not_reached for f in figs)} |")
    walls = [r["wall_s"] for r in results if r.get("wall_s")]
    lines += ["", f"Runs: {len(results)}; processes left running after them (orphans): "
              f"{orphans(results)}; wall clock per run: mean {fmt(mean(walls), 0)} s, "
              f"max {fmt(max(walls, default=None), 0)} s.", "",
              *image_link(out, "plots/mission.png", "completion, time and errors per fault"),
              "## Runs", "",
              *table_head("mode", "fault", "seed", "injected at s", "diagnosis", "recovery",
                          "completed", "total s", "time x", "max error m", "closest m",
                          "reached by", "reason")]
    for fault, mode, mine in _groups(results):
        for r in mine:
            f = figures(r, reference)
            by = ", ".join(p.get("reached_by") or "-" for p in r.get("waypoints") or [])
            lines.append(
                f"| {mode.value} | {fault} | {r['seed']} | {fmt(r.get('injected_at_s'), 1)} | "
                f"{r.get('diagnosis') or '-'} | {r.get('recovery') or '-'} | "
                f"{'yes' if f.completed else 'no'} | {fmt(f.total_s, 1)} | "
                f"{fmt(f.relative_time)} | {fmt(f.max_error_m, 3)} | "
                f"{fmt(f.min_distance_m, 3)} | {by} | {r.get('reason') or ''} |")
    return save_report(out, lines)


def write_plots(results: list[dict], out: Path) -> None:
    """plots/mission.png: completion rate, time relative to the fault-free mission and the
    waypoint errors, per fault, recovery beside baseline."""
    plots = plots_dir(out)
    reference = fault_free_times(results)
    faults = faults_run(results)
    fig, (rate_ax, time_ax, error_ax) = plt.subplots(1, 3, figsize=(15, 4.2))
    width = 0.38
    for k, mode in enumerate(Mode):
        offset = (k - 0.5) * width
        colour = "tab:green" if mode == Mode.RECOVERY else "tab:grey"
        rates, ratio_points, error_points = [], [], []
        for i, fault in enumerate(faults):
            mine = [figures(r, reference) for r in results
                    if r["fault"] == fault and r.get("mode") == mode.value]
            rates.append(100.0 * sum(f.completed for f in mine) / len(mine) if mine else 0.0)
            ratio_points += [(i + offset, f.relative_time) for f in mine
                             if f.completed and f.relative_time is not None]
            error_points += [(i + offset, e) for f in mine for e in f.errors]
        rate_ax.bar([i + offset for i in range(len(faults))], rates, width, color=colour,
                    label=mode.value)
        for ax, points in ((time_ax, ratio_points), (error_ax, error_points)):
            if points:
                ax.scatter(*zip(*points, strict=True), color=colour, s=22, edgecolors="k",
                           linewidths=0.3, label=mode.value)
    time_ax.axhline(3.0, ls="--", color="k", lw=1, label="the issue's bar (3x)")
    error_ax.axhline(REACHED_WITHIN_M, ls="--", color="k", lw=1,
                     label=f"reached within {REACHED_WITHIN_M} m")
    for ax, title, label in ((rate_ax, "missions completed", "% of runs"),
                             (time_ax, "time of completed missions", "x the fault-free mission"),
                             (error_ax, "waypoint errors (ground truth)", "m")):
        ax.set_xticks(range(len(faults)))
        ax.set_xticklabels(faults, rotation=20, fontsize=8)
        ax.set_title(title)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, axis="y")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(plots / "mission.png", dpi=80)
    plt.close(fig)


def run_campaign(faults: Sequence[str], seeds: Sequence[int], modes: Sequence[Mode], out: Path,
                 extra: Sequence[str] = ()) -> list[dict]:
    """Every (seed, fault, mode), runs.csv rewritten after each; report.md and plots at the
    end. The fault-free mission runs with recovery when any run needs its time."""
    jobs = [(mode, fault, seed) for seed in seeds for fault in faults for mode in modes]
    (out / "runs").mkdir(parents=True, exist_ok=True)
    results: list[dict] = []
    started = time.monotonic()
    for done, (mode, fault, seed) in enumerate(jobs, 1):
        result = run_one(mode, fault, seed, out, extra)
        results.append(result)
        elapsed = time.monotonic() - started
        mark = "completed" if result.get("completed") else f"not completed ({result.get('reason')})"
        print(f"[{done}/{len(jobs)}] {mode.value} {fault} seed {seed}: {mark}; elapsed "
              f"{elapsed:.0f} s, eta {elapsed / done * (len(jobs) - done):.0f} s", flush=True)
        write_csv(results, out)
    write_plots(results, out)
    print(write_report(results, out))
    return results
