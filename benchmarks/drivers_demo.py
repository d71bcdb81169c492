#!/usr/bin/env python3
"""The demo under both driver profiles: diagnosis and total time per fault, sim against stock.

For each fault (and each seed) one ``./run.sh demo`` run under ``--drivers sim`` and one under
``--drivers stock``, alternated so both meet the same machine load; prints a table of the
diagnoses and the total diagnosis times (simulated seconds for sim, wall seconds for stock) and
the ratio of the stock total to the sim total (docs/drivers.md keeps the figures).

    ./run.sh bench drivers_demo [--faults F ...] [--seeds 1 ...] [--out DIR]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
from pathlib import Path

from rason_diagnosis.campaign import run_one
from rason_diagnosis.drivers import WIRINGS
from rason_diagnosis.scenario import FAULTS


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--faults", nargs="+", choices=FAULTS, default=list(FAULTS))
    parser.add_argument("--seeds", nargs="+", type=int, default=[1])
    parser.add_argument("--out", type=Path, default=Path("out") / "drivers_demo")
    args = parser.parse_args()
    rows = []
    for seed in args.seeds:
        for fault in args.faults:
            row = {"fault": fault, "seed": seed}
            for drivers in sorted(WIRINGS, reverse=True):        # stock first, then sim
                (args.out / drivers / "runs").mkdir(parents=True, exist_ok=True)
                result = run_one(fault, seed, args.out / drivers,
                                 ["--drivers", drivers, "--no-inspector"])
                row[drivers] = result
                print(f"{fault:15s} seed {seed} {drivers:5s}: {result.get('diagnosis')} "
                      f"({'right' if result.get('correct') else 'NOT right'}), total "
                      f"{result.get('total_s')} s, wall {result.get('wall_s')} s, load "
                      f"{os.getloadavg()[0]:.1f}", flush=True)
            rows.append(row)
    print("\n| fault | seed | sim: diagnosis | sim: total (sim s) | stock: diagnosis | "
          "stock: total (wall s) | stock / sim |")
    print("|---|---|---|---|---|---|---|")
    ratios = []
    for row in rows:
        sim, stock = row["sim"], row["stock"]
        ratio = (stock["total_s"] / sim["total_s"]
                 if sim.get("total_s") and stock.get("total_s") else None)
        if ratio is not None:
            ratios.append(ratio)
        print(f"| {row['fault']} | {row['seed']} | {sim.get('diagnosis')} | {sim.get('total_s')} "
              f"| {stock.get('diagnosis')} | {stock.get('total_s')} | "
              f"{'-' if ratio is None else f'{ratio:.2f}'} |")
    sums = {d: sum(r[d].get("total_s") or 0.0 for r in rows) for d in ("sim", "stock")}
    print(f"\ntotal diagnosis time over all runs: sim {sums['sim']:.2f} s, stock "
          f"{sums['stock']:.2f} s, stock / sim {sums['stock'] / max(sums['sim'], 1e-9):.2f}"
          + (f"; median per-run ratio {statistics.median(ratios):.2f}" if ratios else ""))
    right = all(r[d].get("correct") for r in rows for d in ("sim", "stock"))
    return 0 if right else 1


if __name__ == "__main__":
    sys.exit(main())
