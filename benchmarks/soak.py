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
3. Inspector under load (``--inspector``): ``rosrun rason mind_inspector`` gets a flood of
   presence beats under new names (``--names`` in ``--flood-s`` seconds, 85,000 in 20 s by
   default) and the mind_state of an agent holding a 10 MB belief (a new state every half
   second), with a page's event stream open. Its RSS and the latency of ``GET /api/agents``,
   sampled every second, beside the same for the inspector of git revision ``--compare``
   (default ``main``; ``none`` to skip), run from a temporary ``git worktree`` in the same run.

    ./run.sh bench soak [--minutes 10] [--iterations 1000000] [--quick]
    ./run.sh bench soak --inspector [--compare main] [--names 85000] [--flood-s 20]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request
from dataclasses import dataclass, field
from pathlib import Path

from rason.asl import Agent, AgentArch, AgentOptions
from rason.process.harness import RosHarness

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
            deepest = max([deepest, *(len(i.ims) for i in ag.circ.all_intentions())])
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


ROOT = Path(__file__).resolve().parent.parent
BELIEF_BYTES = 10 * 1024 * 1024


@dataclass
class InspectorRun:
    """One inspector under the load: its RSS and /api/agents latency, sampled every second."""

    label: str
    process: object
    url: str
    rss: list[float] = field(default_factory=list)
    latency: list[float | None] = field(default_factory=list)     # None: no answer in 30 s
    listed: list[int] = field(default_factory=list)
    events_bytes: int = 0

    def sample(self) -> None:
        self.rss.append(rss_mb(self.process.pid) if self.process.alive() else float("nan"))
        start = time.perf_counter()
        try:
            with urllib.request.urlopen(self.url + "api/agents", timeout=30) as reply:
                count = len(json.loads(reply.read())["agents"])
            self.latency.append(time.perf_counter() - start)
            self.listed.append(count)
        except (OSError, ValueError):
            self.latency.append(None)

    def sample_every_second(self, until: float) -> None:
        """Sample until time.monotonic() passes `until` (a thread of its own per inspector)."""
        next_sample = time.monotonic()
        while next_sample < until:
            self.sample()
            next_sample += 1.0
            time.sleep(max(0.0, next_sample - time.monotonic()))

    def read_events(self) -> None:
        """A page's event stream, read and dropped (until the inspector closes it)."""
        try:
            with urllib.request.urlopen(self.url + "api/events", timeout=60) as stream:
                while chunk := stream.read(65536):
                    self.events_bytes += len(chunk)
        except OSError:
            pass


def _start_inspector(ros: RosHarness, label: str, src: Path | None) -> InspectorRun:
    """This tree's inspector (``src`` None) or the one of another checkout's rason sources."""
    name = f"inspector_{label.replace(' ', '_')}"
    if src is None:
        proc = ros.rosrun("rason", "mind_inspector", name=name, params={"port": 0}, echo=False)
    else:
        env = {"PYTHONPATH": f"{src}:{os.environ.get('PYTHONPATH', '')}"}
        proc = ros.run([sys.executable, "-c", "import sys; from rason.inspector.main import main; "
                        "sys.exit(main())", f"__name:={name}", "_port:=0"], label=name,
                       env=env, echo=False)
    url = proc.wait_for_line(r"mind inspector: (http://127\.0\.0\.1:\d+/)", 120).group(1)
    return InspectorRun(label, proc, url)


def _worktree(rev: str, where: Path) -> Path:
    subprocess.run(["git", "-C", str(ROOT), "worktree", "add", "--detach", "-q", str(where), rev],
                   check=True)
    return where / "catkin_ws" / "src" / "rason" / "src"


def inspector_load(names: int, flood_s: float, compare: str) -> list[InspectorRun]:
    """The flood of names and the 10 MB belief, into this tree's inspector (and `compare`'s)."""
    import rospy
    from jason_msgs.msg import AgentMessage

    with tempfile.TemporaryDirectory() as tmp, RosHarness() as ros:
        tree = Path(tmp) / "compare"
        runs = [_start_inspector(ros, "this branch", None)]
        try:
            if compare != "none":
                runs.append(_start_inspector(ros, compare, _worktree(compare, tree)))
            ros.init_rospy("soak_flood")
            messages = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10000)
            ros.wait_for_subscriber("/jason/messages")
            readers = [threading.Thread(target=r.read_events, daemon=True) for r in runs]
            for reader in readers:
                reader.start()

            def beat(name: str) -> AgentMessage:
                return AgentMessage(sender=name, performative="presence")

            big = ros.run([sys.executable, __file__, "--big-mind"], label="big_mind", echo=False)
            ros.wait_for_topic("/soak/jason/big/mind_state", watch=[big], timeout=60)
            for _ in range(3):                          # warm-up: the big agent alone
                for r in runs:
                    r.sample()
                time.sleep(1.0)
            start = time.monotonic()
            end = start + flood_s + 15.0
            samplers = [threading.Thread(target=r.sample_every_second, args=(end,), daemon=True)
                        for r in runs]
            for sampler in samplers:
                sampler.start()
            sent = 0
            while (now := time.monotonic()) < end:
                due = min(names, int(names * (now - start) / flood_s))
                while sent < due:
                    messages.publish(beat(f"flood_{sent}"))
                    sent += 1
                time.sleep(0.005)
            for sampler in samplers:
                sampler.join(60)
            states = sum("published" in line for line in big.lines())
            print(f"  sent {sent:,} presence beats under new names; {states} big states",
                  file=sys.stderr, flush=True)
        finally:
            ros.stop()
            if tree.exists():
                subprocess.run(["git", "-C", str(ROOT), "worktree", "remove", "--force",
                                str(tree)], check=False)
        ros.cleanup_logs()
    return runs


def big_mind() -> None:
    """An agent "big" holding a 10 MB belief: presence beats and a new mind state every 0.5 s
    (a process of its own, so the flood does not slow it), until it is stopped."""
    import rospy
    from jason_msgs.msg import AgentMessage
    from std_msgs.msg import String

    rospy.init_node("soak_big_mind", anonymous=True)
    messages = rospy.Publisher("/jason/messages", AgentMessage, queue_size=10)
    mind = rospy.Publisher("/soak/jason/big/mind_state", String, queue_size=1, latch=True)
    filler = "x" * BELIEF_BYTES
    k = 0
    while not rospy.is_shutdown():
        messages.publish(AgentMessage(sender="big", performative="presence"))
        mind.publish(String(json.dumps({
            "agent": "big", "node": "/soak/jason", "namespace": "/soak/", "stamp": float(k),
            "mind": {"beliefs": [
                {"text": f'big("{filler}")', "group": "big/1", "annots": [], "sources": ["self"]},
                {"text": f"count({k})", "group": "count/1", "annots": [], "sources": ["self"]}]}})))
        print(f"state {k} published", flush=True)
        k += 1
        time.sleep(0.5)


def _inspector_table(runs: list[InspectorRun], names: int, flood_s: float) -> None:
    print(f"\n| mind inspector: {names:,} new names in {flood_s:g} s + a 10 MB belief every 0.5 s"
          " | RSS before (MB) | RSS peak (MB) | RSS end (MB) | /api/agents median (s) | max (s) |"
          " unanswered (of samples) | agents listed, most |")
    print("|---|---|---|---|---|---|---|---|")
    for r in runs:
        answered = [t for t in r.latency if t is not None]
        peak = max((x for x in r.rss if x == x), default=float("nan"))
        print(f"| {r.label} | {r.rss[0]:.0f} | {peak:.0f} | {r.rss[-1]:.0f} | "
              f"{statistics.median(answered) if answered else float('nan'):.3f} | "
              f"{max(answered) if answered else float('nan'):.3f} | "
              f"{len(r.latency) - len(answered)} of {len(r.latency)} | "
              f"{max(r.listed, default=0):,} |")


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
    parser.add_argument("--inspector", action="store_true",
                        help="only the mind inspector under a flood of names and a 10 MB belief")
    parser.add_argument("--compare", default="main",
                        help="git revision whose inspector runs beside (default main; none)")
    parser.add_argument("--names", type=int, default=85_000,
                        help="presence beats under new names in the flood (default 85,000)")
    parser.add_argument("--flood-s", type=float, default=20.0,
                        help="seconds the flood of names lasts (default 20)")
    parser.add_argument("--big-mind", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.big_mind:
        big_mind()
        return 0
    if args.inspector:
        runs = inspector_load(args.names, args.flood_s, args.compare)
        _inspector_table(runs, args.names, args.flood_s)
        return 0
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
