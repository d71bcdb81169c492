#!/usr/bin/env python3
"""Action round trip over loopback: agent act -> decomposer -> feedback -> intention resumed.

A real ``rosrun rason agent`` node performs ``move(I)`` 1000 times against the real
``rosrun rason echo_decomposer`` (which acknowledges and answers at once); the agent times each
action with ``.nano_time`` (ns of ROS time) and prints it in ms. Reports p50, p90, p99 and max.

    ./run.sh bench action_roundtrip [--actions 1000]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
from pathlib import Path

from rason.process.harness import RosHarness

AGENT = """
!start.
+!start <- .wait(1500); !loop(0).
+!loop(I) : I < {actions}
   <- .nano_time(T0); move(I); .nano_time(T1); .print("rt ", (T1 - T0) / 1000000); !loop(I + 1).
+!loop(I) <- .print("finished").
"""


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q / 100 * (len(ordered) - 1)))]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--actions", type=int, default=1000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp, RosHarness() as ros:
        asl = Path(tmp) / "roundtrip.asl"
        asl.write_text(AGENT.format(actions=args.actions))
        ros.rosrun("rason", "echo_decomposer", ns="/rt")
        ros.wait_for_subscriber("/rt/jason/action")
        agent = ros.rosrun("rason", "agent", "tripper", str(asl), ns="/rt")
        agent.wait_for_line(r"\[tripper\] finished", timeout=600)
        times = [float(line.split("rt ", 1)[1]) for line in agent.lines() if "] rt " in line]
        ros.cleanup_logs()
    if len(times) != args.actions:
        print(f"expected {args.actions} round trips, got {len(times)}", file=sys.stderr)
        return 1
    p50 = percentile(times, 50)
    print(f"\naction round trip over loopback, {len(times)} actions (ms)\n")
    print("| p50 | p90 | p99 | max | mean |")
    print("|---|---|---|---|---|")
    print(f"| {p50:.3f} | {percentile(times, 90):.3f} | {percentile(times, 99):.3f} | "
          f"{max(times):.3f} | {statistics.fmean(times):.3f} |")
    print(f"\ntarget p50 < 2 ms: {'PASS' if p50 < 2 else 'FAIL'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
