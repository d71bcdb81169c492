"""``./run.sh demo [--fault NAME] [--seed N] [--drivers sim|stock] [--record] ...``: one diagnosis.

Starts roscore, the simulator (Faulty and Helper side by side 1.5 m apart), a fault injector and
a motion decomposer per robot, Helper's vision synthesizer and both agents, each with ``rosrun``;
injects the fault with the real service before Faulty starts; streams the agents' console; prints
the diagnosis, whether it matches the injected fault, and the latency of the three steps in
simulated seconds (wall seconds with ``--drivers stock``, which runs the simulator under the real
drivers' topic names on wall time, see docs/drivers.md); writes a picture of the run. Exit status
0 only when the diagnosis is right.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import yaml

from rason.process.interrupts import latch_interrupts
from rason_diagnosis import thesis, workstation
from rason_diagnosis.drivers import SIM, WIRINGS, VisionPath, Wiring, wiring_for
from rason_diagnosis.hosts import LinkCut
from rason_diagnosis.paths import world_colours
from rason_diagnosis.scenario import (
    FAULTS,
    INJECTED_FAULTS,
    NO_FAULT,
    VERDICTS,
    RunResult,
    Watch,
    add_watch_options,
    default_fault,
    run_scenario,
)
from turtlebot_sim.config import resolve


def _link_cut(text: str) -> LinkCut:
    try:
        return LinkCut.parse(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def world_problem(path: Path) -> str | None:
    """Why a world file cannot host the case study, or None."""
    if not path.is_file():
        return "no such file"
    try:
        cfg = resolve(path)
    except (OSError, ValueError, TypeError, KeyError, yaml.YAMLError) as err:
        return f"not a valid world file: {' '.join(str(err).split())}"
    kinds = {robot["name"]: robot["kind"] for robot in cfg["robots"]}
    if kinds.get("helper") != "helper" or kinds.get("faulty") != "faulty":
        return ("the case study needs a robot named helper (kind: helper) and one named faulty "
                f"(kind: faulty); found {kinds or 'none'}")
    colours = world_colours(path)
    if colours is not None and not colours.is_file():
        return f"its vision.colours names no file: {colours}"
    return None


def start_line(fault: str, seed: int, out: Path, drawn: bool,
               drivers: str = SIM.drivers.value) -> str:
    """The demo's first line: the fault, how it was chosen and how to choose another, and the
    simulator's drivers profile."""
    if drawn:
        how = (f"drawn by seed {seed} among the real faults; pick one with --fault NAME "
               f"({', '.join(INJECTED_FAULTS)}) or --fault {NO_FAULT}, "
               f"repeat this run with --seed {seed}")
    else:
        how = f"given by --fault, seed {seed}"
    return f"[demo] fault {fault} ({how}), drivers {drivers}; output in {out}"


def main(argv: list[str] | None = None) -> int:
    if "--real" in (sys.argv[1:] if argv is None else argv):   # real robots: workstation side
        return workstation.main(argv)
    parser = argparse.ArgumentParser(prog="./run.sh demo", description=__doc__.split("\n")[0])
    parser.add_argument("--fault", choices=FAULTS,
                        help=f"fault to inject ({NO_FAULT}: a run without a fault; default: one "
                             "of the four real faults, drawn by the seed)")
    parser.add_argument("--seed", type=int, default=None,
                        help="seed of the run's variation (default: from the clock)")
    parser.add_argument("--record", action="store_true", help="also record a bag of the run")
    parser.add_argument("--out", type=Path, default=None, help="folder for the picture and logs")
    parser.add_argument("--world", type=Path, default=None,
                        help="world file (robot poses, room, lighting; as worlds/case_study.yaml)")
    parser.add_argument("--colours", type=Path, default=None,
                        help="the synthesizer's colours file (rosrun rason_vision calibrate; "
                             "default: the one the world names in vision.colours, else the "
                             "detector's ranges; docs/vision.md)")
    parser.add_argument("--drivers", choices=sorted(WIRINGS), default=SIM.drivers.value,
                        help="the simulator's topics: sim (its own, sim time) or stock (the real "
                             "kobuki_node + Kinect drivers' names, wall time; docs/drivers.md)")
    parser.add_argument("--vision", choices=[v.value for v in VisionPath], default=None,
                        help="with --drivers stock: nodelets (default: Debian's debayer and "
                             "point_cloud_xyzrgb in front of the synthesizer, as rgbd_launch) or "
                             "raw (the synthesizer reads the Bayer and depth images itself)")
    parser.add_argument("--json", action="store_true", help="print the result as JSON at the end")
    parser.add_argument("--quiet", action="store_true", help="do not stream the agents' console")
    parser.add_argument("--timeout", type=float, default=300.0,
                        help="seconds allowed (simulated; wall seconds with --drivers stock)")
    add_watch_options(parser, "run")
    parser.add_argument("--hosts", action="store_true",
                        help="world, helper and faulty on hosts of their own (network namespaces "
                             "on a private LAN, as two TurtleBots and a workstation; needs root)")
    parser.add_argument("--cut", type=_link_cut, action="append", default=[],
                        metavar="HOST@Ts+Ds", help="take HOST's link down T simulated "
                        "seconds after the agents start, for D seconds, e.g. faulty@8s+5s "
                        "(implies --hosts; repeatable)")
    parser.add_argument("--real", action="store_true",
                        help="only the workstation side (agents, inspector) against two real "
                             "robots already up, docs/real-robot.md; its own options: "
                             "./run.sh demo --real --help")
    args = parser.parse_args(argv)
    if (args.hosts or args.cut) and os.geteuid() != 0:
        parser.error("--hosts and --cut make network namespaces: run as root")
    if args.world is not None:
        problem = world_problem(args.world)
        if problem:
            parser.error(f"--world {args.world}: {problem}")
    try:
        wiring = wiring_for(args.drivers, args.vision)
    except ValueError as err:
        parser.error(str(err))
    if args.colours is not None and not args.colours.is_file():
        parser.error(f"--colours {args.colours}: no such file")

    seed = args.seed if args.seed is not None else int(time.time()) % 100000
    fault = args.fault or default_fault(seed)
    out = args.out or Path("out") / f"demo-{fault}-{seed}"
    print(start_line(fault, seed, out, drawn=args.fault is None, drivers=args.drivers), flush=True)
    # SIGTERM (the campaign's timeout, a service manager) ends the run as Ctrl-C does: every
    # node, roscore included, is stopped on the way out, also in the middle of the start; and
    # neither is lost to code that swallows its KeyboardInterrupt (rason.process.interrupts)
    latch_interrupts()
    watch: Watch[RunResult] = Watch.of(args, lambda r: _print_result(r, args, out, wiring),
                                       "demo")
    try:
        result = run_scenario(fault, seed, out, record=args.record, echo=not args.quiet,
                              sim_timeout=args.timeout, inspector_port=watch.port,
                              hosts=args.hosts, cuts=args.cut, world=args.world,
                              wiring=wiring, colours=args.colours, hold=watch.hold_callback())
    except KeyboardInterrupt:
        print("\n[demo] interrupted: every node of the run was stopped", flush=True)
        return 130
    watch.print_once(result)
    return 0 if result.correct else 1


def _print_result(result: RunResult, args: argparse.Namespace, out: Path,
                  wiring: Wiring) -> None:
    """The result block: verdict, the three latencies beside the thesis' means, where the
    picture (and bag) went; with --json the result as JSON."""
    fault = result.fault
    print("\n[demo] ---------------- result ----------------")
    print(f"[demo] injected fault : {fault}")
    print(f"[demo] diagnosis      : {result.diagnosis}  (expected {result.expected}) -> "
          f"{VERDICTS[result.outcome]}")
    clock = "simulated" if wiring.sim_time else "wall (stock drivers)"
    for label, value, index in (("fault detection", result.detection_s, 0),
                                ("robot location", result.location_s, 1),
                                ("diagnosis", result.diagnosis_s, 2),
                                ("total", result.total_s, 3)):
        figure = f"{value:6.2f} s" if value is not None else "     - "
        ref = (f"   (thesis mean {thesis.mean(fault, index):.2f} s)" if fault in thesis.TABLES
               else "")
        print(f"[demo] {label:15s}: {figure} {clock}{ref}")
    print(f"[demo] wall-clock     : {result.wall_s:.1f} s")
    if result.error:
        print(f"[demo] error          : {result.error}")
    if result.hosts:
        _print_network(result)
    print(f"[demo] picture        : {out / 'run.png'}")
    if args.record:
        print(f"[demo] bag            : {out / 'run.bag'}  (rosbag play it against a roscore)")
    if args.json:
        print(result.to_json())


def _print_network(result) -> None:
    """--hosts: link events and what each agent noticed of the others' presence."""
    for event in result.link_events:
        print(f"[demo] link           : {event['t']:6.2f} s {event['host']} "
              f"{'up' if event['up'] else 'DOWN'}")
    for event in result.presence:
        print(f"[demo] presence       : {event['t']:6.2f} s {event['observer']} sees "
              f"{event['agent']} {'present' if event['present'] else 'lapsed'}")
    if result.unknown_reason:
        print(f"[demo] unknown because: {result.unknown_reason}")
    print(f"[demo] processes died : {', '.join(result.dead) or 'none'}")


if __name__ == "__main__":
    sys.exit(main())
