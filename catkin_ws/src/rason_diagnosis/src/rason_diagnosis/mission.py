"""``./run.sh mission [--fault F] [--at S] [--seed N] [--world FILE] [--json] [--quiet]
[--no-recovery]``: Faulty's mission, a fault during it, and the team's recovery (issue 38).

Faulty visits the waypoints of the world file's ``mission`` key in order (agents/mission/); the
fault is injected through the real fault injector service ``--at`` simulated seconds after
Faulty's first motion (default: drawn by the seed). When a motion fails, Faulty runs the
cooperative diagnosis with Helper and recovers from what it names (docs/mission.md). The run
ends when every waypoint is reached or the mission is given up with a reason; ground truth (the
simulator's ``ground_truth/odom``) gives each arrival's error.
"""

from __future__ import annotations

import argparse
import json
import math
import random
import re
import sys
import threading
import time
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import rospy
import yaml
from jason_msgs.msg import Action
from jason_msgs.srv import Mind
from nav_msgs.msg import Odometry

from rason.process.harness import HarnessError, RosHarness
from rason.process.interrupts import latch_interrupts
from rason_diagnosis.paths import agents_dir, world_file
from rason_diagnosis.scenario import (
    FAULTS,
    HELPER_MOTION,
    HELPER_VISION,
    NO_FAULT,
    ROBOTS,
    RUN_POLL,
    WallClock,
    Watch,
    add_watch_options,
    keyed,
    raise_if_dead,
    run_key,
    say,
    start_inspector,
)
from rosnode_kit.polling import poll
from turtlebot_sim.config import resolve

#: The mission's agents, a folder of ``agents/``.
MISSION_AGENTS = "mission"
#: The fault is injected, by default, this many simulated seconds after Faulty's first motion
#: at the earliest and at the latest (the fault-free mission of case_study.yaml takes ~60 s).
AT_RANGE = (2.0, 30.0)


class MissionError(ValueError):
    """A world file whose ``mission`` key cannot be run."""


@dataclass(frozen=True)
class Waypoint:
    """A point of the room (world frame, m) a robot must reach."""

    x: float
    y: float


def mission_waypoints(world: dict[str, Any]) -> list[Waypoint]:
    """The ``mission: {waypoints: [[x, y], ...]}`` of a world file's mapping (checked).

    Raises :class:`MissionError` saying what is wrong: no mission key, not a list of at least one
    [x, y] pair of finite numbers, or a point outside the room's walls."""
    mission = world.get("mission")
    if mission is None:
        raise MissionError("the world file has no mission key "
                           "(mission: {waypoints: [[x, y], ...]})")
    if not isinstance(mission, dict) or set(mission) - {"waypoints"}:
        raise MissionError(f"mission must be a mapping with the one key waypoints, got {mission!r}")
    points = mission.get("waypoints")
    if not isinstance(points, list) or not points:
        raise MissionError(f"mission.waypoints must be a non-empty list of [x, y], got {points!r}")
    size = world.get("room", {}).get("size", [10.0, 10.0])
    half_x, half_y = float(size[0]) / 2, float(size[1]) / 2
    out = []
    for i, point in enumerate(points, start=1):
        if (not isinstance(point, list) or len(point) != 2
                or not all(isinstance(v, (int, float)) and not isinstance(v, bool)
                           and math.isfinite(v) for v in point)):
            raise MissionError(f"mission.waypoints[{i}]: expected [x, y] in metres, got {point!r}")
        x, y = float(point[0]), float(point[1])
        if abs(x) >= half_x or abs(y) >= half_y:
            raise MissionError(f"mission.waypoints[{i}] ({x}, {y}) is outside the room "
                               f"({2 * half_x} x {2 * half_y} m, centred on the origin)")
        out.append(Waypoint(x, y))
    return out


def load_mission(path: Path) -> list[Waypoint]:
    """The waypoints of the world file at ``path`` (:func:`mission_waypoints`)."""
    with open(path, encoding="utf-8") as f:
        data = yaml.safe_load(f) or {}
    if not isinstance(data, dict):
        raise MissionError("a world file must be a mapping")
    return mission_waypoints(data)


def default_fault(seed: int) -> str:
    """The fault a seed draws when none is given: any of the four, or none."""
    return random.Random(seed).choice(FAULTS)


def default_at(seed: int) -> float:
    """When a seed injects the fault (simulated s after Faulty's first motion)."""
    return round(random.Random(seed * 7919 + 1).uniform(*AT_RANGE), 1)


@dataclass
class Arrival:
    """One waypoint: who reached it, when (simulated s from the mission's start) and how far
    from it that robot truly was then (ground truth, m); None fields: not reached."""

    x: float
    y: float
    reached_by: str | None = None
    at_s: float | None = None
    error_m: float | None = None


@dataclass
class MissionResult:
    """One mission run; times in simulated seconds from Faulty's first motion."""

    fault: str
    seed: int
    at_s: float
    recovery_enabled: bool = True
    completed: bool = False
    waypoints: list[Arrival] = field(default_factory=list)
    diagnosis: str | None = None
    recovery: str | None = None
    total_s: float | None = None
    reason: str | None = None
    injected_at_s: float | None = None
    min_robot_distance_m: float | None = None
    wall_s: float = 0.0
    error: str = ""
    out_dir: str = ""
    inspector: str = ""        # the mind inspector's address, when it watched the run

    def summary(self) -> dict[str, Any]:
        """The JSON object the run ends with (``reason`` only when not completed)."""
        out = asdict(self)
        if self.completed:
            out.pop("reason")
        return out


class GroundTruth:
    """The latest true position of each robot (the simulator's ``ground_truth/odom``) and the
    closest the two robots' centres came."""

    def __init__(self, robots: tuple[str, ...] = ROBOTS):
        self._lock = threading.Lock()
        self.position: dict[str, tuple[float, float]] = {}
        self.min_distance: float | None = None
        self._subs = [rospy.Subscriber(f"/{r}/ground_truth/odom", Odometry,
                                       lambda m, r=r: self._on(r, m), queue_size=5)
                      for r in robots]

    def _on(self, robot: str, msg: Any) -> None:
        p = msg.pose.pose.position
        with self._lock:
            self.position[robot] = (p.x, p.y)
            if len(self.position) >= 2:
                (ax, ay), (bx, by) = list(self.position.values())[:2]
                d = math.hypot(ax - bx, ay - by)
                self.min_distance = d if self.min_distance is None else min(self.min_distance, d)

    def error(self, robot: str, point: Waypoint) -> float | None:
        with self._lock:
            at = self.position.get(robot)
        return None if at is None else math.hypot(at[0] - point.x, at[1] - point.y)

    def close(self) -> None:
        for sub in self._subs:
            sub.unregister()


REACHED = re.compile(r"reached\((\d+),(\w+)\)")
GAVE_UP = re.compile(r"gaveUp\((.*)\)(?:\[|$)")
BELIEF = {name: re.compile(rf"{name}\((\w+)\)") for name in ("diagnosis", "recovery")}


@dataclass
class MindView:
    """What the runner reads of Faulty's beliefs (agents/mission/faulty.asl's Knowledge)."""

    reached: dict[int, str] = field(default_factory=dict)
    gave_up: str | None = None
    done: bool = False
    diagnosis: str | None = None
    recovery: str | None = None


def read_mind(beliefs: list[str]) -> MindView:
    """Parse Faulty's belief strings (as its mind service lists them)."""
    view = MindView()
    for belief in beliefs:
        compact = belief.replace(" ", "")
        if m := REACHED.match(compact):
            view.reached[int(m.group(1))] = m.group(2)
        elif m := GAVE_UP.match(belief):
            view.gave_up = m.group(1)
        elif compact.startswith("missionDone"):
            view.done = True
        for name, pattern in BELIEF.items():
            if m := pattern.match(compact):
                setattr(view, name, m.group(1))
    return view


def run_mission(fault: str, seed: int, out_dir: Path, at_s: float, world: Path,
                recovery: bool = True, echo: bool = True, sim_timeout: float = 600.0,
                inspector_port: int | None = None,
                hold: Callable[[MissionResult], None] | None = None) -> MissionResult:
    """Run one mission; returns its result (never raises for a mission that fails). With
    `inspector_port` (0: any free port) the mind inspector watches it (its mission view).
    ``hold``: called with the result once the mission is over, while every node still runs;
    the nodes stop when it returns."""
    if fault not in FAULTS:
        raise ValueError(f"unknown fault {fault!r}; valid: {', '.join(FAULTS)}")
    waypoints = load_mission(world)
    out_dir.mkdir(parents=True, exist_ok=True)
    result = MissionResult(fault=fault, seed=seed, at_s=at_s, recovery_enabled=recovery,
                           out_dir=str(out_dir),
                           waypoints=[Arrival(w.x, w.y) for w in waypoints])
    clock = WallClock()
    try:
        with run_key() as key, \
                RosHarness(sim_time=True, echo=False, log_dir=out_dir / "logs") as ros:
            if inspector_port is not None:
                result.inspector = start_inspector(ros, inspector_port, "mission")
            _run(ros, result, waypoints, world, key, recovery, echo, sim_timeout)
            if hold is not None:
                result.wall_s = clock.stop()
                hold(result)
    except HarnessError as err:
        result.error = str(err).splitlines()[0]
        result.reason = result.reason or f"error: {result.error}"
    result.wall_s = clock.stop()   # the one taken before a hold, if any
    (out_dir / "result.json").write_text(json.dumps(result.summary(), indent=2))
    return result


def _start_poses(world: Path, seed: int) -> dict[str, dict[str, float]]:
    """Each robot's true start pose, as the simulator resolves the world with this seed."""
    return {r["name"]: r for r in resolve(world, seed=seed)["robots"]}


def _run(ros: RosHarness, result: MissionResult, waypoints: list[Waypoint], world: Path,
         key: Path, recovery: bool, echo: bool, sim_timeout: float) -> None:
    """Start the mission's nodes (the agents and the decomposers keyed with `key`), inject the
    fault when due, follow the waypoints and fill `result` in."""
    starts = _start_poses(world, result.seed)
    sim = ros.rosrun("turtlebot_sim", "sim", params={"world": str(world), "seed": result.seed})
    ros.wait_for_topic("/clock", timeout=60, watch=[sim])
    for robot in ROBOTS:
        ros.rosrun("kobuki_fault_injector", "fault_injector", ns=f"/{robot}")
        ros.rosrun("rason", "motion_decomposer", ns=f"/{robot}",
                   params=keyed(key, HELPER_MOTION if robot == "helper" else None))
        start = starts[robot]
        task: dict[str, object] = ({"waypoints": [[w.x, w.y] for w in waypoints],
                                    "no_recovery": not recovery} if robot == "faulty" else {})
        ros.rosrun("rason_diagnosis", "pose_synthesizer", ns=f"/{robot}",
                   params={"origin_x": start["x"], "origin_y": start["y"],
                           "origin_yaw": start["yaw"], **task})
    ros.rosrun("rason_vision", "robot_synthesizer", ns="/helper", params=HELPER_VISION)
    for robot in ROBOTS:
        ros.wait_for_service(f"/{robot}/fault_injector", timeout=30)
        ros.wait_for_subscriber(f"/{robot}/jason/action", timeout=30)
    ros.wait_for_topic("/helper/jason/perception", timeout=60, watch=[sim])
    ros.wait_for_topic("/faulty/jason/perception", timeout=60, watch=[sim])
    ros.init_rospy("rason_mission")
    truth = GroundTruth()
    first_motion: list[float] = []
    action_sub = rospy.Subscriber(
        "/faulty/jason/action", Action,
        lambda m: first_motion.append(rospy.get_time()) if not first_motion else None)

    prefix = {robot: (f"{robot:>6} | " if echo else False) for robot in ROBOTS}
    agents = {robot: ros.rosrun("rason", "agent", robot,
                                str(agents_dir() / MISSION_AGENTS / f"{robot}.asl"),
                                ns=f"/{robot}", params=keyed(key), echo=prefix[robot])
              for robot in ("helper", "faulty")}
    ros.wait_for_service("/faulty/jason/faulty/mind", watch=agents.values())
    mind = rospy.ServiceProxy("/faulty/jason/faulty/mind", Mind)

    view = MindView()
    watched = {**agents, "sim": sim}

    def over() -> bool:
        """One look at the mission: inject the fault when due, note the waypoints reached;
        True once Faulty is done or gave up."""
        nonlocal view
        raise_if_dead(watched, "process")
        now = rospy.get_time()
        t0 = first_motion[0] if first_motion else None
        if (t0 is not None and result.fault != NO_FAULT and result.injected_at_s is None
                and now - t0 >= result.at_s):
            reply = ros.check_output(["rosservice", "call", "/faulty/fault_injector",
                                      f"fault: '{result.fault}'"])
            result.injected_at_s = round(rospy.get_time() - t0, 2)
            say(echo, f"[mission] injected {result.fault} at {result.injected_at_s} s: "
                 f"{reply.strip()}")
        try:
            view = read_mind(list(mind().beliefs))
        except (rospy.ServiceException, rospy.ROSException):
            return False
        for index, robot in view.reached.items():
            arrival = result.waypoints[index - 1]
            if arrival.reached_by is None and t0 is not None:
                error = truth.error(robot, waypoints[index - 1])
                arrival.reached_by, arrival.at_s = robot, round(now - t0, 2)
                arrival.error_m = None if error is None else round(error, 3)
                say(echo, f"[mission] waypoint {index} reached by {robot} at "
                     f"{arrival.at_s} s, {arrival.error_m} m from it (ground truth)")
        return view.done or view.gave_up is not None

    try:
        if not poll(over, sim_timeout, RUN_POLL, clock=rospy.get_time):
            result.reason = f"timeout: not over within {sim_timeout:g} simulated seconds"
    finally:
        action_sub.unregister()
        truth.close()
    t0 = first_motion[0] if first_motion else None
    result.diagnosis, result.recovery = view.diagnosis, view.recovery
    result.completed = view.done and all(a.reached_by for a in result.waypoints)
    if view.gave_up is not None:
        result.reason = view.gave_up
    if t0 is not None:
        result.total_s = round(rospy.get_time() - t0, 2)
    if truth.min_distance is not None:
        result.min_robot_distance_m = round(truth.min_distance, 3)


def parser() -> argparse.ArgumentParser:
    """The mission's command line."""
    p = argparse.ArgumentParser(prog="./run.sh mission", description=__doc__.split("\n")[0])
    p.add_argument("--fault", choices=FAULTS,
                   help=f"fault to inject (default: one of the four or {NO_FAULT}, drawn by the "
                        "seed)")
    p.add_argument("--at", type=float, default=None, metavar="SECONDS",
                   help="simulated seconds after Faulty's first motion at which the fault is "
                        f"injected (default: drawn by the seed in {AT_RANGE[0]:g}-{AT_RANGE[1]:g})")
    p.add_argument("--seed", type=int, default=None,
                   help="seed of the run's variation (default: from the clock)")
    p.add_argument("--world", type=Path, default=None,
                   help="world file with a mission key (default: worlds/case_study.yaml)")
    p.add_argument("--out", type=Path, default=None, help="folder for result.json and logs")
    p.add_argument("--json", action="store_true", help="end the output with the result as JSON")
    p.add_argument("--quiet", action="store_true", help="do not stream the agents' console")
    p.add_argument("--no-recovery", action="store_true",
                   help="the baseline: after the diagnosis Faulty gives the mission up")
    p.add_argument("--timeout", type=float, default=600.0, help="simulated seconds allowed")
    add_watch_options(p, "mission")
    return p


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    world = args.world or world_file()
    try:
        waypoints = load_mission(world)
    except (OSError, MissionError, yaml.YAMLError) as err:
        parser().error(f"--world {world}: {err}")
    seed = args.seed if args.seed is not None else int(time.time()) % 100000
    fault = args.fault or default_fault(seed)
    at_s = args.at if args.at is not None else default_at(seed)
    if at_s < 0:
        parser().error("--at must be >= 0")
    out = args.out or Path("out") / f"mission-{fault}-{seed}"
    print(f"[mission] fault {fault} at {at_s:g} s (seed {seed}), {len(waypoints)} waypoints, "
          f"recovery {'off' if args.no_recovery else 'on'}; output in {out}", flush=True)
    latch_interrupts()
    watch: Watch[MissionResult] = Watch.of(args, lambda r: _print_result(r, args.json),
                                           "mission")
    try:
        result = run_mission(fault, seed, out, at_s, world, recovery=not args.no_recovery,
                             echo=not args.quiet, sim_timeout=args.timeout,
                             inspector_port=watch.port, hold=watch.hold_callback())
    except KeyboardInterrupt:
        print("\n[mission] interrupted: every node of the run was stopped", flush=True)
        return 130
    watch.print_once(result)
    return 0 if result.completed else 1


def _print_result(result: MissionResult, as_json: bool) -> None:
    """The result block: completion, each waypoint, diagnosis and recovery, times; with
    `as_json` the result as JSON."""
    print("\n[mission] ---------------- result ----------------")
    print(f"[mission] completed : {result.completed}"
          + ("" if result.completed else f" ({result.reason})"))
    for i, a in enumerate(result.waypoints, start=1):
        print(f"[mission] waypoint {i} ({a.x:g}, {a.y:g}): "
              + (f"{a.reached_by} at {a.at_s} s, {a.error_m} m off" if a.reached_by
                 else "not reached"))
    print(f"[mission] diagnosis : {result.diagnosis}, recovery {result.recovery}")
    print(f"[mission] total     : {result.total_s} s simulated, {result.wall_s} s wall")
    if as_json:
        print(json.dumps(result.summary(), indent=2))


if __name__ == "__main__":
    sys.exit(main())
