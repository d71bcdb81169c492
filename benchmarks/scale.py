#!/usr/bin/env python3
"""Scale benchmark: how the costs of rason.asl grow with the size of an agent's mind.

Axes (each point: best of ``--repeat``, in this process, in CPU time of the process so that
other work on a busy machine inflates the figures less):

* beliefs, 10 to 100k, of one functor (``b(K, K)``) and of many (``bK(K)``): a query by
  functor and first argument (``b(N/2, X)``), one reasoning cycle of the count loop (Listing 5.4,
  ``value(X) & X < M <- -+value(X+1); !!count``) and one belief-addition event (``+seen(K)``
  handled by a plan);
* plans, 10 to 10k (``+!gK(X) : X > K <- .print(X).``): a relevant-plan lookup and one cycle of
  the count loop;
* intentions, 1 to 1k, each looping ``!run(K, N-1)``: one cycle (one step of one intention);
* pending messages, 1 to 10k ``tell``s queued at once: one cycle (one message taken).

Goals (issue 19): a lookup by functor and first argument within 2x from 10 to 100k beliefs; a
cycle within 2x from 1 to 1k intentions. Memory: bytes per belief and per intention frame
(tracemalloc), and the peak RSS of a process holding a 100k-belief agent (goal: under 200 MB).
PyPI ``agentspeak==0.2.2`` (throwaway venv) answers the same belief query (up to 1000 times,
at least 3, for about half a second) and runs the same count loop with the same beliefs, for
comparison (skipped with --no-agentspeak).

Writes ``docs/scale/scale.csv`` and a log-log plot per axis (``docs/scale/*.png``).

Usage: python3 benchmarks/scale.py [--repeat 3] [--quick] [--no-agentspeak] [--no-plots]
"""

from __future__ import annotations

import argparse
import csv
import gc
import json
import os
import subprocess
import sys
import tempfile
import time
import tracemalloc
from collections.abc import Callable

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.join(HERE, "..")
sys.path.insert(0, os.path.join(ROOT, "catkin_ws", "src", "rason", "src"))
sys.path.insert(0, HERE)

from reasoning_cycle import QuietArch, setup_agentspeak  # noqa: E402

from rason.asl import Agent, AgentOptions, Message, parse_term  # noqa: E402
from rason.asl.logic import first_solution  # noqa: E402
from rason.asl.plans import ACHIEVE, ADD, Plan, Trigger  # noqa: E402
from rason.asl.terms import Literal  # noqa: E402

OUT = os.path.join(ROOT, "docs", "scale")
COUNT = 2000          # count-loop iterations per timed run
COUNT_LOOP = """
!count.
+!count : value(X) & X < {m} <- -+value(X+1); !!count.
+!count <- .print(done).
value(0).
"""
COUNT_PROGRAM = COUNT_LOOP.format(m=COUNT)
SEEN_PLAN = "+seen(K) <- true.\n"
PLAN_TEMPLATE = "+!g(X) : X > 0 <- .print(X).\n"
EVENTS = 1000         # belief-addition events per timed run
STEPS = 20000         # intention steps per timed run (shared by the intentions)
MEMORY_BELIEFS = 100000
FRAMES = 10000        # intention frames (tro off) for the bytes per frame

AGENTSPEAK_SCALE = r"""
import io, json, sys, time
import agentspeak, agentspeak.runtime, agentspeak.stdlib
n, many, repeat, count = int(sys.argv[1]), sys.argv[2] == "many", int(sys.argv[3]), int(sys.argv[4])
PROGRAM = (f"value(0).\n!count.\n+!count : value(X) & X < {count} <- -+value(X+1); !!count.\n"
           "+!count <- .print(done).\n")
def agent():
    env = agentspeak.runtime.Environment()
    source = io.StringIO(PROGRAM)
    source.name = "count.asl"
    ag = env.build_agent(source, agentspeak.stdlib.actions)
    for k in range(n):
        name = f"b{k}" if many else "b"
        ag.beliefs[(name, 2)].add(agentspeak.Literal(name, (k, k)))
    return env, ag
env, ag = agent()
query = agentspeak.runtime.TermQuery(
    agentspeak.Literal(f"b{n // 2}" if many else "b", (n // 2, agentspeak.Var())))
best = 1e9
for _ in range(repeat):
    t0 = time.process_time()
    done = 0
    while done < 1000 and (done < 3 or time.process_time() - t0 < 0.5):   # a scan may be slow
        found = next(query.execute(ag, agentspeak.runtime.Intention()), False)
        assert found is None
        done += 1
    best = min(best, (time.process_time() - t0) / done)
cycle = 1e9
for _ in range(repeat):
    env, ag = agent()
    t0 = time.process_time()
    env.run()
    cycle = min(cycle, (time.process_time() - t0) / count)
print(json.dumps({"query": best * 1e6, "cycle": cycle * 1e6}))
"""


def best_of(repeat: int, run: Callable[[], float]) -> float:
    """The smallest of ``repeat`` results of ``run`` (a garbage collection before each)."""
    best = float("inf")
    for _ in range(repeat):
        gc.collect()
        best = min(best, run())
    return best


def run_to_idle(ag: Agent) -> int:
    """Step until nothing is left to do; the number of cycles that did something."""
    n = 0
    step = ag.step
    while step():
        n += 1
    return n


def belief_literal(k: int, many: bool) -> Literal:
    return Literal(f"b{k}" if many else "b", (float(k), float(k)))


def agent_with_beliefs(n: int, many: bool, program: str) -> Agent:
    ag = Agent("scale", program, QuietArch())
    for k in range(n):
        ag.bb.add(belief_literal(k, many))
    return ag


def us_per_query(n: int, many: bool, repeat: int) -> float:
    ag = agent_with_beliefs(n, many, "")
    query = parse_term(f"b{n // 2}({n // 2}, X)" if many else f"b({n // 2}, X)")

    def run() -> float:
        t0 = time.process_time()
        for _ in range(5000):
            assert first_solution(ag, query, {}) is not None
        return (time.process_time() - t0) / 5000 * 1e6
    return best_of(max(repeat, 5), run)     # a few ms per run: more runs tame the noise


def us_per_count_cycle(make: Callable[[], Agent], repeat: int) -> float:
    """µs per iteration of the count loop of an agent ``make`` builds (COUNT iterations)."""
    def run() -> float:
        ag = make()
        t0 = time.process_time()
        run_to_idle(ag)
        elapsed = time.process_time() - t0
        assert ag.arch.lines == ["done"], ag.arch.lines
        return elapsed / COUNT * 1e6
    return best_of(repeat, run)


def us_per_event(n: int, many: bool, repeat: int) -> float:
    def run() -> float:
        ag = agent_with_beliefs(n, many, SEEN_PLAN)
        run_to_idle(ag)
        t0 = time.process_time()
        for k in range(EVENTS):
            ag.add_belief(Literal("seen", (float(k),)))
            run_to_idle(ag)
        return (time.process_time() - t0) / EVENTS * 1e6
    return best_of(repeat, run)


def agent_with_plans(p: int, program: str) -> Agent:
    ag = Agent("scale", program, QuietArch())
    template = Agent("t", PLAN_TEMPLATE, QuietArch()).pl.plans[0]
    for k in range(p):
        trig = Trigger(ADD, ACHIEVE, Literal(f"g{k}", template.trigger.literal.args))
        ag.pl.add(Plan(None, trig, template.context, template.body, template.line, template.src))
    return ag


def us_per_relevant(p: int, repeat: int) -> float:
    ag = agent_with_plans(p, "")
    trig = Trigger(ADD, ACHIEVE, Literal(f"g{p // 2}", (1.0,)))

    def run() -> float:
        t0 = time.process_time()
        for _ in range(1000):
            assert ag.pl.relevant(trig)
        return (time.process_time() - t0) / 1000 * 1e6
    return best_of(repeat, run)


def us_per_intention_step(i: int, repeat: int) -> float:
    each = max(1, STEPS // i)
    program = "+!run(K, N) : N > 0 <- !run(K, N-1).\n+!run(K, 0).\n" + "".join(
        f"!run({k}, {each}).\n" for k in range(i))

    def run() -> float:
        ag = Agent("scale", program, QuietArch())
        t0 = time.process_time()
        cycles = run_to_idle(ag)
        return (time.process_time() - t0) / cycles * 1e6
    return best_of(repeat, run)


def us_per_message(m: int, repeat: int) -> float:
    def run() -> float:
        ag = Agent("scale", "", QuietArch())
        for k in range(m):
            ag.receive(Message("peer", "scale", "tell", Literal("info", (float(k),))))
        t0 = time.process_time()
        cycles = run_to_idle(ag)
        elapsed = time.process_time() - t0
        assert ag.bb.size() == m, ag.bb.size()
        return elapsed / max(cycles, 1) * 1e6
    return best_of(repeat, run)


def bytes_per_belief(n: int) -> float:
    ag = agent_with_beliefs(0, False, "")
    gc.collect()
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    for k in range(n):
        ag.bb.add(Literal("fact", (float(k), "a belief of the mind", float(k + 1))))
    after = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    return (after - before) / n


def bytes_per_frame(depth: int) -> float:
    """Memory of an intention ``depth`` intended means deep (tro off), per intended means."""
    program = (f"!down({depth}).\n+!down(N) : N > 0 <- !down(N-1).\n"
               "+!down(0) <- .suspend.\n")

    def held(d: int) -> int:
        ag = Agent("scale", program.replace(f"!down({depth}).", f"!down({d})."), QuietArch(),
                   options=AgentOptions(tro=False, max_intention_depth=depth + 10))
        gc.collect()
        tracemalloc.start()
        before = tracemalloc.get_traced_memory()[0]
        run_to_idle(ag)
        gc.collect()
        after = tracemalloc.get_traced_memory()[0]
        tracemalloc.stop()
        assert ag.circ.all_intentions(), "the intention should be suspended at the bottom"
        return after - before
    return (held(depth) - held(1)) / (depth - 1)


RSS_CHILD = r"""
import sys
sys.path[:0] = sys.argv[2:]
from rason.asl import Agent
from rason.asl.terms import Literal
from reasoning_cycle import QuietArch
ag = Agent("big", "!count.\n+!count : value(X) & X < 100 <- -+value(X+1); !!count.\nvalue(0).\n", QuietArch())
for k in range(int(sys.argv[1])):
    ag.bb.add(Literal("fact", (float(k), "a belief of the mind", float(k + 1))))
while ag.step():
    pass
# VmHWM: this process's own peak (ru_maxrss would include the parent's peak before exec)
with open("/proc/self/status") as f:
    print(next(int(line.split()[1]) for line in f if line.startswith("VmHWM:")) / 1024)
"""


def rss_mb(n: int) -> float:
    """Peak RSS (MB) of a fresh process holding an agent with ``n`` beliefs (cycles run)."""
    paths = [os.path.join(ROOT, "catkin_ws", "src", "rason", "src"), HERE]
    out = subprocess.run([sys.executable, "-c", RSS_CHILD, str(n), *paths], capture_output=True,
                         text=True, check=True, timeout=600)
    return float(out.stdout.strip().splitlines()[-1])


def agentspeak_beliefs(py: str, n: int, many: bool, repeat: int) -> tuple[float, float] | None:
    proc = subprocess.run([py, "-c", AGENTSPEAK_SCALE, str(n), "many" if many else "one", str(repeat),
                           str(COUNT)],
                          capture_output=True, text=True, timeout=3600)
    if proc.returncode != 0:
        print(f"note: agentspeak run failed: {proc.stderr.strip()[-300:]}", file=sys.stderr)
        return None
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    return res["query"], res["cycle"]


def ratio(values: list[float]) -> float:
    return max(values) / min(values)


def plot(rows: list[dict], axis: str, xlabel: str, series: list[str], path: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    values = []
    for name in series:
        pts = [(r["size"], r[name]) for r in rows if r["axis"] == axis and r.get(name) is not None]
        if pts:
            ax.plot(*zip(*pts, strict=False), marker="o", label=name)
            values += [v for _, v in pts]
    ax.set_xscale("log")
    ax.set_yscale("log")
    if values:   # at least two decades: a flat line looks flat
        low, high = min(values), max(values)
        pad = max(1.0, (100 * low / high) ** 0.5)
        ax.set_ylim(low / pad, high * pad)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("µs")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(f"rason.asl: cost against {xlabel}")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="smaller sizes (a smoke run)")
    ap.add_argument("--no-agentspeak", action="store_true")
    ap.add_argument("--no-plots", action="store_true", help="do not write docs/scale")
    args = ap.parse_args()
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20000))
    top = 3 if args.quick else 5
    belief_sizes = [10 ** k for k in range(1, top + 1)]
    plan_sizes = [10 ** k for k in range(1, min(top, 4) + 1)]
    intention_sizes = [10 ** k for k in range(0, min(top, 3) + 1)]
    message_sizes = [10 ** k for k in range(0, min(top, 4) + 1)]
    rep = args.repeat
    rows: list[dict] = []
    load = os.getloadavg()[0]

    with tempfile.TemporaryDirectory(prefix="rason-scale-") as tmp:
        py = None if args.no_agentspeak else setup_agentspeak(tmp)
        # warm-up (untimed): the first runs of each path cost more (compiled contexts, caches)
        us_per_query(10, False, 1)
        us_per_count_cycle(lambda: agent_with_beliefs(10, False, COUNT_PROGRAM), 1)
        us_per_event(10, False, 1)
        us_per_message(10, 1)
        print(f"Beliefs (µs, best of {rep}); Python {sys.version.split()[0]}")
        print(f"{'beliefs':>8} | {'functors':>8} | {'query b(K,X)':>12} | {'cycle':>7} | {'event':>7} | "
              f"{'agentspeak query':>16} | {'agentspeak cycle':>16}")
        print("-" * 92)
        for many in (False, True):
            for n in belief_sizes:
                row = {"axis": "beliefs-many" if many else "beliefs-one", "size": n,
                       "query": us_per_query(n, many, rep),
                       "cycle": us_per_count_cycle(
                           lambda n=n, many=many: agent_with_beliefs(n, many, COUNT_PROGRAM), rep),
                       "event": us_per_event(n, many, rep)}
                theirs = None if py is None else agentspeak_beliefs(py, n, many, rep)
                row["agentspeak query"], row["agentspeak cycle"] = theirs if theirs else (None, None)
                rows.append(row)
                aq = "n/a" if theirs is None else f"{theirs[0]:.2f}"
                ac = "n/a" if theirs is None else f"{theirs[1]:.2f}"
                print(f"{n:>8} | {n if many else 1:>8} | {row['query']:12.2f} | {row['cycle']:7.2f} | "
                      f"{row['event']:7.2f} | {aq:>16} | {ac:>16}")
        for axis in ("beliefs-one", "beliefs-many"):
            q = [r["query"] for r in rows if r["axis"] == axis]
            print(f"query {axis}: largest/smallest = {ratio(q):.2f}x (goal <= 2x): "
                  f"{'met' if ratio(q) <= 2 else 'NOT met'}")

        print(f"\nPlans (µs, best of {rep})")
        print(f"{'plans':>8} | {'relevant lookup':>15} | {'cycle':>7}")
        print("-" * 38)
        for p in plan_sizes:
            row = {"axis": "plans", "size": p, "relevant": us_per_relevant(p, rep),
                   "cycle": us_per_count_cycle(lambda p=p: agent_with_plans(p, COUNT_PROGRAM), rep)}
            rows.append(row)
            print(f"{p:>8} | {row['relevant']:15.2f} | {row['cycle']:7.2f}")

        print(f"\nIntentions (µs per cycle, best of {rep})")
        print(f"{'intentions':>10} | {'cycle':>7}")
        print("-" * 21)
        for i in intention_sizes:
            row = {"axis": "intentions", "size": i, "cycle": us_per_intention_step(i, rep)}
            rows.append(row)
            print(f"{i:>10} | {row['cycle']:7.2f}")
        c = [r["cycle"] for r in rows if r["axis"] == "intentions"]
        print(f"cycle 1 to {intention_sizes[-1]} intentions: largest/smallest = {ratio(c):.2f}x "
              "(goal <= 2x): "
              f"{'met' if ratio(c) <= 2 else 'NOT met'}")

        print(f"\nPending messages (µs per cycle, best of {rep})")
        print(f"{'messages':>10} | {'cycle':>7}")
        print("-" * 21)
        for m in message_sizes:
            row = {"axis": "messages", "size": m, "cycle": us_per_message(m, rep)}
            rows.append(row)
            print(f"{m:>10} | {row['cycle']:7.2f}")

    n_mem = 10000 if args.quick else MEMORY_BELIEFS
    per_belief = bytes_per_belief(n_mem)
    per_frame = bytes_per_frame(1000 if args.quick else FRAMES)
    rss = rss_mb(n_mem)
    print(f"\nMemory: {per_belief:.0f} bytes per belief (fact(K, \"a belief of the mind\", K+1), "
          f"{n_mem} beliefs, tracemalloc); {per_frame:.0f} bytes per intention frame (tro off); "
          f"peak RSS of a process with a {n_mem}-belief agent: {rss:.1f} MB (goal < 200 MB for 100k): "
          f"{'met' if rss < 200 else 'NOT met'}")
    print(f"load average at the start: {load:.1f}")

    if not args.no_plots:
        os.makedirs(OUT, exist_ok=True)
        fields = ["axis", "size", "query", "cycle", "event", "agentspeak query", "agentspeak cycle",
                  "relevant"]
        with open(os.path.join(OUT, "scale.csv"), "w", newline="", encoding="utf-8") as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            for r in rows:
                w.writerow({k: (f"{r[k]:.3f}" if isinstance(r.get(k), float) else r.get(k, ""))
                            for k in fields})
        series = ["query", "cycle", "event", "agentspeak query", "agentspeak cycle"]
        plot(rows, "beliefs-one", "beliefs of one functor", series, os.path.join(OUT, "beliefs_one.png"))
        plot(rows, "beliefs-many", "beliefs of as many functors", series,
             os.path.join(OUT, "beliefs_many.png"))
        plot(rows, "plans", "plans", ["relevant", "cycle"], os.path.join(OUT, "plans.png"))
        plot(rows, "intentions", "intentions", ["cycle"], os.path.join(OUT, "intentions.png"))
        plot(rows, "messages", "pending messages", ["cycle"], os.path.join(OUT, "messages.png"))
        print(f"wrote {OUT}/scale.csv and the plots")
    return 0


if __name__ == "__main__":
    sys.exit(main())
