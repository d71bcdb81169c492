"""``./run.sh demo --real``: the case study's workstation side, against robots already up.

For two real TurtleBots (docs/real-robot.md): the robots run their drivers and rason's
robot-side nodes (fault injector, motion decomposer, Helper's vision synthesizer); the master
runs where ``ROS_MASTER_URI`` says. This starts only what belongs on the workstation: the two
agents (and the mind inspector), nothing robot-side, no simulator, no roscore. It checks first
that each robot's nodes are there, optionally injects a fault through Faulty's own
``fault_injector`` service, lets the agents run the case study, and takes the verdict from the
agents themselves: Faulty's ``diagnosis(D)`` belief (and ``unknownBecause(Why)``) read through
its mind service, beside the lines the agents print. There is no ground truth to judge by: with
``--fault`` the diagnosis is compared with what was injected, without it it is reported as is.
Times are ROS time (wall time on robots). ``--record`` records a bag of what the agents
exchanged and the robots' light topics (no camera: see docs/real-robot.md, bandwidth).
``--key FILE`` gives the agents the fleet's shared key, the file the robots' decomposers were
started with (``_auth_key_file:=``): the robots already run, so this side cannot make one for
the run as the simulated demo does (docs/real-robot.md, "Signed traffic").
"""

from __future__ import annotations

import argparse
import os
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import rospy
from jason_msgs.srv import Mind

from rason.process.harness import HarnessError, Process, RosHarness
from rason.process.interrupts import latch_interrupts
from rason.ros.auth import AuthKeyError, load_key
from rason_diagnosis.monitor import RunMonitor
from rason_diagnosis.paths import agent_file
from rason_diagnosis.scenario import (
    FAULTS,
    ROBOTS,
    UNKNOWN_BECAUSE,
    VERDICTS,
    Outcome,
    Watch,
    add_watch_options,
    expected_diagnosis,
    keyed,
    outcome_of,
    say,
    seconds_between,
    start_inspector,
    wait_for_diagnosis,
)
from rosnode_kit.polling import Deadline

#: What each robot must already run, as (kind, name, what it is), before the agents start.
ROBOT_SIDE = {
    "faulty": [("subscriber", "/faulty/jason/action", "Faulty's motion_decomposer"),
               ("service", "/faulty/fault_injector", "Faulty's fault_injector")],
    "helper": [("subscriber", "/helper/jason/action", "Helper's motion_decomposer"),
               ("service", "/helper/fault_injector", "Helper's fault_injector"),
               ("topic", "/helper/jason/perception", "Helper's robot_synthesizer")],
}
#: What ``--record`` records: the agents' traffic and the robots' light topics, both profiles'
#: odometry names (no camera, no point cloud: they would cross the Wi-Fi to the workstation).
RECORDED_TOPICS = [
    "/jason/messages", "/diagnostics", "/rosout_agg",
    *(f"/{robot}/{topic}" for robot in ROBOTS for topic in (
        "jason/action", "jason/event", "jason/perception", "odom", "fault_injector/odom",
        "cmd_vel", "fault_injector/status", "mobile_base/events/bumper",
        "mobile_base/events/cliff", "mobile_base/events/wheel_drop")),
]
PREFIX = "[real]"
#: Faulty's printed conclusions (faulty.asl): "... thanks helper", "the fault is unknown: ...",
#: "Arriving at destination" (nothing wrong).
CONCLUSION = re.compile(r"^\[faulty\] .*(thanks|the fault is unknown|Arriving at destination)")


@dataclass
class RealResult:
    """What the agents concluded; times in ROS seconds (wall time on robots)."""

    fault: str | None                 # injected by this run (None: not known here)
    diagnosis: str | None = None      # Faulty's diagnosis(D) belief
    unknown_because: str = ""
    detection_s: float | None = None
    location_s: float | None = None
    diagnosis_s: float | None = None
    total_s: float | None = None
    error: str = ""
    agent_lines: list[str] = field(default_factory=list)

    @property
    def outcome(self) -> Outcome | None:
        """Against the injected fault; None when no fault was given (nothing to judge by)."""
        if self.fault is None:
            return None
        return outcome_of(self.diagnosis == expected_diagnosis(self.fault) and not self.error,
                          self.diagnosis)


def check_robot_side(ros: RosHarness, timeout: float) -> None:
    """Wait up to `timeout` s for every robot-side node; HarnessError naming what is missing."""
    deadline = Deadline(timeout)
    waits = {"subscriber": ros.wait_for_subscriber, "topic": ros.wait_for_topic,
             "service": ros.wait_for_service}
    for robot, needs in ROBOT_SIDE.items():
        for kind, name, what in needs:
            try:
                waits[kind](name, timeout=max(0.1, deadline.remaining()))
            except HarnessError:
                raise HarnessError(f"{what} is not up ({kind} {name} not seen on the master "
                                   f"{ros.master_uri}): start {robot}'s robot side first "
                                   "(docs/real-robot.md)") from None


def run_workstation(out_dir: Path, fault: str | None = None, record: bool = False,
                    echo: bool = True, timeout: float = 300.0, robots_timeout: float = 30.0,
                    inspector_port: int | None = None,
                    master_uri: str | None = None,
                    hold: Callable[[RealResult], None] | None = None,
                    key: Path | None = None) -> RealResult:
    """Run the agents against the robots at `master_uri` (default ``ROS_MASTER_URI``), keyed
    with the fleet's `key` file when given (else unsigned, as the robots' decomposers must be).
    ``hold``: called with the result once the run is over, while the agents (and the
    inspector) still run (``--hold``)."""
    if fault is not None and fault not in FAULTS:
        raise ValueError(f"unknown fault {fault!r}; valid: {', '.join(FAULTS)}")
    out_dir.mkdir(parents=True, exist_ok=True)
    result = RealResult(fault=fault)
    ros = RosHarness(log_dir=out_dir / "logs")
    try:
        ros.attach(master_uri or os.environ.get("ROS_MASTER_URI", "http://localhost:11311"))
        say(echo, f"{PREFIX} master {ros.master_uri}; checking the robots' nodes")
        check_robot_side(ros, robots_timeout)
        _run(ros, result, out_dir, fault, record, echo, timeout, inspector_port, key)
        if hold is not None:
            hold(result)
    except HarnessError as err:
        result.error = str(err).splitlines()[0]
    finally:
        ros.stop()               # the agents (they say goodbye: the decomposers stop the bases)
    return result


def _run(ros: RosHarness, result: RealResult, out_dir: Path, fault: str | None, record: bool,
         echo: bool, timeout: float, inspector_port: int | None, key: Path | None) -> None:
    if inspector_port is not None:
        start_inspector(ros, inspector_port)
    ros.init_rospy("rason_workstation")
    monitor = RunMonitor(sensors=False)
    if record:
        ros.run(["rosbag", "record", "-O", str(out_dir / "run.bag"), *RECORDED_TOPICS],
                label="rosbag_record", echo=False)
    if fault is not None and fault != "none":
        reply = ros.check_output(["rosservice", "call", "/faulty/fault_injector",
                                  f"fault: '{fault}'"])
        say(echo, f"{PREFIX} injected {fault} on Faulty: {reply.strip()}")
    agents: dict[str, Process] = {
        robot: ros.rosrun("rason", "agent", robot, str(agent_file(robot)), ns=f"/{robot}",
                          params=keyed(key.resolve()) if key else None,
                          echo=f"{robot:>6} | " if echo else False)
        for robot in ("helper", "faulty")}
    say(echo, f"{PREFIX} started on this machine: the agents "
               f"{', '.join(f'/{r}/jason/{r}' for r in agents)}; nothing robot-side")
    ros.wait_for_service("/faulty/jason/faulty/mind", watch=agents.values())
    mind = rospy.ServiceProxy("/faulty/jason/faulty/mind", Mind)
    diagnosis = wait_for_diagnosis(mind, agents, timeout, "agent")
    if diagnosis is not None:
        result.diagnosis = diagnosis
        monitor.times.diagnosis = monitor.times.diagnosis or rospy.get_time()
    else:
        result.error = f"no diagnosis within {timeout:g} s"
    if result.diagnosis == "unknown":
        try:
            beliefs = mind().beliefs
        except (rospy.ServiceException, rospy.ROSException):
            beliefs = []
        result.unknown_because = next((m.group(1) for m in map(UNKNOWN_BECAUSE.match, beliefs)
                                       if m), "")
    t = monitor.times
    result.detection_s = seconds_between(t.move_start, t.help_request)
    result.location_s = seconds_between(t.help_request, t.found)
    result.diagnosis_s = seconds_between(t.found, t.diagnosis)
    result.total_s = seconds_between(t.move_start, t.diagnosis)
    result.agent_lines = [line for proc in agents.values() for line in proc.lines()
                          if line.startswith("[")]
    monitor.close()




def print_result(result: RealResult) -> None:
    print(f"\n{PREFIX} ---------------- result (from the agents) ----------------")
    for line in filter(CONCLUSION.search, result.agent_lines):
        print(f"{PREFIX} agent said    : {line}")
    shown = result.diagnosis or "none"
    if result.outcome is None:
        print(f"{PREFIX} diagnosis     : {shown}  (Faulty's belief; no --fault to compare with)")
    else:
        print(f"{PREFIX} diagnosis     : {shown}  (Faulty's belief; injected {result.fault}, "
              f"expected {expected_diagnosis(result.fault or 'none')}) -> "
              f"{VERDICTS[result.outcome]}")
    if result.unknown_because:
        print(f"{PREFIX} unknown because: {result.unknown_because}")
    for label, value in (("fault detection", result.detection_s),
                         ("robot location", result.location_s),
                         ("diagnosis", result.diagnosis_s), ("total", result.total_s)):
        print(f"{PREFIX} {label:15s}: " + (f"{value:6.2f} s" if value is not None else "     -"))
    if result.error:
        print(f"{PREFIX} error         : {result.error}")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="./run.sh demo --real", description=(__doc__ or "").split("\n")[0])
    parser.add_argument("--real", action="store_true", help="(this mode; implied)")
    parser.add_argument("--fault", choices=FAULTS, default=None,
                        help="inject this fault on Faulty first (through its fault_injector) "
                             "and judge the diagnosis against it (default: inject nothing, "
                             "report what the agents conclude)")
    parser.add_argument("--record", action="store_true", help="also record a bag of the run")
    parser.add_argument("--out", type=Path, default=None, help="folder for logs and the bag")
    parser.add_argument("--timeout", type=float, default=300.0, help="seconds allowed")
    parser.add_argument("--robots-timeout", type=float, default=30.0,
                        help="seconds to wait for the robots' nodes")
    parser.add_argument("--key", type=Path, default=None, metavar="FILE",
                        help="the fleet's shared key file, the one the robots' decomposers run "
                             "with (_auth_key_file:=); the agents then sign and check every "
                             "action, feedback and message (default: none, all unsigned; "
                             "docs/real-robot.md, 'Signed traffic')")
    add_watch_options(parser, "run")
    parser.add_argument("--quiet", action="store_true", help="do not stream the agents' console")
    args = parser.parse_args(argv)
    if args.key is not None:
        try:
            load_key(args.key, warn=lambda text: print(f"{PREFIX} warning: {text}", flush=True))
        except AuthKeyError as err:
            parser.error(f"--key: {err}")
    out = args.out or Path("out") / f"real-{time.strftime('%Y%m%d-%H%M%S')}"
    print(f"{PREFIX} workstation side only; output in {out}", flush=True)
    if args.key is None:
        print(f"{PREFIX} no --key: the agents and the robots' decomposers talk unsigned (any "
              "process on the network may command the robots); docs/real-robot.md, "
              "'Signed traffic'", flush=True)
    latch_interrupts()

    def show(result: RealResult) -> None:
        print_result(result)
        if args.record:
            print(f"{PREFIX} bag           : {out / 'run.bag'}")
    watch: Watch[RealResult] = Watch.of(args, show, "real")
    try:
        result = run_workstation(out, args.fault, args.record, not args.quiet, args.timeout,
                                 args.robots_timeout, watch.port, hold=watch.hold_callback(),
                                 key=args.key)
    except KeyboardInterrupt:
        print(f"\n{PREFIX} interrupted: the agents were stopped (the robots' nodes run on)")
        return 130
    watch.print_once(result)
    good = result.diagnosis is not None and not result.error and \
        result.outcome in (None, Outcome.RIGHT)
    return 0 if good else 1
