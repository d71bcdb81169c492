"""What the mind inspector knows, without ROS or HTTP: agents, their mind history, the robots.

ROS callbacks write here from rospy's threads; the web server reads from its event loop. Every
change calls ``on_change(kind, payload)`` (the web layer turns it into a pushed event), outside
the store's lock.
"""

from __future__ import annotations

import math
import threading
from collections import deque
from collections.abc import Callable
from dataclasses import asdict, dataclass, field
from typing import Any

Notify = Callable[[str, dict], None]

#: Fields a mind_state document must have (rason.ros.mind_state) to be kept.
REQUIRED_FIELDS = ("agent", "mind")
TRAIL_POINTS = 600          # poses kept per trail
TRAIL_STEP_M = 0.01         # a trail point every centimetre moved...
TRAIL_STEP_RAD = 0.03       # ...or 1.7 degrees turned


@dataclass
class MindEntry:
    """One mind state of an agent, numbered per agent from 0 (numbers are never reused)."""

    index: int
    received: float           # ROS time the inspector got it
    state: dict


@dataclass
class AgentRecord:
    """An agent found through presence, its mind_state topic and its bounded history."""

    name: str
    present: bool = True
    topic: str | None = None
    history: deque[MindEntry] = field(default_factory=deque)
    next_index: int = 0

    def summary(self) -> dict:
        last = self.history[-1] if self.history else None
        return {"name": self.name, "present": self.present, "topic": self.topic,
                "namespace": last.state.get("namespace") if last else None,
                "first": self.history[0].index if self.history else None,
                "last": last.index if last else None}


class BadMindState(ValueError):
    """A mind_state message that is not a JSON object of the expected shape."""


class InspectorStore:
    """Agents and their mind histories (at most `history` states each), thread-safe."""

    def __init__(self, history: int = 300, on_change: Notify | None = None) -> None:
        if history < 1:
            raise ValueError(f"history must keep at least one state, not {history}")
        self.history = history
        self.on_change: Notify = on_change or (lambda kind, payload: None)
        self.robots = RobotsView()
        self._agents: dict[str, AgentRecord] = {}
        self._lock = threading.Lock()

    # -- agents ---------------------------------------------------------------------------------
    def agent_heard(self, name: str) -> bool:
        """`name` announced itself; True if it is new (or back)."""
        with self._lock:
            record = self._agents.get(name)
            if record is not None and record.present:
                return False
            if record is None:
                record = self._agents[name] = AgentRecord(
                    name, history=deque(maxlen=self.history))
            record.present = True
        self._agents_changed()
        return True

    def agent_gone(self, name: str) -> bool:
        """`name` said goodbye or was not heard for too long; True if it was present."""
        with self._lock:
            record = self._agents.get(name)
            if record is None or not record.present:
                return False
            record.present = False
        self._agents_changed()
        return True

    def set_topic(self, name: str, topic: str) -> None:
        with self._lock:
            record = self._agents.get(name)
            if record is None or record.topic == topic:
                return
            record.topic = topic
        self._agents_changed()

    def without_topic(self) -> list[str]:
        """Present agents whose mind_state topic is not known yet."""
        with self._lock:
            return [r.name for r in self._agents.values() if r.present and r.topic is None]

    def add_state(self, name: str, state: Any, received: float) -> MindEntry:
        """Keep a mind state of `name` (a parsed mind_state document)."""
        if not isinstance(state, dict) or any(k not in state for k in REQUIRED_FIELDS) \
                or not isinstance(state["mind"], dict):
            raise BadMindState(f"mind_state of {name} lacks {', '.join(REQUIRED_FIELDS)}")
        with self._lock:
            record = self._agents.get(name)
            if record is None:
                raise KeyError(name)
            entry = MindEntry(record.next_index, received, state)
            record.next_index += 1
            record.history.append(entry)
            first = record.history[0].index
        if entry.index == 0:
            self._agents_changed()          # its namespace is known from now on
        self.on_change("mind", {"agent": name, "index": entry.index, "first": first})
        return entry

    def agents(self) -> list[dict]:
        """The present agents, sorted by name."""
        with self._lock:
            return [r.summary() for r in sorted(self._agents.values(), key=lambda r: r.name)
                    if r.present]

    def known(self, name: str) -> bool:
        with self._lock:
            return name in self._agents

    def mind(self, name: str, index: int | None = None) -> dict | None:
        """State `index` of `name` (the latest when None), with the history's bounds; None if
        the agent has no such state (unknown agent, nothing yet, or dropped from the history)."""
        with self._lock:
            record = self._agents.get(name)
            if record is None or not record.history:
                return None
            history = record.history
            first = history[0].index
            if index is None:
                entry = history[-1]
            elif first <= index <= history[-1].index:
                entry = history[index - first]
            else:
                return None
            return {"agent": name, "index": entry.index, "first": first,
                    "last": history[-1].index, "received": entry.received,
                    "present": record.present, "state": entry.state}

    def _agents_changed(self) -> None:
        self.on_change("agents", {"agents": self.agents()})


@dataclass
class Pose:
    x: float
    y: float
    yaw: float                # radians, counter-clockwise from +x
    stamp: float


@dataclass
class Track:
    """A robot's pose from one source (its odometry or the simulator's ground truth)."""

    pose: Pose | None = None
    first: Pose | None = None         # the first pose seen (anchors odometry on the map)
    trail: list[list[float]] = field(default_factory=list)   # [x, y] points

    def add(self, pose: Pose) -> None:
        last = self.pose
        self.pose = pose
        if self.first is None:
            self.first = pose
        if last is None or not self.trail or \
                math.hypot(pose.x - self.trail[-1][0], pose.y - self.trail[-1][1]) > TRAIL_STEP_M \
                or abs(pose.yaw - last.yaw) > TRAIL_STEP_RAD:
            self.trail.append([round(pose.x, 4), round(pose.y, 4)])
            del self.trail[:-TRAIL_POINTS]


@dataclass
class CameraFrame:
    """The last frame of a robot's camera, kept raw; encoded only when a page asks for it."""

    seq: int
    stamp: float
    width: int
    height: int
    encoding: str
    data: bytes


class RobotsView:
    """Robots' poses, perceptions, camera frames and diagnostics (the page's second view)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.version = 0
        self._odom: dict[str, Track] = {}
        self._truth: dict[str, Track] = {}
        self._perceptions: dict[str, dict[str, list[str]]] = {}   # robot -> source -> list
        self._diagnostics: dict[str, dict] = {}
        self._cameras: dict[str, CameraFrame] = {}

    def pose(self, robot: str, truth: bool, pose: Pose) -> None:
        with self._lock:
            tracks = self._truth if truth else self._odom
            tracks.setdefault(robot, Track()).add(pose)
            self.version += 1

    def perception(self, robot: str, source: str, perceptions: list[str]) -> None:
        with self._lock:
            self._perceptions.setdefault(robot, {})[source] = list(perceptions)
            self.version += 1

    def diagnostic(self, name: str, level: int, message: str, values: dict[str, str],
                   stamp: float) -> None:
        with self._lock:
            self._diagnostics[name] = {"name": name, "level": level, "message": message,
                                       "values": values, "stamp": stamp}
            self.version += 1

    def camera(self, robot: str, frame: CameraFrame) -> None:
        with self._lock:
            self._cameras[robot] = frame
            self.version += 1

    def frame(self, robot: str) -> CameraFrame | None:
        with self._lock:
            return self._cameras.get(robot)

    def snapshot(self) -> dict:
        """Everything but the camera pixels, JSON-ready."""
        with self._lock:
            names = sorted(set(self._odom) | set(self._truth) | set(self._perceptions)
                           | set(self._cameras))
            robots = {}
            for name in names:
                odom, truth = self._odom.get(name), self._truth.get(name)
                frame = self._cameras.get(name)
                robots[name] = {
                    "odom": _track(odom), "truth": _track(truth),
                    "perceptions": dict(self._perceptions.get(name, {})),
                    "camera": ({"seq": frame.seq, "stamp": frame.stamp, "width": frame.width,
                                "height": frame.height} if frame else None)}
            return {"version": self.version, "robots": robots,
                    "diagnostics": sorted(self._diagnostics.values(), key=lambda d: d["name"])}


def _track(track: Track | None) -> dict | None:
    if track is None or track.pose is None:
        return None
    first = asdict(track.first) if track.first is not None else None
    return {"pose": asdict(track.pose), "first": first, "trail": list(track.trail)}
