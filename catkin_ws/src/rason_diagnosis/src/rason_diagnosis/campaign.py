"""``./run.sh campaign [--runs N] [--world FILE] [--drivers sim|stock] ...``: every scenario N times.

With ``--mission``, the runs are missions instead of demos (rason_diagnosis.mission_campaign).

Each run is a separate demo process (its own roscore, simulator, nodes and agents) with a seed
that varies start poses, lighting and sensor noise. Writes ``runs.csv``, ``report.md`` (tables in
the form of thesis Tables 7.1-7.4 beside the thesis' figures, success rate per scenario) and PNG
plots in the form of Figures 7.1-7.8 (latency by step per run, total per run).
"""

from __future__ import annotations

import argparse
import csv
import statistics
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import yaml

from rason_diagnosis import thesis
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
from rason_diagnosis.drivers import SIM, WIRINGS, VisionPath, wiring_for
from rason_diagnosis.paths import world_colours, world_file
from rason_diagnosis.scenario import FAULTS, Outcome, outcome_of

#: Wall seconds a demo process may take before the campaign stops it.
RUN_WALL_TIMEOUT_S = 900
FIELDS = ("fault", "seed", "diagnosis", "expected", "correct", "detection_s", "location_s",
          "diagnosis_s", "total_s", "wall_s", "orphans", "error", "unknown_reason")
STEP_FIELDS = ("detection_s", "location_s", "diagnosis_s")


def run_one(fault: str, seed: int, out: Path, extra: Sequence[str] = ()) -> dict:
    """One demo run in its own process (``extra``: more demo options, e.g. --hosts); its
    result.json as a dict."""
    run_dir = out / "runs" / f"{fault}-{seed}"
    cmd = [sys.executable, "-m", "rason_diagnosis", "--fault", fault, "--seed", str(seed), "--quiet",
           "--out", str(run_dir), *extra]
    # on SIGTERM the demo stops its nodes (and --hosts namespaces)
    return run_process(cmd, run_dir, out / "runs" / f"{fault}-{seed}.log", RUN_WALL_TIMEOUT_S,
                       {"fault": fault, "seed": seed, "correct": False, "error": "no result.json"})


def demo_options(args: argparse.Namespace) -> list[str]:
    """The demo options every run of the campaign gets (a random layout's run replaces
    ``--world`` by its own, so the world's colours file is passed on explicitly)."""
    colours = args.colours or (world_colours(args.world) if args.world else None)
    return [*(["--hosts"] if args.hosts else []), "--drivers", args.drivers,
            *(["--vision", args.vision] if args.vision else []),
            *(["--world", str(args.world)] if args.world and args.layouts == "fixed" else []),
            *(["--colours", str(colours)] if colours else [])]


def progress(done: int, total: int, started: float, last: dict) -> None:
    width = 30
    filled = int(width * done / total)
    elapsed = time.monotonic() - started
    eta = elapsed / done * (total - done) if done else 0.0
    mark = "ok" if last.get("correct") else "WRONG"
    print(f"\r[{'#' * filled}{'.' * (width - filled)}] {done}/{total} "
          f"{last.get('fault', '')}-{last.get('seed', '')}: {last.get('diagnosis')} ({mark}) "
          f"elapsed {elapsed:4.0f} s, eta {eta:4.0f} s   ", end="", flush=True)


def verdict(result: dict) -> str:
    """What a report adds to a run's diagnosis that is not right: why it is unknown, or WRONG."""
    if outcome(result) == Outcome.WRONG:
        return " (WRONG)"
    return f" ({result.get('unknown_reason') or result.get('error') or 'no reason given'})"


def write_report(results: list[dict], out: Path, runs: int) -> str:
    """report.md of a fixed-layout campaign: the faults that ran, and the plots written."""
    lines = [f"# Cooperative fault diagnosis: campaign of {runs} run(s) per scenario", "",
             "Simulated TurtleBot 2 robots (pybullet), latencies in simulated seconds; the thesis "
             "ran real robots (Morais 2015, ch. 7).", "",
             *table_head("scenario", "correct (ours)", "correct (thesis)", "total mean (ours)",
                         "sd", "total mean (thesis)", "sd")]
    for fault in faults_run(results):
        mine = [r for r in results if r["fault"] == fault]
        ok = sum(1 for r in mine if r.get("correct"))
        totals = [r["total_s"] for r in mine if r.get("total_s") is not None]
        sd = statistics.stdev(totals) if len(totals) > 1 else None
        if fault in thesis.TABLES:
            t_ok, t_n = thesis.successes(fault)
            ref = f"{t_ok}/{t_n} | {thesis.mean(fault, 3):.2f} | {thesis.stdev(fault, 3):.2f}"
        else:
            ref = "- | - | -"
        lines.append(f"| {fault} | {ok}/{len(mine)} | {ref.split(' | ')[0]} | {fmt(mean(totals))} | "
                     f"{fmt(sd)} | {' | '.join(ref.split(' | ')[1:])} |")
    total_ok = sum(1 for r in results if r.get("correct"))
    walls = [r["wall_s"] for r in results if r.get("wall_s") is not None]
    lines += ["", f"Overall: {total_ok}/{len(results)} correct "
              f"({100.0 * total_ok / max(1, len(results)):.0f}%); the thesis: 19/20 (95%).",
              f"Processes left running after the runs (orphans): {orphans(results)}.",
              f"Wall clock per run: mean {fmt(mean(walls))} s, max {fmt(max(walls, default=None))} s "
              "(roscore, simulator, nodes and agents started and stopped each run).", ""]
    for fault in faults_run(results):
        mine = [r for r in results if r["fault"] == fault]
        name = thesis.TABLES[fault][0] if fault in thesis.TABLES else "no fault"
        lines += [f"## {fault} (form of {name})", "",
                  *table_head("run", "seed", "detection", "location", "diagnosis", "total",
                              "diagnosis made")]
        for i, r in enumerate(mine, 1):
            lines.append(f"| {i} | {r['seed']} | {fmt(r.get('detection_s'))} | "
                         f"{fmt(r.get('location_s'))} | {fmt(r.get('diagnosis_s'))} | "
                         f"{fmt(r.get('total_s'))} | {r.get('diagnosis')}"
                         f"{'' if r.get('correct') else verdict(r)} |")
        means = [mean([r.get(f) for r in mine]) for f in (*STEP_FIELDS, "total_s")]
        lines.append("| mean (ours) | | " + " | ".join(fmt(m) for m in means) + " | |")
        if fault in thesis.TABLES:
            lines.append("| thesis mean | | " + " | ".join(
                f"{thesis.mean(fault, s):.2f}" for s in range(4)) + " | |")
        lines += ["", *image_link(out, f"plots/{fault}.png", fault)]
    return save_report(out, lines)


def write_plots(results: list[dict], out: Path) -> None:
    """Per scenario: stacked latency by step per run (Figs 7.1/7.3/7.5/7.7 style) and totals."""
    plots = plots_dir(out)
    for fault in faults_run(results):
        mine = [r for r in results if r["fault"] == fault]
        fig, (steps_ax, total_ax) = plt.subplots(1, 2, figsize=(11, 4))
        xs = list(range(1, len(mine) + 1))
        bottom = [0.0] * len(mine)
        for field, label in zip(STEP_FIELDS, ("fault detection", "robot location", "diagnosis"), strict=True):
            values = [r.get(field) or 0.0 for r in mine]
            steps_ax.bar(xs, values, bottom=bottom, label=label)
            bottom = [b + v for b, v in zip(bottom, values, strict=True)]
        steps_ax.set_xlabel("run")
        steps_ax.set_ylabel("latency (simulated s)")
        steps_ax.set_title(f"{fault}: latency by step")
        steps_ax.legend(fontsize=8)
        totals = [r.get("total_s") or 0.0 for r in mine]
        colours = ["tab:green" if r.get("correct") else "tab:red" for r in mine]
        total_ax.bar(xs, totals, color=colours)
        if fault in thesis.TABLES:
            total_ax.axhline(thesis.mean(fault, 3), ls="--", color="k",
                             label=f"thesis mean {thesis.mean(fault, 3):.1f} s")
            total_ax.legend(fontsize=8)
        total_ax.set_xlabel("run")
        total_ax.set_ylabel("total (simulated s)")
        total_ax.set_title(f"{fault}: total per run (red = wrong diagnosis)")
        fig.tight_layout()
        fig.savefig(plots / f"{fault}.png", dpi=80)
        plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="./run.sh campaign", description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=10, help="runs per scenario (default 10)")
    parser.add_argument("--out", type=Path, default=None,
                        help="the folder for the report (default: out/campaign, with --mission "
                             "out/campaign-mission)")
    parser.add_argument("--faults", nargs="+", choices=FAULTS, default=list(FAULTS))
    parser.add_argument("--first-seed", type=int, default=1)
    parser.add_argument("--hosts", action="store_true",
                        help="every run across hosts of its own (./run.sh demo --hosts; root)")
    parser.add_argument("--drivers", choices=sorted(WIRINGS), default=SIM.drivers.value,
                        help="every run under this driver profile (./run.sh demo --drivers; "
                             "docs/drivers.md)")
    parser.add_argument("--vision", choices=[v.value for v in VisionPath], default=None,
                        help="with --drivers stock: nodelets (default) or raw (./run.sh demo "
                             "--vision; docs/drivers.md)")
    parser.add_argument("--world", type=Path, default=None,
                        help="every run in this world file (./run.sh demo --world; with "
                             "--layouts random: its room, light and camera under each layout)")
    parser.add_argument("--colours", type=Path, default=None,
                        help="the synthesizer's colours file (rosrun rason_vision calibrate; "
                             "default: the one the world names in vision.colours)")
    parser.add_argument("--layouts", choices=("fixed", "random"), default="fixed",
                        help="fixed: the thesis' layout; random: a seeded layout per run index "
                             "(the same N layouts for every fault)")
    parser.add_argument("--mission", action="store_true",
                        help="run the mission (./run.sh mission) instead of the demo: completion, "
                             "time, waypoint errors and contacts per fault (docs/mission.md)")
    recovery = parser.add_mutually_exclusive_group()
    recovery.add_argument("--no-recovery", action="store_true",
                          help="with --mission: only the baseline, every mission without recovery")
    recovery.add_argument("--baseline", action="store_true",
                          help="with --mission: every mission with recovery and again without it "
                               "(the baseline), side by side in one report")
    parser.add_argument("--report-only", action="store_true",
                        help="only rewrite report.md and the plots from the runs.csv in --out "
                             "(e.g. of a campaign cut short)")
    args = parser.parse_args(argv)
    try:
        wiring_for(args.drivers, args.vision)
    except ValueError as err:
        parser.error(str(err))
    for flag, path in (("--world", args.world), ("--colours", args.colours)):
        if path is not None and not path.is_file():
            parser.error(f"{flag} {path}: no such file")
    args.out = args.out or Path("out") / ("campaign-mission" if args.mission else "campaign")
    if args.mission:
        return mission_campaign(parser, args)
    if args.no_recovery or args.baseline:
        parser.error("--no-recovery and --baseline go with --mission")
    if args.report_only:
        return report_only(args)
    (args.out / "runs").mkdir(parents=True, exist_ok=True)
    if args.layouts == "random":
        return random_campaign(args)

    jobs = [(fault, args.first_seed + i) for i in range(args.runs) for fault in args.faults]
    results: list[dict] = []
    started = time.monotonic()
    for done, (fault, seed) in enumerate(jobs, 1):
        results.append(run_one(fault, seed, args.out, demo_options(args)))
        progress(done, len(jobs), started, results[-1])
        with open(args.out / "runs.csv", "w", newline="") as f:
            writer = csv.DictWriter(f, FIELDS, extrasaction="ignore")
            writer.writeheader()
            writer.writerows(results)
    print()
    write_plots(results, args.out)
    print(write_report(results, args.out, args.runs))
    print(f"wrote {args.out / 'runs.csv'}, {args.out / 'report.md'}, {args.out / 'plots'}")
    return 0 if all(r.get("correct") and not r.get("orphans") for r in results) else 1


def mission_campaign(parser: argparse.ArgumentParser, args: argparse.Namespace) -> int:
    """``--mission``: the mission over faults x seeds (rason_diagnosis.mission_campaign)."""
    from rason_diagnosis import mission_campaign as mc

    if (args.hosts or args.layouts != "fixed" or args.drivers != SIM.drivers.value
            or args.vision or args.colours):
        parser.error("--mission runs the simulated mission in one world: --hosts, --layouts "
                     "random, --drivers stock, --vision and --colours do not apply")
    if args.report_only:
        results = mc.load_runs(args.out)
        if not results:
            parser.error(f"--report-only: no runs/*/result.json in {args.out}")
        mc.write_csv(results, args.out)
        mc.write_plots(results, args.out)
        print(mc.write_report(results, args.out))
        return 0
    modes = ([mc.Mode.BASELINE] if args.no_recovery else
             [mc.Mode.RECOVERY, mc.Mode.BASELINE] if args.baseline else [mc.Mode.RECOVERY])
    seeds = [args.first_seed + i for i in range(args.runs)]
    results = mc.run_campaign(args.faults, seeds, modes, args.out,
                              ["--world", str(args.world)] if args.world else [])
    print(f"wrote {args.out / 'runs.csv'}, {args.out / 'report.md'}, {args.out / 'plots'}, "
          f"{args.out / 'runs'}")
    return 0 if all(r.get("completed") and not r.get("orphans") for r in results) else 1


# -- randomized layouts -----------------------------------------------------------------------

LAYOUT_FIELDS = ("distance", "bearing", "relative_heading", "helper_x", "helper_y", "helper_yaw",
                 "faulty_x", "faulty_y", "faulty_yaw")
OUTCOME_COLOURS = {Outcome.RIGHT: "tab:green", Outcome.UNKNOWN: "tab:orange",
                   Outcome.WRONG: "tab:red"}


def outcome(result: dict) -> str:
    """right, unknown (no component named, or no answer) or wrong (a wrong component)."""
    return outcome_of(result.get("correct"), result.get("diagnosis")).value


def random_campaign(args: argparse.Namespace) -> int:
    """Every fault in N seeded random layouts; report.md, runs.csv, layouts.csv, plots."""
    from rason_diagnosis.layouts import random_layout, write_world

    base = args.world or world_file()
    room = tuple(yaml.safe_load(base.read_text()).get("room", {}).get("size", (10.0, 10.0)))
    layouts = [random_layout(args.first_seed + i, room) for i in range(args.runs)]
    worlds = {lay.seed: write_world(lay, base, args.out / "worlds" / f"layout-{lay.seed}.yaml")
              for lay in layouts}
    jobs = [(fault, lay) for lay in layouts for fault in args.faults]
    results: list[dict] = []
    started = time.monotonic()
    for done, (fault, lay) in enumerate(jobs, 1):
        extra = ["--world", str(worlds[lay.seed]), *demo_options(args)]
        result = run_one(fault, lay.seed, args.out, extra)
        result.update({k: round(getattr(lay, k), 3) for k in LAYOUT_FIELDS})
        result["outcome"] = outcome(result)
        results.append(result)
        progress(done, len(jobs), started, result)
        with open(args.out / "runs.csv", "w", newline="") as f:
            writer = csv.DictWriter(f, (*FIELDS, "outcome", *LAYOUT_FIELDS), extrasaction="ignore")
            writer.writeheader()
            writer.writerows(results)
    print()
    write_layout_plot(results, args.out)
    print(write_layout_report(results, layouts, args.out))
    print(f"wrote {args.out / 'runs.csv'}, {args.out / 'report.md'}, {args.out / 'plots'}")
    wrong = sum(1 for r in results if r["outcome"] == Outcome.WRONG)
    return 0 if wrong == 0 and not orphans(results) else 1


def _from_csv(row: dict) -> dict:
    """A runs.csv row with its numbers and flags parsed back."""
    out: dict = {}
    for key, value in row.items():
        if value in ("", None):
            out[key] = None
        elif key in ("correct",):
            out[key] = value == "True"
        elif key in ("seed", "orphans"):
            out[key] = int(value)
        else:
            try:
                out[key] = float(value)
            except ValueError:
                out[key] = value
    return out


def report_only(args: argparse.Namespace) -> int:
    """Rewrite report.md and plots from ``--out``/runs.csv."""
    from rason_diagnosis.layouts import random_layout

    with open(args.out / "runs.csv", newline="") as f:
        results = [_from_csv(row) for row in csv.DictReader(f)]
    if results and "outcome" in results[0]:
        room = tuple(yaml.safe_load(world_file().read_text()).get("room", {}).get(
            "size", (10.0, 10.0)))
        seeds = sorted({r["seed"] for r in results})
        write_layout_plot(results, args.out)
        print(write_layout_report(results, [random_layout(s, room) for s in seeds], args.out))
    else:
        runs = max((sum(1 for r in results if r["fault"] == f) for f in FAULTS), default=0)
        write_plots(results, args.out)
        print(write_report(results, args.out, runs))
    return 0


def write_layout_report(results: list[dict], layouts: list, out: Path) -> str:
    runs = len(layouts)
    lines = [f"# Cooperative fault diagnosis in {runs} random layout(s) per fault", "",
             "Faulty 0.8-4 m from Helper at any bearing, both robots at any heading, inside the "
             "room (`rason_diagnosis.layouts`); the same layouts for every fault. Latencies in "
             "simulated seconds. right: the injected fault; unknown: no component named (or no "
             "answer); wrong: a wrong component.", "",
             *table_head("fault", "right", "unknown", "wrong", "location mean (max)",
                         "total mean (max)")]
    for fault in faults_run(results):
        mine = [r for r in results if r["fault"] == fault]
        count = {k: sum(1 for r in mine if r["outcome"] == k) for k in OUTCOME_COLOURS}
        loc = [r["location_s"] for r in mine if r.get("location_s") is not None]
        tot = [r["total_s"] for r in mine if r.get("total_s") is not None]
        lines.append(f"| {fault} | {count[Outcome.RIGHT]}/{len(mine)} | {count[Outcome.UNKNOWN]} | "
                     f"{count[Outcome.WRONG]} | {fmt(mean(loc))} ({fmt(max(loc, default=None))}) | "
                     f"{fmt(mean(tot))} ({fmt(max(tot, default=None))}) |")
    total = {k: sum(1 for r in results if r["outcome"] == k) for k in OUTCOME_COLOURS}
    lines += ["", f"Overall: {total[Outcome.RIGHT]}/{len(results)} right "
              f"({100.0 * total[Outcome.RIGHT] / max(1, len(results)):.0f}%), "
              f"{total[Outcome.UNKNOWN]} unknown, "
              f"{total[Outcome.WRONG]} wrong. Processes left running: {orphans(results)}.", "",
              *image_link(out, "plots/layouts.png", "outcome against the layout"),
              "## Layouts", "",
              *table_head("seed", "distance (m)", "bearing (deg)", "relative heading (deg)",
                          "Helper x, y, yaw", "Faulty x, y, yaw", "outcomes")]
    for lay in layouts:
        mine = [r for r in results if r["seed"] == lay.seed]
        outcomes = ", ".join(f"{r['fault']}: {r.get('diagnosis')} ({r['outcome']})" for r in mine)
        lines.append(f"| {lay.seed} | {lay.distance:.2f} | {lay.bearing:.0f} | "
                     f"{lay.relative_heading:.0f} | {lay.helper_x:.2f}, {lay.helper_y:.2f}, "
                     f"{lay.helper_yaw:.0f} | {lay.faulty_x:.2f}, {lay.faulty_y:.2f}, "
                     f"{lay.faulty_yaw:.0f} | {outcomes} |")
    return save_report(out, lines)


def write_layout_plot(results: list[dict], out: Path) -> None:
    """Outcome (colour) of every run against bearing, distance and relative heading."""
    plots = plots_dir(out)
    faults = faults_run(results)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4), sharey=True)
    for ax, key, label, span in zip(
            axes, ("bearing", "distance", "relative_heading"),
            ("bearing of Faulty from Helper (deg, + = right)", "distance (m)",
             "Faulty's heading - line of sight (deg, -90 = thesis)"),
            ((-180, 180), (0.7, 4.1), (-180, 180)), strict=True):
        ax.set_xlim(*span)
        for kind, colour in OUTCOME_COLOURS.items():
            pts = [(r[key], faults.index(r["fault"])) for r in results if r["outcome"] == kind]
            if pts:
                ax.scatter(*zip(*pts, strict=True), c=colour, label=kind, s=30,
                           edgecolors="k", linewidths=0.3)
        ax.set_xlabel(label)
        ax.grid(alpha=0.3)
    axes[0].set_yticks(range(len(faults)))
    axes[0].set_yticklabels(faults)
    axes[0].legend(fontsize=8)
    fig.suptitle("outcome of every run against the layout")
    fig.tight_layout()
    fig.savefig(plots / "layouts.png", dpi=80)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main())
