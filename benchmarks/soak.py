#!/usr/bin/env python3
"""Soak: memory stays flat while an agent runs for long.

1. Recursion: an agent loops by recursion (``+!loop : n(N) & N < M <- -+n(N+1); !loop.``) for
   a million iterations, in this process; its RSS after warm-up and at the end (target: within
   10%), beside the same loop with tail-recursion optimisation off (the peer: Jason's
   ``tro=false``), run for fewer iterations with the depth limit raised so it can grow.
2. Perception stream: a real ``rosrun rason agent`` node (real roscore) gets a perception list
   at 50 Hz for ``--minutes`` minutes, each with new values and, every tenth message, a distinct
   malformed string; the agent loops by recursion with ``.wait``. The node's RSS after warm-up
   and at the end (target: within 10%), and how many warnings it logged.

    ./run.sh bench soak [--minutes 10] [--iterations 1000000] [--quick]
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

from rason.asl import Agent, AgentArch, AgentOptions
from rason.testing.harness import RosHarness

LOOP = """n(0).
!loop.
+!loop : n(N) & N < {count} <- -+n(N+1); !loop.
+!loop : n(N) <- .print("done ", N).
"""

WATCHER = """!watch.
+!watch <- .wait(1000); !report; !watch.
+!report : robot(_, _, _, T)[source(percept)] <- -+seen(T).
+!report <- true.
+robot(_, X, _, _)[source(percept)] : X > 1000000 <- .print("never").
"""


def rss_mb(pid: int | str = "self") -> float:
    """Resident set size of a process, in MB (from /proc)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    raise RuntimeError(f"no VmRSS for {pid}")


class _Quiet(AgentArch):
    def console(self, agent_name: str, text: str) -> None:
        self.last = text


def recursion(iterations: int, tro: bool) -> dict[str, float]:
    """Run the loop agent in this process; RSS after warm-up and at the end."""
    arch = _Quiet()
    ag = Agent("looper", LOOP.format(count=iterations), arch,
               options=AgentOptions(tro=tro, max_intention_depth=iterations + 10))
    warmup = min(10_000, iterations // 10)
    steps = 0
    deepest = 0
    start_rss = start_t = 0.0
    while ag.step():
        steps += 1
        if steps == warmup:
            start_rss, start_t = rss_mb(), time.perf_counter()
        if steps % 1000 == 0:
            deepest = max([deepest, *(len(i.ims) for i in ag.all_intentions())])
    end_rss, end_t = rss_mb(), time.perf_counter()
    assert arch.last == f"done {iterations}", arch.last
    return {"iterations": iterations, "start": start_rss, "end": end_rss, "seconds": end_t - start_t,
            "deepest": deepest}


def perception_stream(minutes: float, warmup_s: float) -> dict[str, float]:
    """50 Hz of perceptions into a real agent node; its RSS after warm-up and at the end."""
    import rospy
    from jason_msgs.msg import Perception

    with tempfile.TemporaryDirectory() as tmp, RosHarness() as ros:
        asl = Path(tmp) / "watcher.asl"
        asl.write_text(WATCHER)
        agent = ros.rosrun("rason", "agent", "watcher", str(asl), ns="/soak", echo=False)
        ros.wait_for_node("/soak/jason/watcher", watch=[agent])
        ros.init_rospy("soak_publisher")
        pub = rospy.Publisher("/soak/jason/perception", Perception, queue_size=100)
        ros.wait_for_subscriber("/soak/jason/perception")
        rate = rospy.Rate(50)
        sent = 0
        start_rss = None
        t0 = time.monotonic()
        end = t0 + warmup_s + minutes * 60.0
        while time.monotonic() < end and not rospy.is_shutdown():
            k = sent
            texts = [f"robot(faulty,{k % 640},{(k * 7) % 480},{k})", f"battery({100 - k % 100})"]
            if k % 10 == 0:
                texts.append(f"robot(faulty,{k},NaN,{k})" if k % 20 == 0 else f"garbage({k}")
            pub.publish(Perception(source="soak_synth", perception=texts))
            sent += 1
            if start_rss is None and time.monotonic() - t0 >= warmup_s:
                start_rss = rss_mb(agent.pid)
            rate.sleep()
        time.sleep(1.0)
        end_rss = rss_mb(agent.pid)
        alive = agent.alive()
        warnings = sum("malformed perception" in line for line in agent.output().splitlines())
        ros.cleanup_logs()
    return {"messages": sent, "start": start_rss or end_rss, "end": end_rss, "alive": alive,
            "warnings": warnings, "minutes": minutes}


def _change(start: float, end: float) -> float:
    return 100.0 * (end - start) / start


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--minutes", type=float, default=10.0,
                        help="minutes of the 50 Hz perception stream (default 10)")
    parser.add_argument("--iterations", type=int, default=1_000_000,
                        help="iterations of the recursive loop (default 1,000,000)")
    parser.add_argument("--quick", action="store_true",
                        help="100,000 iterations and half a minute of perceptions")
    parser.add_argument("--skip-recursion", action="store_true")
    parser.add_argument("--skip-perception", action="store_true")
    args = parser.parse_args()
    iterations = 100_000 if args.quick else args.iterations
    minutes = 0.5 if args.quick else args.minutes

    rows = []
    if not args.skip_recursion:
        on = recursion(iterations, tro=True)
        print(f"  recursion, tro on: {on}", file=sys.stderr, flush=True)
        off = recursion(min(iterations, 100_000), tro=False)
        print(f"  recursion, tro off: {off}", file=sys.stderr, flush=True)
        rows += [("recursion, tro on (rason default)", on), ("recursion, tro off (peer)", off)]
    stream = None
    if not args.skip_perception:
        stream = perception_stream(minutes, warmup_s=min(30.0, 10.0 + minutes * 3.0))
        print(f"  perception stream: {stream}", file=sys.stderr, flush=True)

    if rows:
        print("\n| loop by recursion | iterations | s after warm-up | deepest intention | "
              "RSS start (MB) | RSS end (MB) | change |")
        print("|---|---|---|---|---|---|---|")
        for label, r in rows:
            print(f"| {label} | {r['iterations']:,} | {r['seconds']:.1f} | {r['deepest']:,} | "
                  f"{r['start']:.1f} | {r['end']:.1f} | {_change(r['start'], r['end']):+.1f}% |")
        on = rows[0][1]
        flat = abs(_change(on["start"], on["end"]))
        print(f"\nrecursion with tro: RSS change {flat:.1f}% (target within 10%) "
              f"{'PASS' if flat <= 10 else 'FAIL'}")
    if stream is not None:
        print("\n| 50 Hz perception stream into an agent node | minutes | messages | "
              "warnings logged | RSS start (MB) | RSS end (MB) | change | node alive |")
        print("|---|---|---|---|---|---|---|---|")
        print(f"| 2 percepts + 1 malformed in 10 messages | {stream['minutes']:g} | "
              f"{stream['messages']:,} | {stream['warnings']} | {stream['start']:.1f} | "
              f"{stream['end']:.1f} | {_change(stream['start'], stream['end']):+.1f}% | "
              f"{stream['alive']} |")
        flat = abs(_change(stream["start"], stream["end"]))
        print(f"\nperception stream: RSS change {flat:.1f}% (target within 10%) "
              f"{'PASS' if flat <= 10 and stream['alive'] else 'FAIL'}")
    return 0


if __name__ == "__main__":
    os.environ.setdefault("PYTHONUNBUFFERED", "1")
    sys.exit(main())
