#!/usr/bin/env python3
"""Fleet scale: N robot hosts on one LAN, every agent broadcasting (needs root: ip netns).

For each N (default 1, 5, 10, 20) a fresh LAN of network namespaces (``rason.process.netns``,
the firewall of docs/deployment.md on every host): a ``master`` host with ``roscore``, and N robot hosts
``r1..rN``, each with ``rosrun rason agent rK``, ``rosrun rason echo_decomposer`` and a 20 Hz
perception stream (``rostopic pub -r 20``), all in the robot's namespace ``/rK``. Every agent
broadcasts ``ping(Seq, T)`` twice a second (``T``: ``.nano_time``, and all namespaces share one
kernel clock, so one-way latency is exact) and performs a ``move`` on its decomposer; every agent
prints the latency of every ping it receives, into its log file (the benchmark reads the files,
not pipes). ``--pacing`` says when an agent pings:

* ``slot`` (default): ping ``I`` at a random moment of the ``I``-th 500 ms slot after the
  agent's start ``T0``: twice a second on average, whatever the latencies are, at times
  independent of the other agents' (the load a latency figure is meant for);
* ``wait``: ``.wait(500)`` after each ping's ``move`` is done, so an agent's period stretches
  with the delays of the machine it measures. Agents delayed by the same burst ping again
  together, and the fleet falls into step (the benchmark's only pacing until the late night
  of 2026-11-26).

Measured:

* message latency p50/p99 between hosts (agent broadcast -> another host's agent's plan runs);
* crowding: how many other broadcasts come within 5 ms of a broadcast, on average, against
  what independent times at the same rate give (1: independent; 2: twice as many neighbours);
* presence convergence: a host joins (its agent starts: until every other agent logged it
  ``present``), leaves (SIGINT: it says goodbye; until every agent forgot it) and vanishes (its
  link cut: until every agent forgot it, ``~presence_timeout`` (3.5 s) after it was last heard);
* CPU per agent (% of one core, over the measuring window) and the master's load (rosmaster's
  CPU over the window and over the fleet's start, and its number of registered nodes).

Prints a table, writes ``docs/fleet/fleet.csv`` and ``docs/fleet/fleet.png`` (each figure
against N). Aim: p99 under 20 ms at N = 20 on 2 cores; presence converging within two presence
periods (join and leave; a vanished host is forgotten after the timeout plus at most a period).

    ./run.sh bench fleet [--sizes 1 5 10 20] [--window 30] [--pacing slot|wait]
"""

from __future__ import annotations

import argparse
import bisect
import csv
import os
import re
import shutil
import signal
import statistics
import subprocess
import sys
import tempfile
import time
from dataclasses import asdict, dataclass, fields
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from rason.process import netns
from rason.process.harness import Process, RosHarness
from rason.process.procstat import cpu_seconds

ROOT = Path(__file__).resolve().parent.parent
PRESENCE_PERIOD = 1.0
PRESENCE_TIMEOUT = 3.5
PING_PERIOD_MS = 500
#: two broadcasts this close (ms) are neighbours in the crowding figure
NEIGHBOUR_MS = 5.0
#: how a fleet's run (a child process) starts a line of its stderr the parent passes on
NOTE = "[fleet] "

#: the agent's plans for each ``--pacing`` (placeholders __WARMUP__, __COUNT__, __PERIOD__ in ms)
PACING = {
    "slot": """
+!start <- .wait(__WARMUP__); .nano_time(T0); !loop(0, T0).
+!loop(I, T0) : I < __COUNT__
   <- .random(R); .nano_time(Now); .wait(math.max(0, (T0 - Now) / 1000000 + (I + R) * __PERIOD__));
      .nano_time(T); .broadcast(tell, ping(I, T)); move(I); !loop(I + 1, T0).
+!loop(_, _) <- .print("done").
""",
    "wait": """
+!start <- .wait(__WARMUP__); !loop(0).
+!loop(I) : I < __COUNT__
   <- .nano_time(T); .broadcast(tell, ping(I, T)); move(I); .wait(__PERIOD__); !loop(I + 1).
+!loop(_) <- .print("done").
""",
}
#: every agent's plan for a ping it hears: one line with the sender, latency (ms), I and T
HEAR = """
!start.
+ping(I, T)[source(S)]
   <- .nano_time(Now); .print("lat ", S, " ", (Now - T) / 1000000, " ", I, " ", T);
      -ping(I, T)[source(S)].
"""
LATENCY = re.compile(r"\] lat (\w+) ([\d.eE+-]+) (\d+) (\d+)$")
# rospy log: "[INFO] [WALL]: agent r3 present" ("[WALL, ROS]" under sim time)
LOG = re.compile(r"\[INFO\] \[([\d.]+)(?:, [\d.]+)?\]: (.*)$")


@dataclass
class FleetResult:
    """One fleet size's figures (ms, s, % of one core)."""

    n: int
    pacing: str
    messages: int
    p50_ms: float
    p99_ms: float
    max_ms: float
    crowding: float  # neighbours within NEIGHBOUR_MS per broadcast / those of independent times
    join_s: float
    leave_s: float
    vanish_s: float
    cpu_agent_pct: float
    cpu_master_pct: float
    master_start_cpu_s: float
    nodes: int
    load: float      # the machine's 1-minute load average at the end of the window


#: how a FleetResult field is read back from text (the CSV, the child's RESULT line)
FIELD_TYPES = {"int": int, "float": float, "str": str}


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(q / 100 * (len(ordered) - 1)))] if ordered else 0.0


@dataclass(frozen=True)
class Heard:
    """One ping one agent heard: its sender, sequence number, send time (ns) and latency."""

    sender: str
    seq: int
    sent_ns: int
    latency_ms: float


def crowding(sent_ns: list[int], window_s: float) -> float:
    """How many other broadcasts come within :data:`NEIGHBOUR_MS` of each of ``sent_ns`` (the
    broadcasts of a window of ``window_s`` seconds), on average, divided by what independent
    times at the same rate give: 1 for independent times, more when they come in bunches."""
    times = sorted(t / 1e6 for t in sent_ns)
    if len(times) < 2 or window_s <= 0:
        return float("nan")
    neighbours = sum(bisect.bisect_right(times, t + NEIGHBOUR_MS)
                     - bisect.bisect_left(times, t - NEIGHBOUR_MS) - 1 for t in times)
    rate_per_ms = (len(times) - 1) / (window_s * 1000)
    return neighbours / len(times) / (2 * NEIGHBOUR_MS * rate_per_ms)


def rosmaster_pid(roscore: Process) -> int:
    """The rosmaster process roscore started (its child)."""
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                cmd = f.read().split(b"\0")
            with open(f"/proc/{pid}/stat") as f:
                ppid = int(f.read().rsplit(")", 1)[1].split()[1])
        except OSError:
            continue
        if ppid == roscore.pid and any(b"rosmaster" in part for part in cmd):
            return int(pid)
    raise RuntimeError("rosmaster not found under roscore")


def log_times(lines: list[str], text: str | tuple[str, ...]) -> list[float]:
    """Wall times of the log ``lines`` that contain ``text`` (or one of them)."""
    texts = (text,) if isinstance(text, str) else text
    times = []
    for line in lines:
        match = LOG.search(line)
        if match and any(t in match.group(2) for t in texts):
            times.append(float(match.group(1)))
    return times


def line_marks(procs: dict[str, Process]) -> dict[str, int]:
    """How many lines each process has printed so far (where a wait starts reading)."""
    return {name: len(proc.lines()) for name, proc in procs.items()}


def wait_all(agents: dict[str, Process], text: str | tuple[str, ...], since: float,
             marks: dict[str, int], timeout: float) -> float:
    """Wall time at which the last of ``agents`` logged ``text`` at ``since`` or later.

    Reads each agent's lines from its mark on, each line once (the agents print every ping:
    rescanning all their output each poll would load the machine being measured)."""
    deadline = time.monotonic() + timeout
    read = dict(marks)
    last: dict[str, float | None] = dict.fromkeys(agents)
    while True:
        for name, proc in agents.items():
            lines = proc.lines()
            found = [t for t in log_times(lines[read[name]:], text) if t >= since]
            read[name] = len(lines)
            if found:
                last[name] = max(found)
        if all(t is not None for t in last.values()):
            return max(t for t in last.values() if t is not None)
        if time.monotonic() > deadline:
            missing = [n for n, t in last.items() if t is None]
            raise RuntimeError(f"{missing} never logged {text!r}")
        time.sleep(0.1)


def wait_known(agents: dict[str, Process], timeout: float) -> None:
    """Wait until every agent has logged every other one ``present``."""
    deadline = time.monotonic() + timeout
    while True:
        missing = {}
        for name, proc in agents.items():
            seen = {m.group(1) for line in proc.lines()
                    if (m := re.search(r"agent (\w+) present", line))}
            if set(agents) - {name} - seen:
                missing[name] = sorted(set(agents) - {name} - seen)
        if not missing:
            return
        if time.monotonic() > deadline:
            raise RuntimeError(f"presence never converged: {missing}")
        time.sleep(0.2)


def start_robot(ros: RosHarness, host: netns.Host, asl: Path) -> Process:
    ns = f"/{host.name}"
    ros.rosrun("rason", "echo_decomposer", ns=ns, host=host)
    ros.run(["rostopic", "pub", "-r", "20", f"{ns}/jason/perception", "jason_msgs/Perception",
             "{source: camera, perception: ['battery(90)', 'seen(dock, 1.5)']}"],
            label=f"{host.name}/perception", host=host)
    # an agent prints a line per ping: it writes its log file itself, as on a robot (through a
    # pipe the benchmark's reader thread was woken for each line, competing with the fleet)
    return ros.rosrun("rason", "agent", host.name, str(asl), ns=ns, host=host, piped=False,
                      params={"presence_period": PRESENCE_PERIOD,
                              "presence_timeout": PRESENCE_TIMEOUT})


def run_fleet(n: int, window: float, pacing: str, tmp: Path) -> FleetResult:
    """One fleet of ``n`` robot hosts (plus a joining one) pinging by ``pacing``; its figures."""
    robots = [f"r{i}" for i in range(1, n + 1)]
    asl = tmp / "fleet.asl"
    asl.write_text((HEAR + PACING[pacing]).replace("__WARMUP__", "1000")
                   .replace("__COUNT__", "100000").replace("__PERIOD__", str(PING_PERIOD_MS)))
    lan = netns.Lan(["master", *robots], firewall=True)
    with lan:
        netns.enter(lan.host("master"))
        with RosHarness(master_host=lan.host("master"), log_dir=tmp / f"logs-{n}") as ros:
            master = rosmaster_pid(ros.roscore)
            master_cpu0 = cpu_seconds(master)
            agents = {r: start_robot(ros, lan.host(r), asl) for r in robots}
            for r in robots:
                ros.wait_for_node(f"/{r}/jason/{r}", timeout=120 + 5 * n,
                                  watch=agents.values())
            # every agent knows every other one: the fleet is up
            wait_known(agents, 60 + 3 * n)
            master_start_cpu = cpu_seconds(master) - master_cpu0
            time.sleep(3)

            # -- steady state: latency, CPU ---------------------------------------------------
            marks = line_marks(agents)
            cpu0 = {r: cpu_seconds(p.pid) for r, p in agents.items()}
            m0, t0 = cpu_seconds(master), time.monotonic()
            time.sleep(window)
            elapsed = time.monotonic() - t0
            cpu_agent = statistics.fmean((cpu_seconds(p.pid) - cpu0[r]) / elapsed * 100
                                         for r, p in agents.items())
            cpu_master = (cpu_seconds(master) - m0) / elapsed * 100
            heard = [Heard(m.group(1), int(m.group(3)), int(m.group(4)), float(m.group(2)))
                     for r, p in agents.items() for line in p.lines()[marks[r]:]
                     if (m := LATENCY.search(line))]
            latencies = [h.latency_ms for h in heard]
            broadcasts = {(h.sender, h.seq): h.sent_ns for h in heard}
            dead = [p.name for p in ros.processes if not p.alive()]
            if dead:
                raise RuntimeError(f"processes died during the window: {dead}")
            nodes = len(ros.nodes())
            load = os.getloadavg()[0]

            # -- presence: a host joins, leaves (goodbye), joins again and vanishes --------------
            newcomer = netns.Host("rnew", f"{netns.PREFIX}-{lan.owner}-rnew",
                                  f"{lan.subnet}.{n + 2}")
            lan.add(newcomer)
            marks, started = line_marks(agents), time.time()
            joining = start_robot(ros, newcomer, asl)
            joining.wait_for_line(r"hosting rnew", timeout=120)
            hosted = log_times(joining.lines(), "hosting rnew")[0]
            # 0 when the others heard the newcomer before it logged that it is up
            join = max(0.0, wait_all(agents, "agent rnew present", started, marks, 30) - hosted)
            mark = len(ros.processes) - 3
            # the clock is read before the signal: an agent may log the goodbye before this
            # thread runs again (the run once lost those that did, and waited for them in vain)
            marks, left = line_marks(agents), time.time()
            joining.signal_group(signal.SIGINT)
            # the goodbye is best effort (a node may exit before it reaches everyone): whoever
            # missed it forgets the agent after the presence timeout
            leave = wait_all(agents, ("agent rnew said goodbye", "agent rnew not heard"), left,
                             marks, 30) - left
            ros.stop_started_since(mark)

            marks = line_marks(agents)
            again = start_robot(ros, newcomer, asl)
            again.wait_for_line(r"hosting rnew", timeout=120)
            rejoined = log_times(again.lines(), "hosting rnew")[0]
            try:
                wait_all(agents, "agent rnew present", rejoined - 0.5, marks, 60)
                time.sleep(2)
                marks, cut = line_marks(agents), time.time()
                lan.cut("rnew")
                vanish = wait_all(agents, "agent rnew not heard", cut, marks, 30) - cut
                lan.restore("rnew")
            except RuntimeError as err:   # reported as not measured, the rest is kept
                print(f"{NOTE}vanish not measured: {err}", file=sys.stderr)
                vanish = float("nan")
    return FleetResult(
        n=n, pacing=pacing, messages=len(latencies), p50_ms=round(percentile(latencies, 50), 2),
        p99_ms=round(percentile(latencies, 99), 2), max_ms=round(max(latencies, default=0), 2),
        crowding=round(crowding(list(broadcasts.values()), elapsed), 2),
        join_s=round(join, 2), leave_s=round(leave, 2), vanish_s=round(vanish, 2),
        cpu_agent_pct=round(cpu_agent, 1), cpu_master_pct=round(cpu_master, 1),
        master_start_cpu_s=round(master_start_cpu, 2), nodes=nodes, load=round(load, 1))


def table(results: list[FleetResult]) -> str:
    columns = ["N robots", "pacing", "messages", "latency p50", "p99", "max", "crowding", "join",
               "leave (Ctrl-C)", "vanish (link cut)", "CPU per agent", "rosmaster CPU",
               "rosmaster CPU for the start", "nodes", "load"]
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for r in results:
        latency = (f"{r.p50_ms:.2f} ms | {r.p99_ms:.2f} ms | {r.max_ms:.1f} ms | {r.crowding:.2f}"
                   if r.messages else "- | - | - | -")   # one robot: no other host to hear from
        lines.append(f"| {r.n} | {r.pacing} | {r.messages} | {latency} | {r.join_s:.2f} s | "
                     f"{r.leave_s:.2f} s | {r.vanish_s:.2f} s | {r.cpu_agent_pct:.1f}% | "
                     f"{r.cpu_master_pct:.1f}% | {r.master_start_cpu_s:.2f} s | {r.nodes} | "
                     f"{r.load:.1f} |")
    return "\n".join(lines)


def plot(results: list[FleetResult], path: Path) -> None:
    ns = [r.n for r in results]
    fig, axes = plt.subplots(1, 4, figsize=(17, 4))
    ax = axes[0]
    heard = [r for r in results if r.messages]
    ax.plot([r.n for r in heard], [r.p50_ms for r in heard], "o-", label="p50")
    ax.plot([r.n for r in heard], [r.p99_ms for r in heard], "s-", label="p99")
    ax.axhline(20, ls="--", color="k", label="aim: p99 < 20 ms")
    ax.set_title(f"message latency between hosts ({', '.join(sorted({r.pacing for r in results}))}"
                 " pacing)")
    ax.set_ylabel("ms")
    ax = axes[1]
    ax.plot(ns, [r.join_s for r in results], "o-", label="join")
    ax.plot(ns, [r.leave_s for r in results], "s-", label="leave (Ctrl-C: goodbye)")
    ax.plot(ns, [r.vanish_s for r in results], "^-", label="vanish (link cut)")
    ax.axhline(2 * PRESENCE_PERIOD, ls="--", color="k", label="two presence periods")
    ax.axhline(PRESENCE_TIMEOUT, ls=":", color="grey", label="presence timeout")
    ax.set_title("presence convergence")
    ax.set_ylabel("s")
    ax = axes[2]
    ax.plot(ns, [r.cpu_agent_pct for r in results], "o-")
    ax.set_title("CPU per agent")
    ax.set_ylabel("% of one core")
    ax = axes[3]
    ax.plot(ns, [r.cpu_master_pct for r in results], "o-", label="steady")
    ax.set_title("rosmaster CPU (steady state)")
    ax.set_ylabel("% of one core")
    for ax in axes:
        ax.set_xlabel("robot hosts N")
        ax.set_xticks(ns)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1, 5, 10, 20])
    parser.add_argument("--window", type=float, default=30.0, help="seconds of steady state")
    parser.add_argument("--pacing", choices=sorted(PACING), default="slot",
                        help="slot: every agent pings once in each 500 ms slot of its own, at a "
                             "random moment of it; wait: 500 ms after each ping's move is done "
                             "(the fleet falls into step)")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "fleet")
    parser.add_argument("--replot", action="store_true",
                        help="only redraw the table and plot from OUT/fleet.csv")
    args = parser.parse_args()
    if args.replot:
        with open(args.out / "fleet.csv") as f:
            rows = list(csv.DictReader(f))
        results = [FleetResult(**{fld.name: FIELD_TYPES[fld.type](row[fld.name])
                                  for fld in fields(FleetResult)}) for row in rows]
        plot(results, args.out / "fleet.png")
        print(table(results))
        return 0
    if os.geteuid() != 0:
        print("fleet needs root (network namespaces)", file=sys.stderr)
        return 2
    # Each size runs in a child process: a process can enter a namespace only once usefully,
    # and each fleet needs a fresh LAN.
    if os.environ.get("RASON_FLEET_ONE"):
        tmp = Path(tempfile.mkdtemp(prefix="rason-fleet-"))
        try:
            result = run_fleet(int(os.environ["RASON_FLEET_ONE"]), args.window, args.pacing, tmp)
        except BaseException:
            print(f"the nodes' logs are kept in {tmp}", file=sys.stderr)   # to see why
            raise
        shutil.rmtree(tmp, ignore_errors=True)
        print("RESULT " + ",".join(str(v) for v in asdict(result).values()), flush=True)
        return 0
    args.out.mkdir(parents=True, exist_ok=True)
    results = []
    for n in args.sizes:
        print(f"{NOTE}N = {n} ...", flush=True)
        done = subprocess.run([sys.executable, __file__, "--window", str(args.window),
                               "--pacing", args.pacing],
                              env={**os.environ, "RASON_FLEET_ONE": str(n)},
                              capture_output=True, text=True, timeout=1800)
        line = next((x for x in done.stdout.splitlines() if x.startswith("RESULT ")), None)
        if done.returncode != 0 or line is None:
            print(done.stdout[-3000:], done.stderr[-3000:], file=sys.stderr)
            return 1
        for note in done.stderr.splitlines():    # what the run noted (its nodes' noise is not)
            if note.startswith(NOTE):
                print(note, file=sys.stderr, flush=True)
        values = line[len("RESULT "):].split(",")
        results.append(FleetResult(*(FIELD_TYPES[f.type](v)
                                     for f, v in zip(fields(FleetResult), values, strict=True))))
        print(table(results[-1:]).splitlines()[-1], flush=True)
    with open(args.out / "fleet.csv", "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow([f.name for f in fields(FleetResult)])
        writer.writerows([list(asdict(r).values()) for r in results])
    plot(results, args.out / "fleet.png")
    print(f"\nfleet of N robot hosts ({args.pacing} pacing; this machine: {os.cpu_count()} "
          "cores)\n")
    print(table(results))
    last = results[-1]
    met = last.messages > 0 and last.p99_ms < 20      # no message measured is no latency met
    print(f"\naim p99 < 20 ms at N = {last.n}: {'PASS' if met else 'FAIL'} "
          f"({last.p99_ms:.2f} ms over {last.messages} messages); presence within two periods "
          f"({2 * PRESENCE_PERIOD:g} s): "
          f"join {'PASS' if last.join_s <= 2 * PRESENCE_PERIOD else 'FAIL'}, leave "
          f"{'PASS' if last.leave_s <= 2 * PRESENCE_PERIOD else 'FAIL'}; vanish "
          f"{last.vanish_s:.2f} s after the cut (forgotten {PRESENCE_TIMEOUT:g} s after it "
          "was last heard, by design)")
    print(f"wrote {args.out / 'fleet.csv'} and {args.out / 'fleet.png'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
