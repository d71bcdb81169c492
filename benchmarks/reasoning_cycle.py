#!/usr/bin/env python3
"""Reasoning-cycle benchmark: the thesis' Listing 5.4 agent on rason.asl and on PyPI agentspeak.

The agent counts ``value(X)`` up to N with ``-+value(X+1); !!goToDestination`` (the thesis'
``++value`` is a typo for ``-+``), one new intention per loop iteration. We report the mean
time per loop iteration (µs) for:

* rason.asl (this repository), in this process, with its reasoning cycle compiled by mypyc
  (``rason.asl.native``, built by setup.sh), and the same modules run as Python
  (``RASON_NATIVE=0``) in a child process;
* the PyPI ``agentspeak==0.2.2`` stock runtime on the same program (minimally adapted to its
  dialect: no ``.time``/``.puts``), installed by this script into a throwaway venv under a
  temporary directory and run as a subprocess (skipped with --no-agentspeak or when pip
  cannot install it);
* for scale, real Jason on the JVM: about 2.7 µs per iteration (reference figure), or measured
  in this run with ``--jason-jar CLASSPATH`` (Jason 3's jar and the javax.json jars it needs):
  the same loop counted to N four times in one agent (``.nano_time``), the best of the last
  three (warm) passes;
* as whole processes: ``python -m rason.asl run`` against ``python -m agentspeak`` on the same
  program counting to 100000, wall and CPU time of the process (best of R; target: 5x), both
  with their compiled modules (``PYTHONDONTWRITEBYTECODE`` is dropped for the children, whose
  modules are compiled by one untimed run of each and kept under the temporary folder).

Then the cost of the mind inspector for the reasoning cycle: the same agent while a thread
publishes its mind exactly as the agent node does (``rason.ros.mind_state``: a timer thread
ticks, the agent's thread takes the snapshot at its next cycle when it is busy, JSON, compare
with the last one; the text is dropped instead of sent) at the
node's default ``~mind_state_rate`` (10 Hz) and at 100 Hz, against no publication, interleaved,
best of R; also with 200 more beliefs in the mind (a snapshot costs more for a larger mind).
The cost is compared in CPU time of the process (both threads) per iteration, which other
processes on a busy machine do not inflate; wall time is shown beside it.

Both interpreters are timed in CPU time of their process (wall time on a machine shared with
other work mostly measures waiting for a core); both run a 2000-iteration warm-up first, and a
garbage collection precedes each timed run; the best of ``--repeat`` runs counts (more for
small N, the same number for both: about 200000 timed iterations).

Usage: python3 benchmarks/reasoning_cycle.py [--counts 3700 100000] [--repeat 3] [--no-agentspeak]
       [--no-mind-state] [--jason-jar CLASSPATH] [--whole-count 100000]
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "catkin_ws", "src", "rason", "src"))

from rason.asl import Agent, AgentArch, WallClock, native  # noqa: E402

JASON_JVM_US = 2.7
WARM_UP = 2000      # iterations run once, untimed, before measuring (both interpreters)
TARGET_SPEEDUP = 3.0
TARGET_WHOLE_SPEEDUP = 5.0

# Jason on the JVM: the loop counted to {n} four times in one agent; each pass prints its µs
# per iteration (the first pass warms the JIT up).
JASON_PROGRAM = """
value(0).
pass(0).
!start.
+!start : .nano_time(T) <- -+init(T); !!count.
+!count : value(X) & X < {n} <- -+value(X+1); !!count.
+!count : pass(P) & P < 4 & .nano_time(T) & init(I) & value(X)
   <- .print("pass ", P, " ", (T - I) / X / 1000); -+pass(P + 1); -+value(0);
      .nano_time(T2); -+init(T2); !!count.
+!count <- .stopMAS.
"""
JASON_LOGGING = """handlers = java.util.logging.ConsoleHandler
.level = INFO
java.util.logging.ConsoleHandler.level = INFO
java.util.logging.ConsoleHandler.formatter = java.util.logging.SimpleFormatter
java.util.logging.SimpleFormatter.format = %5$s%n
"""

PERCEPTION_PLANS = "\n".join(f'+perception{k} <- .print("p{k}").' for k in range(1, 11))

# Listing 5.4 (fixed: -+value). .time(T) with one argument = milliseconds (thesis' modification).
LISTING_5_4 = """
value(0).
!start.
+!start : .time(X) <- +init(X); !goToDestination.
+!goToDestination : value(X) & X < {n} <- -+value(X+1); !!goToDestination.
+!goToDestination : value(X) & .time(T) & init(I) <- .puts("Done"); .print(((T - I)/X)).
""" + PERCEPTION_PLANS

# The same program in agentspeak 0.2.2's dialect (no .time/.puts; timed from outside).
AGENTSPEAK_PROGRAM = """
value(0).
!start.
+!start <- !goToDestination.
+!goToDestination : value(X) & X < {n} <- -+value(X+1); !!goToDestination.
+!goToDestination : value(X) <- .print("Done", X).
""" + PERCEPTION_PLANS

AGENTSPEAK_RUNNER = r"""
import gc, json, sys, time
import agentspeak.runtime, agentspeak.stdlib
def timed(path):
    env = agentspeak.runtime.Environment()
    with open(path) as f:
        agent = env.build_agent(f, agentspeak.stdlib.actions)
    gc.collect()
    t0 = time.process_time()
    env.run()
    return time.process_time() - t0
timed(sys.argv[1])                      # warm-up, as for rason.asl
print(json.dumps({"elapsed": min(timed(sys.argv[2]) for _ in range(int(sys.argv[3])))}))
"""


class QuietArch(AgentArch):
    """No environment, console collected in memory."""

    def __init__(self) -> None:
        super().__init__(WallClock())
        self.lines: list[str] = []

    def console(self, agent_name: str, text: str) -> None:
        self.lines.append(text)


def bench_rason(n: int) -> tuple[float, str]:
    """µs per iteration (CPU time of the whole run / n: other work on a busy machine inflates
    it less than wall time) and the agent's own figure (ms, wall)."""
    arch = QuietArch()
    ag = Agent("bench", LISTING_5_4.format(n=n), arch)
    gc.collect()
    t0 = time.process_time()
    step = ag.step
    while step():
        pass
    t1 = time.process_time()
    assert arch.lines and arch.lines[0] == "Done", arch.lines
    return (t1 - t0) / n * 1e6, arch.lines[-1]


MIND_STATE_COUNT = 200000            # iterations per run: about 1 s, 10 publications at 10 Hz
MIND_STATE_RATES = (0.0, 10.0, 100.0)
BIG_MIND = "".join(f'fact({k}, "a belief of the larger mind", [{k}, {k + 1}]).\n' for k in range(200))


class PublishingArch(QuietArch):
    """QuietArch that runs ``at_next_cycle`` once at the next reasoning cycle, as RosAgArch."""

    at_next_cycle = None

    def perceive(self):
        if self.at_next_cycle is not None:
            hook, self.at_next_cycle = self.at_next_cycle, None
            hook()
        return None


def bench_rason_as_python(n: int, repeat: int) -> float | None:
    """µs per iteration of :func:`bench_rason` in a child process running rason.asl's modules as
    Python (``RASON_NATIVE=0``): the best of ``repeat`` runs after the warm-up."""
    code = (f"import sys; sys.path.insert(0, {HERE!r}); import reasoning_cycle as r; "
            f"r.bench_rason(r.WARM_UP); print(min(r.bench_rason({n})[0] for _ in range({repeat})))")
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=3600,
                          env={**os.environ, native.SWITCH: "0"})
    if proc.returncode != 0:
        print(f"note: the Python run failed: {proc.stderr.strip()[-300:]}", file=sys.stderr)
        return None
    return float(proc.stdout.strip().splitlines()[-1])


def bench_mind_state(n: int, hz: float, extra: str = "") -> tuple[float, float, int, float]:
    """CPU and wall µs per iteration while the mind is published at `hz` (0: not at all), the
    number of publications and the mean µs of one timer tick (a snapshot + JSON + compare when the agent
    was between cycles; else only leaving the snapshot to the agent's thread)."""
    from rason.ros.mind_state import MindStatePublisher

    arch = PublishingArch()
    ag = Agent("bench", extra + LISTING_5_4.format(n=n), arch)
    sent: list[str] = []
    publisher = MindStatePublisher(ag, lambda: [], sent.append, "/bench", "/",
                                   schedule=lambda hook: setattr(arch, "at_next_cycle", hook))
    stop = threading.Event()
    ticks: list[float] = []

    def publish() -> None:
        period = 1.0 / hz
        deadline = time.perf_counter()
        while not stop.is_set():
            start = time.perf_counter()
            publisher.tick(start)
            ticks.append(time.perf_counter() - start)
            deadline += period
            stop.wait(max(0.0, deadline - time.perf_counter()))

    thread = threading.Thread(target=publish, daemon=True) if hz > 0 else None
    gc.collect()
    c0, t0 = time.process_time(), time.perf_counter()
    if thread is not None:
        thread.start()
    step = ag.step
    while step():
        pass
    stop.set()
    if thread is not None:
        thread.join()
    c1, t1 = time.process_time(), time.perf_counter()
    assert arch.lines and arch.lines[0] == "Done", arch.lines
    return ((c1 - c0) / n * 1e6, (t1 - t0) / n * 1e6, len(sent),
            sum(ticks) / len(ticks) * 1e6 if ticks else 0.0)


def mind_state_table(repeat: int) -> None:
    print(f"\nCost of publishing the mind (rason.ros.mind_state) for the reasoning cycle: "
          f"Listing 5.4, count to {MIND_STATE_COUNT}, best of {repeat}, interleaved")
    print(f"{'mind':>14} | {'publication':>11} | {'CPU µs/it':>9} | {'vs off':>7} | "
          f"{'wall µs/it':>10} | {'publications':>12} | {'µs per tick':>11}")
    print("-" * 94)
    for label, extra in (("Listing 5.4", ""), ("+ 200 beliefs", BIG_MIND)):
        best: dict[float, tuple[float, float, int, float]] = {}
        for _ in range(repeat):
            for hz in MIND_STATE_RATES:
                run = bench_mind_state(MIND_STATE_COUNT, hz, extra)
                if hz not in best or run[0] < best[hz][0]:
                    best[hz] = run
        off = best[0.0][0]
        for hz in MIND_STATE_RATES:
            cpu, wall, count, tick = best[hz]
            rate = "off" if hz == 0 else f"{hz:g} Hz"
            print(f"{label:>14} | {rate:>11} | {cpu:9.2f} | {100 * (cpu / off - 1):+6.1f}% | "
                  f"{wall:10.2f} | {count:>12} | {tick:11.0f}")
    print("target: under 5% at the default rate (10 Hz)")


def setup_agentspeak(tmp: str) -> str | None:
    venv = os.path.join(tmp, "venv")
    try:
        subprocess.run([sys.executable, "-m", "venv", venv], check=True, capture_output=True)
        py = os.path.join(venv, "bin", "python")
        subprocess.run([py, "-m", "pip", "install", "-q", "agentspeak==0.2.2"], check=True,
                       capture_output=True, timeout=600)
        return py
    except (subprocess.CalledProcessError, subprocess.TimeoutExpired, OSError) as e:
        print(f"note: agentspeak==0.2.2 could not be installed ({e}); skipping it", file=sys.stderr)
        return None


def bench_agentspeak(py: str, n: int, tmp: str, repeat: int) -> float | None:
    """µs per iteration on agentspeak: the best of ``repeat`` runs in one process."""
    paths = []
    for count in (WARM_UP, n):
        paths.append(os.path.join(tmp, f"listing54_{count}.asl"))
        with open(paths[-1], "w", encoding="utf-8") as f:
            f.write(AGENTSPEAK_PROGRAM.format(n=count))
    proc = subprocess.run([py, "-c", AGENTSPEAK_RUNNER, *paths, str(repeat)], capture_output=True, text=True,
                          timeout=3600)
    if proc.returncode != 0:
        print(f"note: agentspeak run failed: {proc.stderr.strip()[-300:]}", file=sys.stderr)
        return None
    last = proc.stdout.strip().splitlines()[-1]
    return json.loads(last)["elapsed"] / n * 1e6


def bench_jason_jvm(classpath: str, n: int, tmp: str) -> float | None:
    """µs per iteration of Jason on the JVM (best warm pass), or None when it cannot run."""
    folder = os.path.join(tmp, "jason")
    os.makedirs(folder, exist_ok=True)
    for name, text in (("count.asl", JASON_PROGRAM.format(n=n)), ("logging.properties", JASON_LOGGING),
                       ("count.mas2j", "MAS count { agents: bench count.asl; }\n")):
        with open(os.path.join(folder, name), "w", encoding="utf-8") as f:
            f.write(text)
    try:
        proc = subprocess.run(["java", "-cp", classpath, "jason.infra.local.RunLocalMAS", "count.mas2j",
                               "--log-conf", "logging.properties"], cwd=folder, capture_output=True,
                              text=True, timeout=1800)
    except (OSError, subprocess.TimeoutExpired) as e:
        print(f"note: Jason could not run ({e})", file=sys.stderr)
        return None
    passes = [float(line.split()[-1]) for line in (proc.stdout + proc.stderr).splitlines()
              if line.startswith("pass ")]
    if len(passes) < 2:
        print(f"note: Jason printed no timing: {(proc.stdout + proc.stderr).strip()[-300:]}", file=sys.stderr)
        return None
    return min(passes[1:])


def whole_process(cmd: list[str], repeat: int, env: dict[str, str] | None = None) -> tuple[float, float]:
    """Best wall and best CPU seconds (user + system) of ``repeat`` runs of ``cmd``."""
    wall, cpu = float("inf"), float("inf")
    for _ in range(repeat):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, capture_output=True, timeout=3600, env=env)
        wall = min(wall, time.perf_counter() - t0)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = min(cpu, after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return wall, cpu


def whole_process_table(py: str | None, n: int, tmp: str, repeat: int) -> None:
    ours_path = os.path.join(tmp, f"rason_{n}.asl")
    theirs_path = os.path.join(tmp, f"agentspeak_whole_{n}.asl")
    with open(ours_path, "w", encoding="utf-8") as f:
        f.write(LISTING_5_4.format(n=n))
    with open(theirs_path, "w", encoding="utf-8") as f:
        f.write(AGENTSPEAK_PROGRAM.format(n=n))
    src = os.path.abspath(os.path.join(HERE, "..", "catkin_ws", "src", "rason", "src"))
    env = dict(os.environ, PYTHONPATH=src + os.pathsep + os.environ.get("PYTHONPATH", ""))
    # both use compiled modules, as on a user's machine: a first, untimed run of each compiles
    # them (kept under the temporary folder, out of the source tree)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    env["PYTHONPYCACHEPREFIX"] = os.path.join(tmp, "pycache")
    python_env = {**env, native.SWITCH: "0"}
    ours_cmd = [sys.executable, "-m", "rason.asl", "run", ours_path]
    theirs_cmd = None if py is None else [py, "-m", "agentspeak", theirs_path]
    for cmd, cmd_env in ((ours_cmd, env), (ours_cmd, python_env), (theirs_cmd, env)):
        if cmd is not None:
            subprocess.run(cmd, check=True, capture_output=True, timeout=3600, env=cmd_env)
    ours = whole_process(ours_cmd, repeat, env)
    as_python = whole_process(ours_cmd, repeat, python_env)
    theirs = None if theirs_cmd is None else whole_process(theirs_cmd, repeat, env)
    print(f"\nWhole process, Listing 5.4 counting to {n} (start-up included), best of {repeat}")
    print(f"{'':>10} | {'rason.asl s':>11} | {'as Python s':>11} | {'agentspeak 0.2.2 s':>18} | "
          f"{'speedup':>7} | {'target':>6}")
    print("-" * 78)
    for k, label in ((0, "wall"), (1, "CPU")):
        t = "n/a" if theirs is None else f"{theirs[k]:.2f}"
        r = "n/a" if theirs is None else f"{theirs[k] / ours[k]:.2f}x"
        print(f"{label:>10} | {ours[k]:11.2f} | {as_python[k]:11.2f} | {t:>18} | {r:>7} | "
              f"{TARGET_WHOLE_SPEEDUP:5.1f}x")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--counts", type=int, nargs="+", default=[3700, 100000])
    ap.add_argument("--repeat", type=int, default=3,
                    help="best of R runs (at least enough for 200000 timed iterations)")
    ap.add_argument("--no-agentspeak", action="store_true")
    ap.add_argument("--no-mind-state", action="store_true",
                    help="skip the cost of publishing the mind (mind inspector)")
    ap.add_argument("--jason-jar", metavar="CLASSPATH", default=None,
                    help="measure Jason on the JVM in this run (java -cp CLASSPATH: Jason 3's jar and "
                         "the javax.json jars)")
    ap.add_argument("--whole-count", type=int, default=100000,
                    help="N of the whole-process comparison (0: skip it)")
    args = ap.parse_args()
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20000))

    rows = []
    with tempfile.TemporaryDirectory(prefix="rason-bench-") as tmp:
        py = None if args.no_agentspeak else setup_agentspeak(tmp)
        bench_rason(WARM_UP)
        for n in args.counts:
            # short runs are noisy: repeat until about 200000 iterations were timed
            repeat = max(args.repeat, round(200000 / n))
            ours = []
            own = ""
            for _ in range(repeat):
                us, own = bench_rason(n)
                ours.append(us)
            theirs = None if py is None else bench_agentspeak(py, n, tmp, repeat)
            rows.append((n, min(ours), own, theirs, bench_rason_as_python(n, repeat)))
        jvm = {n: bench_jason_jvm(args.jason_jar, n, tmp) for n in args.counts} if args.jason_jar else {}
        if args.whole_count:
            whole_process_table(py, args.whole_count, tmp, args.repeat)

    print(f"\nListing 5.4 (count to N, one new intention per iteration), CPU µs per iteration (Jason: "
          f"its own .nano_time); Python {sys.version.split()[0]}; rason.asl's compiled modules "
          f"{'in use' if native.in_use() else 'NOT in use (python -m rason.asl native build)'}; "
          f"load average {os.getloadavg()[0]:.1f}; Jason JVM: "
          + ("measured in this run" if jvm else "reference figure (no --jason-jar)"))
    print(f"{'N':>8} | {'rason.asl µs/it':>15} | {'(agent .time)':>13} | {'as Python':>9} | "
          f"{'agentspeak 0.2.2 µs/it':>22} | {'speedup':>7} | {'target':>6} | {'Jason JVM µs/it':>15} | "
          f"{'vs JVM':>7}")
    print("-" * 130)
    ok = True
    for n, ours, own, theirs, as_python in rows:
        ratio = f"{theirs / ours:6.2f}x" if theirs else "    n/a"
        if theirs and theirs / ours < TARGET_SPEEDUP:
            ok = False
        own_us = f"{float(own) * 1000:10.2f}" if own else "n/a"
        theirs_s = "n/a" if theirs is None else f"{theirs:.2f}"
        jason = jvm.get(n) or JASON_JVM_US
        jason_s = f"{jason:15.2f}" if jvm.get(n) else f"{jason:14.1f}*"
        python_s = "n/a" if as_python is None else f"{as_python:.2f}"
        print(f"{n:>8} | {ours:15.2f} | {own_us:>13} | {python_s:>9} | {theirs_s:>22} | "
              f"{ratio:>7} | {TARGET_SPEEDUP:5.1f}x | {jason_s} | {ours / jason:6.2f}x")
    print("target (>= 3x faster than agentspeak per iteration):", "met" if ok else "NOT met")
    # the JVM is warm at the largest N only (its first passes at 3,700 still run in the interpreter)
    n, ours = rows[-1][0], rows[-1][1]
    jason = jvm.get(n) or JASON_JVM_US
    print(f"target (at or below Jason on the JVM, warm, N = {n}, "
          f"{'measured in this run' if jvm.get(n) else 'reference figure'}):",
          "met" if ours <= jason else "NOT met", f"({ours:.2f} vs {jason:.2f} µs)")
    if not args.no_mind_state:
        mind_state_table(args.repeat)
    return 0


if __name__ == "__main__":
    sys.exit(main())
