"""One run of the cooperative fault diagnosis (thesis ch. 6-7) in simulation, end to end.

Everything is started with ``rosrun`` through the shared harness: the simulator, a fault injector
and a motion decomposer per robot, Helper's vision synthesizer, and the two agents. The fault is
injected with the real service (``rosservice call``) before Faulty starts. The agents and the
decomposers share a key made for the run (:func:`run_key`): every action, feedback, message and
presence beat between them is signed (:mod:`rason.ros.auth`).
"""

from __future__ import annotations

import argparse
import contextlib
import json
import random
import re
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import asdict, dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import Generic, TypeVar

import rospy

from rason.inspector.main import InspectorParams
from rason.process.harness import HarnessError, Process, RosHarness, echo_line
from rason.process.interrupts import forget_interrupt, raise_if_interrupted
from rason.ros.auth import write_new_key
from rason_diagnosis.drivers import SIM, Wiring
from rason_diagnosis.hosts import CaseStudyLan, LinkCut, LinkCutter, presence_events
from rason_diagnosis.paths import agent_file, world_colours, world_file
from rosnode_kit.polling import poll

#: The injected run without a fault (Faulty should conclude ``no_fault``).
NO_FAULT = "none"
#: The faults the injector can break Faulty with.
INJECTED_FAULTS = ("both_actuators", "odometry", "left_actuator", "right_actuator")
FAULTS = (*INJECTED_FAULTS, NO_FAULT)
ROBOTS = ("faulty", "helper")
RECORDED_TOPICS = [
    "/clock", "/jason/messages", "/faulty/jason/action", "/faulty/jason/event",
    "/helper/jason/action", "/helper/jason/event", "/helper/jason/perception",
    "/faulty/odom", "/faulty/cmd_vel", "/helper/cmd_vel", "/faulty/ground_truth/odom",
    "/helper/ground_truth/odom", "/faulty/fault_injector/status", "/diagnostics",
]


def expected_diagnosis(fault: str) -> str:
    """What Faulty should conclude for an injected fault."""
    return "no_fault" if fault == NO_FAULT else fault


class Outcome(StrEnum):
    """How a run's answer counts: the worst answer is a wrong component, not `unknown`."""

    RIGHT = "right"        # the injected fault
    UNKNOWN = "unknown"    # no component named (or no answer)
    WRONG = "wrong"        # a wrong component


#: What the demo and the workstation print for each outcome of a run.
VERDICTS = {Outcome.RIGHT: "CORRECT", Outcome.UNKNOWN: "UNKNOWN (no component named)",
            Outcome.WRONG: "WRONG"}


def outcome_of(correct: object, diagnosis: str | None) -> Outcome:
    if correct:
        return Outcome.RIGHT
    if diagnosis in (None, "unknown"):
        return Outcome.UNKNOWN
    return Outcome.WRONG


@dataclass
class RunResult:
    """The outcome of one run; times in simulated seconds (wall seconds under stock drivers)."""

    fault: str
    seed: int
    diagnosis: str | None = None
    expected: str = ""
    correct: bool = False
    detection_s: float | None = None
    location_s: float | None = None
    diagnosis_s: float | None = None
    total_s: float | None = None
    wall_s: float = 0.0
    error: str = ""
    out_dir: str = ""
    inspector: str = ""        # the mind inspector's address, when it watched the run
    console: list[str] = field(default_factory=list)
    # --hosts / --cut: the hosts, the link events, what the agents noticed, processes that died
    hosts: bool = False
    cuts: list[str] = field(default_factory=list)
    link_events: list[dict] = field(default_factory=list)
    presence: list[dict] = field(default_factory=list)
    dead: list[str] = field(default_factory=list)
    unknown_reason: str = ""
    drivers: str = "sim"
    vision: str | None = None  # the stock profile's image path (rason_diagnosis.drivers)

    @property
    def outcome(self) -> Outcome:
        return outcome_of(self.correct, self.diagnosis)

    def to_json(self) -> str:
        return json.dumps(asdict(self), indent=2)


def seconds_between(a: float | None, b: float | None) -> float | None:
    """``b - a`` in seconds, rounded to 0.01 s; None when either moment is unknown."""
    return round(b - a, 2) if a is not None and b is not None else None


#: Helper's motion decomposer: its search sweep (one full turn, cut short at the first sighting)
#: cruises at 120 deg/s (Kobuki: up to 180) and every turn speeds up at 220 deg/s^2, just under
#: the base's 4 rad/s^2 (turtlebot_sim.kobuki.ACCEL_W), and brakes to its goal at 180 deg/s^2.
#: A cut sweep stops at the base's own limit in 0.52 s (31 deg) plus what it turned while the
#: frame was detected and acted on (0.1-0.5 s of simulated time, more on a busy machine): Faulty
#: may be out of view by then; Helper turns back to the heading where it saw it (`turn_to`,
#: with the synthesizer's `seen_at`). helper.asl's `sweepBrake` counts on these figures.
HELPER_MOTION: dict[str, object] = {"angular_speed": 120.0, "angular_accel": 220.0,
                                    "angular_decel": 180.0}
#: Helper's vision synthesizer also reports where it saw Faulty in the odometry frame, marks
#: sightings from frames not taken with the camera at rest ([moving]) and stamps every sighting
#: with its frame's time ([stamp(Ms)]): Helper's observations count only frames at rest and
#: newer than the start of the observation (helper.asl, !observe; docs/thesis-fixes.md F10).
HELPER_VISION: dict[str, object] = {"odom_bearings": True, "frame_stamps": True}


@contextlib.contextmanager
def run_key() -> Iterator[Path]:
    """A fresh shared key for one run's agents and decomposers (their ``~auth_key_file``), in a
    temporary folder of its own, readable by its owner only; removed when the run ends."""
    with tempfile.TemporaryDirectory(prefix="rason-run-key-") as folder:
        yield write_new_key(Path(folder) / "run.key")


def keyed(key: Path, params: dict[str, object] | None = None) -> dict[str, object]:
    """A node's private parameters `params` with the run's key as its ``~auth_key_file``."""
    return {**(params or {}), "auth_key_file": str(key)}


def run_scenario(fault: str, seed: int, out_dir: Path, record: bool = False, echo: bool = True,
                 sim_timeout: float = 300.0, real_time_factor: float = 1.0,
                 inspector_port: int | None = None, hosts: bool = False,
                 cuts: Sequence[LinkCut] = (), world: Path | None = None,
                 wiring: Wiring = SIM, colours: Path | None = None,
                 hold: Callable[[RunResult], None] | None = None) -> RunResult:
    """Run one scenario; returns its result (never raises for a failed diagnosis).

    With `inspector_port` (0: any free port) the mind inspector watches the run; its address is
    printed (and kept in ``result.inspector``) as soon as it listens.
    ``hosts``: world, helper and faulty on their own network namespaces (see hosts.py);
    ``cuts``: links taken down and up again during the run (implies ``hosts``).
    ``world``: a world file (robot poses, room, lighting, camera; see ``worlds/case_study.yaml``),
    default the thesis' layout. ``wiring``: the driver profile (:mod:`rason_diagnosis.drivers`);
    under ``STOCK`` the times are wall seconds, as on robots. ``colours``: the synthesizer's
    colours file (default: the one the world names, else the detector's ranges).
    ``hold``: called with the result once the run is over, while every node (the inspector
    included) still runs; the nodes stop when it returns.
    """
    if fault not in FAULTS:
        raise ValueError(f"unknown fault {fault!r}; valid: {', '.join(FAULTS)}")
    out_dir.mkdir(parents=True, exist_ok=True)
    result = RunResult(fault=fault, seed=seed, expected=expected_diagnosis(fault),
                       drivers=wiring.drivers.value, vision=wiring.vision,
                       out_dir=str(out_dir), hosts=hosts or bool(cuts),
                       cuts=[str(c) for c in cuts])
    clock = WallClock()
    with contextlib.ExitStack() as stack:
        key = stack.enter_context(run_key())      # removed last, after every node has stopped
        network = stack.enter_context(CaseStudyLan(relay_port=inspector_port)) \
            if result.hosts else None
        if network and inspector_port is not None:   # the inspector on the world host
            inspector_port = network.relay_port        # at the address relayed to this machine
        ros = RosHarness(sim_time=wiring.sim_time, echo=False, log_dir=out_dir / "logs",
                         master_host=network.world if network else None,
                         placement=network.placement() if network else None)
        try:
            with ros:
                if inspector_port is not None:
                    result.inspector = start_inspector(ros, inspector_port)
                _run(ros, result, out_dir, key, record, echo, sim_timeout, real_time_factor,
                     network, cuts, world or world_file(), wiring, colours)
                if hold is not None:
                    _conclude(result, clock.stop())
                    hold(result)
        except HarnessError as err:
            result.error = str(err).splitlines()[0]
    _conclude(result, clock.stop())   # the wall time stays the one taken before a hold
    (out_dir / "result.json").write_text(result.to_json())
    return result


def _conclude(result: RunResult, wall_s: float) -> None:
    """The result's wall time and verdict."""
    result.wall_s = wall_s
    result.correct = result.diagnosis == result.expected and not result.error


def _run(ros: RosHarness, result: RunResult, out_dir: Path, key: Path, record: bool,
         echo: bool, sim_timeout: float, real_time_factor: float,
         network: CaseStudyLan | None = None, cuts: Sequence[LinkCut] = (),
         world: Path | None = None, wiring: Wiring = SIM, colours: Path | None = None) -> None:
    """Start the run's nodes (the agents and the decomposers keyed with `key`), inject the
    fault, wait for Faulty's diagnosis and fill `result` in."""
    from jason_msgs.msg import Perception

    from rason_diagnosis.monitor import RunMonitor
    from rason_diagnosis.plots import save_run_picture

    sim = ros.rosrun("turtlebot_sim", "sim", params={
        "world": str(world or world_file()), "seed": result.seed,
        "real_time_factor": real_time_factor, **wiring.sim_params()})
    ros.wait_for_topic(wiring.ready_topic, timeout=60, watch=[sim])
    for robot in ROBOTS:
        ros.rosrun("kobuki_fault_injector", "fault_injector", ns=f"/{robot}",
                   params=wiring.injector_params)
        ros.rosrun("rason", "motion_decomposer", *wiring.odom_reader_args, ns=f"/{robot}",
                   params=keyed(key, HELPER_MOTION if robot == "helper" else None))
    colours = colours or world_colours(world or world_file())
    vision_colours = {"colours": str(colours.resolve())} if colours else {}
    for line in wiring.vision_nodes:
        ros.rosrun(line.package, line.executable, *line.args, ns=line.ns)
    ros.rosrun("rason_vision", "robot_synthesizer", *wiring.odom_reader_args,
               *wiring.synthesizer_args, ns="/helper",
               params={**HELPER_VISION, **wiring.synthesizer_params, **vision_colours})
    for robot in ROBOTS:
        ros.wait_for_service(f"/{robot}/fault_injector", timeout=30)
        ros.wait_for_subscriber(f"/{robot}/jason/action", timeout=30)
    ros.wait_for_topic("/helper/jason/perception", timeout=60, watch=[sim])
    ros.init_rospy("rason_demo")          # the demo process joins the run as an observer
    # the camera's frames reach the synthesizer before Helper may look: under the stock drivers
    # the image nodelets subscribe lazily, and a sweep made before they deliver sees nothing
    rospy.wait_for_message("/helper/jason/perception", Perception, timeout=60)
    monitor = RunMonitor(odom_topic=wiring.odom_topic, image_topic=wiring.image_topic,
                         cloud_topic=wiring.cloud_topic)
    if record:
        topics = [t for t in RECORDED_TOPICS if wiring.sim_time or t != "/clock"]
        topics += [f"/{r}/{wiring.odom_topic}" for r in ROBOTS if wiring.odom_topic != "odom"]
        ros.run(["rosbag", "record", "-O", str(out_dir / "run.bag"), *topics],
                label="rosbag_record", echo=False)

    if result.fault != NO_FAULT:
        reply = ros.check_output(["rosservice", "call", "/faulty/fault_injector",
                                  f"fault: '{result.fault}'"])
        say(echo, f"[demo] injected {result.fault}: {reply.strip()}")

    prefix = {robot: (f"{robot:>6} | " if echo else False) for robot in ROBOTS}
    agents = {robot: ros.rosrun("rason", "agent", robot,
                                str(agent_file(robot)), ns=f"/{robot}",
                                params=keyed(key), echo=prefix[robot])
              for robot in ("helper", "faulty")}
    ros.wait_for_node("/helper/jason/helper", watch=agents.values())
    ros.wait_for_node("/faulty/jason/faulty", watch=agents.values())

    from jason_msgs.srv import Mind

    ros.wait_for_service("/faulty/jason/faulty/mind", watch=agents.values())
    mind = rospy.ServiceProxy("/faulty/jason/faulty/mind", Mind)
    cutter = (LinkCutter(network.lan, cuts, rospy.get_time, start=rospy.get_time())
              if network and cuts else None)
    if cutter:
        cutter.start()
    diagnosis = wait_for_diagnosis(mind, {**agents, "sim": sim}, sim_timeout, "process")
    if diagnosis is not None:
        result.diagnosis = diagnosis
        if monitor.times.diagnosis is None:
            monitor.times.diagnosis = rospy.get_time()
    else:
        result.error = f"no diagnosis within {sim_timeout:g} simulated seconds"
    if result.hosts:
        _network_outcome(ros, result, agents, mind, cutter)
    if result.diagnosis == "unknown":
        result.unknown_reason = _unknown_reason(mind)

    t = monitor.times
    result.detection_s = seconds_between(t.move_start, t.help_request)
    result.location_s = seconds_between(t.help_request, t.found)
    result.diagnosis_s = seconds_between(t.found, t.diagnosis)
    result.total_s = seconds_between(t.move_start, t.diagnosis)
    result.correct = result.diagnosis == result.expected and not result.error
    result.console = [line for a in agents.values() for line in a.lines() if line.startswith("[")]
    try:
        save_run_picture(monitor, result, out_dir / "run.png")
    except Exception as err:
        say(echo, f"[demo] could not draw the run picture: {err}")
    monitor.close()


@dataclass
class WallClock:
    """A run's wall-clock seconds, on the monotonic clock; stopped by its first reading (the one
    before ``--hold``, which the result keeps however long the hold lasts)."""

    started: float = field(default_factory=time.monotonic)
    stopped: float | None = None

    def stop(self) -> float:
        """The seconds from the start to the first call, rounded to 0.1 s."""
        if self.stopped is None:
            self.stopped = round(time.monotonic() - self.started, 1)
        return self.stopped


def add_watch_options(parser: argparse.ArgumentParser, what: str) -> None:
    """The options of the mind inspector's watch over a run: ``--inspector/--no-inspector``,
    ``--inspector-port`` and ``--hold``; `what` names the run in their help ("run", "mission")."""
    parser.add_argument("--inspector", action=argparse.BooleanOptionalAction, default=True,
                        help=f"watch the {what} in the mind inspector (web page; default: on)")
    parser.add_argument("--inspector-port", type=int, default=InspectorParams().port,
                        help="the inspector's port on 127.0.0.1 (0: any free port)")
    parser.add_argument("--hold", action="store_true",
                        help=f"after the result, keep every node up (the inspector still serves "
                             f"the {what}'s history) until Ctrl-C")


R = TypeVar("R")


@dataclass
class Watch(Generic[R]):
    """What :func:`add_watch_options`' options ask of one run: the inspector's port (None: no
    inspector), and the result block, printed once: before the hold with ``--hold`` (while every
    node still runs), else when the run is over."""

    port: int | None
    hold: bool
    show: Callable[[R], None]   # prints the result block
    run: str = "demo"           # the tag of the hold's lines
    printed: bool = False

    @classmethod
    def of(cls, args: argparse.Namespace, show: Callable[[R], None], run: str) -> Watch[R]:
        """The watch the parsed options `args` ask for."""
        return cls(port=args.inspector_port if args.inspector else None, hold=args.hold,
                   show=show, run=run)

    def hold_callback(self) -> Callable[[R], None] | None:
        """The ``hold`` argument of the run function: None without ``--hold``."""
        return self.print_then_hold if self.hold else None

    def print_then_hold(self, result: R) -> None:
        """Print the result block, then hold until Ctrl-C."""
        self.print_once(result)
        hold_until_interrupted(self.run)

    def print_once(self, result: R) -> None:
        """Print the result block unless it was printed already."""
        if not self.printed:
            self.printed = True
            self.show(result)


def hold_until_interrupted(run: str = "demo") -> None:
    """``--hold``: say so (lines tagged ``[run]``) and return at Ctrl-C or SIGTERM, while the
    run's nodes, the inspector among them, stay up."""
    print(f"[{run}] holding: every node still runs (the inspector too); Ctrl-C ends", flush=True)
    try:
        while True:
            time.sleep(3600)
    except KeyboardInterrupt:
        forget_interrupt()             # acted on: the teardown that follows is no new start
        print(f"[{run}] hold ended", flush=True)


def start_inspector(ros: RosHarness, port: int, run: str = "demo") -> str:
    """Start ``rosrun rason mind_inspector`` and print its address (lines tagged ``[run]``);
    "" if it cannot listen."""
    inspector = ros.rosrun("rason", "mind_inspector", params={"port": port})
    try:
        line = inspector.wait_for_line(r"mind inspector: (http://\S+)|cannot listen.*", timeout=30)
    except HarnessError as err:
        echo_line(f"[{run}] mind inspector did not start: {str(err).splitlines()[0]}")
        return ""
    if line.group(1) is None:
        echo_line(f"[{run}] mind inspector not started: {line.group(0)}")
        return ""
    echo_line(f"[{run}] mind inspector: {line.group(1)}  (open it in a browser to watch the run)")
    return line.group(1)


DIAGNOSIS = re.compile(r"diagnosis\((\w+)\)")
UNKNOWN_BECAUSE = re.compile(r'unknownBecause\("?(.*?)"?\)(?:\[|$)')


def _network_outcome(ros: RosHarness, result: RunResult, agents: dict, mind,
                     cutter: LinkCutter | None) -> None:
    """--hosts: restore cut links, then record link events, what the agents noticed about each
    other's presence and the processes that died."""
    if cutter:
        cutter.finish()
        result.link_events = [asdict(e) for e in cutter.events]
        if cutter.errors:
            result.error = result.error or f"link cut failed: {cutter.errors[0]}"
    result.presence = [e.as_dict() for robot, proc in agents.items()
                       for e in presence_events(robot, proc.lines())]
    result.dead = [p.name for p in ros.processes if not p.alive()]
    if result.dead:
        result.error = result.error or f"processes died: {', '.join(result.dead)}"


def _unknown_reason(mind) -> str:
    """Why Faulty concluded ``unknown`` (its ``unknownBecause`` belief), or ""."""
    try:
        beliefs = mind().beliefs
    except (rospy.ServiceException, rospy.ROSException):
        beliefs = []
    return next((m.group(1) for m in map(UNKNOWN_BECAUSE.match, beliefs) if m), "")


def read_diagnosis(mind) -> str | None:
    """Faulty's ``diagnosis(D)`` belief, read through its mind service, or None."""
    try:
        beliefs = mind().beliefs
    except (rospy.ServiceException, rospy.ROSException):
        return None
    for belief in beliefs:
        match = DIAGNOSIS.match(belief)
        if match:
            return match.group(1)
    return None


#: wall-clock seconds between two looks at a run's progress (Faulty's mind, the processes)
RUN_POLL = 0.25


def raise_if_dead(processes: dict[str, Process], what: str) -> None:
    """HarnessError ``WHAT died: [names]`` naming those of ``processes`` that have exited."""
    dead = [name for name, proc in processes.items() if not proc.alive()]
    if dead:
        raise HarnessError(f"{what} died: {dead}")


def wait_for_diagnosis(mind, processes: dict[str, Process], timeout: float,
                       what: str) -> str | None:
    """Faulty's diagnosis (:func:`read_diagnosis`) once it has one, else None after ``timeout``
    seconds of ROS time; each look first checks that none of ``processes`` has died
    (:func:`raise_if_dead`, ``what`` names them in the error)."""
    def diagnosed() -> str | None:
        raise_if_interrupted()
        raise_if_dead(processes, what)
        return read_diagnosis(mind)
    return poll(diagnosed, timeout, RUN_POLL, clock=rospy.get_time)


def say(echo: bool, text: str) -> None:
    """Print `text` as one whole console line when `echo` is set."""
    if echo:
        echo_line(text)


def default_fault(seed: int) -> str:
    """The fault a seed picks when none is given: always a real one (never ``none``), so a
    first run shows the two robots cooperating; the same seed picks the same fault."""
    return random.Random(seed).choice(INJECTED_FAULTS)
