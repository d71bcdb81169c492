#!/usr/bin/env python3
"""What the mind inspector costs a real agent node: the reasoning cycle with the mind published.

The Listing 5.4 agent (counting with ``-+value(X+1); !!goToDestination``) runs as a real
``rosrun rason agent`` node; we read the CPU time the node's process used while it counted
(from its "hosting" log line to its result, ``/proc``), per loop iteration, which other
processes on a busy machine do not inflate, and the agent's own ``.time`` figure (wall), with
``_mind_state_rate:=0`` (no ``jason/NAME/mind_state``), with the default 10 Hz and nobody
listening, and with 10 Hz while ``rosrun rason mind_inspector`` is subscribed (every state is
sent, parsed and kept). Runs are interleaved, best of ``--repeat``.

    ./run.sh bench mind_state_cost [--count 300000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

from rason.process.harness import RosHarness
from rason.process.procstat import cpu_seconds

LISTING_5_4 = """
value(0).
!start.
+!start : .time(X) <- +init(X); !goToDestination.
+!goToDestination : value(X) & X < {count} <- -+value(X+1); !!goToDestination.
+!goToDestination : value(X) & .time(T) & init(I) <- .puts("Done"); .print("ms_per_cycle ", ((T - I)/X)).
"""

VARIANTS = (("mind not published (_mind_state_rate:=0)", 0.0, False),
            ("published at 10 Hz, nobody listening", 10.0, False),
            ("published at 10 Hz, mind_inspector subscribed", 10.0, True))


def measure(ros: RosHarness, asl: Path, rate: float, ns: str, count: int) -> tuple[float, float]:
    """CPU µs and wall µs (the agent's .time) per loop iteration of one run."""
    mark = len(ros.processes)
    try:
        agent = ros.rosrun("rason", "agent", "bench", str(asl), ns=ns,
                           params={"mind_state_rate": rate}, echo=False)
        agent.wait_for_line(r"hosting bench", timeout=120)
        start = cpu_seconds(agent.pid)
        ms = float(agent.wait_for_line(r"ms_per_cycle (\S+)", timeout=900).group(1))
        return (cpu_seconds(agent.pid) - start) / count * 1e6, ms * 1000
    finally:
        ros.stop_started_since(mark)



def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--count", type=int, default=200000, help="iterations per run")
    parser.add_argument("--repeat", type=int, default=3, help="best of R runs per variant")
    args = parser.parse_args()
    results: dict[str, list[tuple[float, float]]] = {label: [] for label, _, _ in VARIANTS}
    with tempfile.TemporaryDirectory() as tmp, RosHarness() as ros:
        asl = Path(tmp) / "bench.asl"
        asl.write_text(LISTING_5_4.format(count=args.count))
        run = 0
        for _ in range(args.repeat):
            for label, rate, inspector in VARIANTS:
                run += 1
                mark = len(ros.processes)
                if inspector:
                    ros.rosrun("rason", "mind_inspector", params={"port": 0}, echo=False) \
                        .wait_for_line(r"mind inspector: http", timeout=60)
                try:
                    cpu, wall = measure(ros, asl, rate, f"/msc{run}", args.count)
                finally:
                    ros.stop_started_since(mark)
                results[label].append((cpu, wall))
                print(f"  {label}: CPU {cpu:.2f} µs/it, wall {wall:.2f} µs/it", file=sys.stderr,
                      flush=True)
        ros.cleanup_logs()
    off = min(cpu for cpu, _ in results[VARIANTS[0][0]])
    print(f"\nListing 5.4 as a ROS node, count to {args.count}, µs per loop iteration, "
          f"best of {args.repeat}\n")
    print("| agent node | CPU µs per iteration | vs not published | wall µs per iteration (.time) |")
    print("|---|---|---|---|")
    for label, _, _ in VARIANTS:
        cpu = min(c for c, _ in results[label])
        wall = min(w for _, w in results[label])
        print(f"| {label} | {cpu:.2f} | {100 * (cpu / off - 1):+.1f}% | {wall:.2f} |")
    worst = max(min(c for c, _ in v) for v in results.values()) / off - 1
    print(f"\nworst cost: {100 * worst:+.1f}% (target: under 5%) {'PASS' if worst < 0.05 else 'FAIL'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
