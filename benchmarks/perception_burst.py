#!/usr/bin/env python3
"""Thesis Tables 5.1 and 5.2 through real ROS: reasoning-cycle time under perception bursts.

The Listing 5.4 agent (counting with ``-+value(X+1); !!goToDestination``) runs as a real
``rosrun rason agent`` node while ``rostopic pub -r F`` publishes N perceptions at F Hz on its
``jason/perception`` topic. Each cell is the mean milliseconds per loop iteration, measured by the
agent itself with ``.time``, in ``queue`` mode (every message applied: the thesis' unfiltered
Table 5.1) and in ``replace`` mode (per-source replacement: Table 5.2), beside the thesis' figures.
Then what per-agent perception filtering saves at the heaviest cell: the same run with the
agent filtering the burst out by source and by functor, and the agent process's CPU use while
the burst goes on after it finished counting.

    ./run.sh bench perception_burst [--count 100000] [--quick]
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

from rason.process.harness import RosHarness
from rason.process.procstat import cpu_seconds

N_VALUES = (1, 3, 5, 10)
F_VALUES = (1, 3, 5, 10, 30, 50)
THESIS = {  # (N, F): (Table 5.1 no filter, Table 5.2 filter), ms per reasoning cycle
    (1, 1): (0.48, 0.49), (1, 3): (0.50, 0.50), (1, 5): (0.49, 0.53), (1, 10): (0.57, 0.55),
    (1, 30): (0.89, 0.75), (1, 50): (1.12, 0.85),
    (3, 1): (0.50, 0.52), (3, 3): (0.54, 0.58), (3, 5): (0.56, 0.59), (3, 10): (0.57, 0.71),
    (3, 30): (1.03, 1.10), (3, 50): (1.24, 1.32),
    (5, 1): (0.54, 0.53), (5, 3): (0.57, 0.60), (5, 5): (0.67, 0.68), (5, 10): (0.83, 0.85),
    (5, 30): (1.35, 1.25), (5, 50): (1.88, 1.68),
    (10, 1): (0.64, 0.61), (10, 3): (0.99, 0.77), (10, 5): (1.04, 0.85), (10, 10): (1.05, 1.17),
    (10, 30): (2.26, 2.09), (10, 50): (6.23, 2.58),
}

LISTING_5_4 = """
value(0).
!start.
+!start : .time(X) <- +init(X); !goToDestination.
+!goToDestination : value(X) & X < {count} <- -+value(X+1); !!goToDestination.
+!goToDestination : value(X) & .time(T) & init(I) <- .puts("Done"); .print("ms_per_cycle ", ((T - I)/X)).
""" + "".join(f'+perception{i} <- .print("p{i}").\n' for i in range(1, 11))


def measure(ros: RosHarness, asl: Path, n: int, f: int, mode: str, ns: str,
            params: dict[str, object] | None = None, idle_s: float = 0.0) -> tuple[float, float]:
    """One cell: ms per loop iteration of the agent while N perceptions arrive at F Hz.

    With ``idle_s``, also the agent process's CPU use (percent of one core) over that many
    seconds after it finished counting, with the burst still arriving; else NaN.
    """
    percepts = "[" + ", ".join(f"'perception{i}'" for i in range(1, n + 1)) + "]"
    mark = len(ros.processes)
    try:
        ros.run(["rostopic", "pub", "-r", str(f), f"{ns}/jason/perception",
                 "jason_msgs/Perception", f"{{source: burst_synth, perception: {percepts}}}"],
                label=f"burst{ns}", echo=False)
        ros.wait_for_topic(f"{ns}/jason/perception", timeout=20)
        agent = ros.rosrun("rason", "agent", "bench", str(asl), ns=ns,
                           params={"perception_mode": mode, **(params or {})}, echo=False)
        match = agent.wait_for_line(r"ms_per_cycle (\S+)", timeout=300)
        cpu = math.nan
        if idle_s > 0:
            start_cpu, start = cpu_seconds(agent.pid), time.monotonic()
            time.sleep(idle_s)
            cpu = 100.0 * (cpu_seconds(agent.pid) - start_cpu) / (time.monotonic() - start)
        return float(match.group(1)), cpu
    finally:
        ros.stop_started_since(mark)



def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=100000,
                        help="iterations per run (the thesis counted to 3700; more is steadier)")
    parser.add_argument("--quick", action="store_true", help="only N in {1,10}, F in {1,50}")
    parser.add_argument("--no-filter", action="store_true",
                        help="skip the per-agent filtering measurement")
    args = parser.parse_args()
    ns_values = (1, 10) if args.quick else N_VALUES
    f_values = (1, 50) if args.quick else F_VALUES

    with tempfile.TemporaryDirectory() as tmp, RosHarness() as ros:
        asl = Path(tmp) / "bench.asl"
        asl.write_text(LISTING_5_4.format(count=args.count))
        results: dict[tuple[int, int, str], float] = {}
        cell = 0
        for n in ns_values:
            for f in f_values:
                for mode in ("queue", "replace"):
                    cell += 1
                    results[(n, f, mode)] = measure(ros, asl, n, f, mode, f"/pb{cell}")[0]
                    print(f"  N={n:2d} F={f:2d} Hz {mode:7s}: "
                          f"{results[(n, f, mode)]:.4f} ms/cycle", file=sys.stderr, flush=True)
        savings = {}
        if not args.no_filter:
            n, f = ns_values[-1], f_values[-1]
            for label, params in (("no filter", {}),
                                  ("perception_sources: [kinect]", {"perception_sources": ["kinect"]}),
                                  ("perception_functors: [robot/4]",
                                   {"perception_functors": ["robot/4"]})):
                cell += 1
                savings[label] = measure(ros, asl, n, f, "queue", f"/pb{cell}", params, idle_s=10.0)
                print(f"  filter {label}: {savings[label][0]:.4f} ms/cycle, "
                      f"{savings[label][1]:.1f}% CPU idle", file=sys.stderr, flush=True)
        ros.cleanup_logs()

    print(f"\nms per reasoning cycle (Listing 5.4, count to {args.count}); thesis = 1.8 GHz "
          "dual-core AMD64, Jason + rosjava\n")
    print("| N | F (Hz) | ours, queue | thesis 5.1 (no filter) | speed-up | ours, replace | "
          "thesis 5.2 (filter) | speed-up |")
    print("|---|---|---|---|---|---|---|---|")
    ratios = []
    for n in ns_values:
        for f in f_values:
            q, r = results[(n, f, "queue")], results[(n, f, "replace")]
            tq, tr = THESIS[(n, f)]
            ratios += [tq / q, tr / r]
            print(f"| {n} | {f} | {q:.4f} | {tq:.2f} | {tq / q:.0f}x | {r:.4f} | {tr:.2f} | "
                  f"{tr / r:.0f}x |")
    worst = min(ratios)
    base = results[(ns_values[0], f_values[0], "replace")]
    top = results[(ns_values[-1], f_values[-1], "replace")]
    print(f"\nslowest cell vs thesis: {worst:.1f}x faster (target: every cell >= 10x) "
          f"{'PASS' if worst >= 10 else 'FAIL'}")
    print(f"(N={ns_values[-1]}, {f_values[-1]} Hz) / (N={ns_values[0]}, {f_values[0]} Hz), replace: "
          f"{top / base:.2f} (target <= 2) {'PASS' if top / base <= 2 else 'FAIL'}")
    if savings:
        n, f = ns_values[-1], f_values[-1]
        print(f"\nper-agent perception filtering, N={n} perceptions at {f} Hz from source "
              "burst_synth, queue mode (every message applied unless filtered out):\n")
        print("| agent's filter | ms per cycle while counting | agent CPU while idle, burst going |")
        print("|---|---|---|")
        for label, (ms, cpu) in savings.items():
            print(f"| {label} | {ms:.4f} | {cpu:.1f}% of a core |")
        plain = savings["no filter"][1]
        best = min(cpu for _, cpu in savings.values())
        print(f"\nfiltering saves {plain - best:.1f} points of CPU ({plain:.1f}% -> {best:.1f}%) "
              "while nothing else happens")
    spread = statistics.pstdev([results[k] for k in results]) if len(results) > 1 else 0.0
    print(f"spread over all cells: sd {spread:.4f} ms")
    return 0


if __name__ == "__main__":
    sys.exit(main())
