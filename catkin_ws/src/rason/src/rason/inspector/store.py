"""What the mind inspector knows, without ROS or HTTP: agents, their mind history, the robots.

ROS callbacks write here from rospy's threads; the web server reads from its event loop. Every
change calls ``on_change(kind, payload)`` (the web layer turns it into a pushed event), outside
the store's lock. Changes are pushed one agent at a time (``agent``: its summary, ``gone``: its
name), never as the whole list.

Memory is bounded whatever the graph sends: at most ``max_agents`` agents are listed (names
heard beyond that are ignored until a place frees), at most ``MAX_GONE`` agents that left are
kept (their last states stay readable), and the mind states of all agents together take at most
``history_bytes`` of JSON text (the oldest states go first, each agent's newest last; a state
larger than half of it is refused).
"""

from __future__ import annotations

import json
import math
import threading
from collections import OrderedDict, deque
from collections.abc import Callable
from dataclasses import asdict, dataclass, field

from rason.inspector.mission import mission_of

Notify = Callable[[str, dict], None]

#: Fields a mind_state document must have (rason.ros.mind_state) to be kept.
REQUIRED_FIELDS = ("agent", "mind")
TRAIL_POINTS = 600          # poses kept per trail
TRAIL_STEP_M = 0.01         # a trail point every centimetre moved...
TRAIL_STEP_RAD = 0.03       # ...or 1.7 degrees turned
#: agents that left (goodbye or silence) kept with their history; older ones are pruned
MAX_GONE = 32
#: the longest agent name listed (longer ones are ignored: a flood of huge names is not kept)
MAX_NAME = 100
#: perception sources kept per robot, and diagnostics kept, before the oldest go
MAX_SOURCES = 64
MAX_DIAGNOSTICS = 256
#: agents whose missions are kept (the latest to change last)
MAX_MISSIONS = 16


@dataclass
class MindEntry:
    """One mind state of an agent, numbered per agent from 0 (numbers are never reused); kept
    as the JSON text it came in (what the page gets, and what the byte bound counts)."""

    index: int
    received: float           # ROS time the inspector got it
    text: str
    seq: int = 0              # arrival number among every agent's states

    @property
    def state(self) -> dict:
        return json.loads(self.text)


@dataclass
class AgentRecord:
    """An agent found through presence, its mind_state topic and its bounded history."""

    name: str
    present: bool = True
    topic: str | None = None
    namespace: str | None = None
    history: deque[MindEntry] = field(default_factory=deque)
    next_index: int = 0

    def summary(self) -> dict:
        last = self.history[-1] if self.history else None
        return {"name": self.name, "present": self.present, "topic": self.topic,
                "namespace": self.namespace,
                "first": self.history[0].index if self.history else None,
                "last": last.index if last else None}


class BadMindState(ValueError):
    """A mind_state message that is not a JSON object of the expected shape, or too large."""


class InspectorStore:
    """Agents and their mind histories (at most `history` states each and `history_bytes` of
    JSON text in all), thread-safe."""

    def __init__(self, history: int = 300, on_change: Notify | None = None,
                 history_bytes: int = 64 * 1024 * 1024, max_agents: int = 1000) -> None:
        if history < 1:
            raise ValueError(f"history must keep at least one state, not {history}")
        self.history = history
        self.history_bytes = history_bytes
        self.max_agents = max_agents
        self.on_change: Notify = on_change or (lambda kind, payload: None)
        self.robots = RobotsView()
        self._agents: dict[str, AgentRecord] = {}
        self._gone: OrderedDict[str, None] = OrderedDict()    # absent agents, oldest first
        self._present = 0
        self._bytes = 0
        self._states = 0
        self._seq = 0
        #: (agent, seq) of every state kept (and some dropped since), oldest first
        self._arrivals: deque[tuple[str, int]] = deque()
        #: names ignored because max_agents were listed (a warning's figure)
        self.refused = 0
        self._lock = threading.Lock()

    # -- agents ---------------------------------------------------------------------------------
    def agent_heard(self, name: str) -> bool:
        """`name` announced itself; True if it is new (or back). A new name is ignored while
        `max_agents` are listed, and a name longer than MAX_NAME always."""
        if len(name) > MAX_NAME:
            return False
        with self._lock:
            record = self._agents.get(name)
            if record is not None and record.present:
                return False
            if self._present >= self.max_agents:
                self.refused += 1
                return False
            if record is None:
                record = self._agents[name] = AgentRecord(name)
            self._gone.pop(name, None)
            record.present = True
            self._present += 1
            summary = record.summary()
        self.on_change("agent", summary)
        return True

    def agent_gone(self, name: str) -> bool:
        """`name` said goodbye or was not heard for too long; True if it was present. Agents
        that left beyond the last MAX_GONE are forgotten, history and all."""
        with self._lock:
            record = self._agents.get(name)
            if record is None or not record.present:
                return False
            record.present = False
            self._present -= 1
            if record.history:
                self._gone[name] = None
            else:                   # nothing to show of it: forget it at once
                del self._agents[name]
            while len(self._gone) > MAX_GONE:
                self._forget(self._gone.popitem(last=False)[0])
        self.on_change("gone", {"name": name})
        return True

    def _forget(self, name: str) -> None:
        record = self._agents.pop(name)
        self._bytes -= sum(len(e.text) for e in record.history)
        self._states -= len(record.history)
        record.history.clear()          # its places in _arrivals are skipped when reached

    def set_topic(self, name: str, topic: str) -> None:
        with self._lock:
            record = self._agents.get(name)
            if record is None or record.topic == topic:
                return
            record.topic = topic
            summary = record.summary()
        self.on_change("agent", summary)

    def without_topic(self) -> list[str]:
        """Present agents whose mind_state topic is not known yet."""
        with self._lock:
            return [r.name for r in self._agents.values() if r.present and r.topic is None]

    def add_state(self, name: str, text: str, received: float) -> MindEntry:
        """Keep a mind state of `name` (a mind_state document, JSON text)."""
        if len(text) > self.history_bytes // 2:
            raise BadMindState(f"mind_state of {name} is {len(text):,} bytes, more than half of "
                               f"~history_bytes ({self.history_bytes:,})")
        try:
            state = json.loads(text)
        except ValueError as err:
            raise BadMindState(f"mind_state of {name} is not JSON: {err}") from None
        if not isinstance(state, dict) or any(k not in state for k in REQUIRED_FIELDS) \
                or not isinstance(state["mind"], dict):
            raise BadMindState(f"mind_state of {name} lacks {', '.join(REQUIRED_FIELDS)}")
        namespace = state.get("namespace")
        with self._lock:
            record = self._agents.get(name)
            if record is None:
                raise KeyError(name)
            self._seq += 1
            entry = MindEntry(record.next_index, received, text, self._seq)
            record.next_index += 1
            if len(record.history) >= self.history:
                self._bytes -= len(record.history.popleft().text)
                self._states -= 1
            record.history.append(entry)
            self._bytes += len(text)
            self._states += 1
            self._arrivals.append((name, entry.seq))
            self._trim((name, entry.seq))
            first = record.history[0].index
            changed = entry.index == 0 or namespace != record.namespace
            record.namespace = namespace if isinstance(namespace, str) else None
            summary = record.summary()
        beliefs = state["mind"].get("beliefs")
        if isinstance(beliefs, list):
            mission = mission_of(name, [b for b in beliefs if isinstance(b, dict)])
            if mission is not None:
                self.robots.mission(name, mission.to_dict())
        if changed:
            self.on_change("agent", summary)        # its namespace is known from now on
        self.on_change("mind", {"agent": name, "index": entry.index, "first": first})
        return entry

    def _trim(self, newest: tuple[str, int]) -> None:
        """Drop the oldest states until all fit in history_bytes: first those that are not an
        agent's newest, then (many agents with large minds) newest ones too, except `newest`."""
        if self._bytes > self.history_bytes:
            self._drop(lambda record: len(record.history) > 1, newest)
        if self._bytes > self.history_bytes:
            self._drop(lambda record: True, newest)
        if len(self._arrivals) > 2 * self._states + 1024:     # forget dropped states' places
            self._arrivals = deque(a for a in self._arrivals if self._live(a))

    def _live(self, arrival: tuple[str, int]) -> bool:
        record = self._agents.get(arrival[0])
        return record is not None and bool(record.history) and \
            record.history[0].seq <= arrival[1]

    def _drop(self, droppable: Callable[[AgentRecord], bool], keep: tuple[str, int]) -> None:
        kept: list[tuple[str, int]] = []
        while self._arrivals and self._bytes > self.history_bytes:
            arrival = self._arrivals.popleft()
            if not self._live(arrival):
                continue
            record = self._agents[arrival[0]]     # arrival is its oldest state (they are in order)
            if arrival == keep or not droppable(record):
                kept.append(arrival)
                continue
            self._bytes -= len(record.history.popleft().text)
            self._states -= 1
        self._arrivals.extendleft(reversed(kept))

    def memory(self) -> dict:
        """What the store holds: agents listed, agents kept that left, bytes of mind states."""
        with self._lock:
            return {"present": self._present, "gone": len(self._gone), "bytes": self._bytes,
                    "refused": self.refused}

    def agents(self) -> list[dict]:
        """The present agents, sorted by name."""
        with self._lock:
            return [r.summary() for r in sorted(self._agents.values(), key=lambda r: r.name)
                    if r.present]

    def known(self, name: str) -> bool:
        with self._lock:
            return name in self._agents

    def mind_text(self, name: str, index: int | None = None) -> tuple[dict, str] | None:
        """State `index` of `name` (the latest when None): the history's bounds and the state's
        JSON text; None if the agent has no such state (unknown agent, nothing yet, or dropped
        from the history)."""
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
                    "present": record.present}, entry.text

    def mind(self, name: str, index: int | None = None) -> dict | None:
        """Like :meth:`mind_text`, with the state parsed (under ``state``)."""
        found = self.mind_text(name, index)
        return None if found is None else {**found[0], "state": json.loads(found[1])}


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
    """Robots' poses, perceptions, camera frames, diagnostics and the missions the agents
    believe they have (the page's second view)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self.version = 0
        self._odom: dict[str, Track] = {}
        self._truth: dict[str, Track] = {}
        self._perceptions: dict[str, dict[str, list[str]]] = {}   # robot -> source -> list
        self._diagnostics: dict[str, dict] = {}
        self._cameras: dict[str, CameraFrame] = {}
        self._missions: dict[str, dict] = {}    # agent -> rason.inspector.mission.MissionState

    def pose(self, robot: str, truth: bool, pose: Pose) -> None:
        with self._lock:
            tracks = self._truth if truth else self._odom
            tracks.setdefault(robot, Track()).add(pose)
            self.version += 1

    def perception(self, robot: str, source: str, perceptions: list[str]) -> None:
        with self._lock:
            sources = self._perceptions.setdefault(robot, {})
            sources.pop(source, None)
            sources[source] = list(perceptions)
            _keep_newest(sources, MAX_SOURCES)
            self.version += 1

    def diagnostic(self, name: str, level: int, message: str, values: dict[str, str],
                   stamp: float) -> None:
        with self._lock:
            self._diagnostics.pop(name, None)
            self._diagnostics[name] = {"name": name, "level": level, "message": message,
                                       "values": values, "stamp": stamp}
            _keep_newest(self._diagnostics, MAX_DIAGNOSTICS)
            self.version += 1

    def mission(self, agent: str, mission: dict) -> None:
        """The mission `agent` believes it has (a MissionState as a dict); a change only when
        it differs from the last one."""
        with self._lock:
            if self._missions.get(agent) == mission:
                return
            self._missions.pop(agent, None)
            self._missions[agent] = mission
            _keep_newest(self._missions, MAX_MISSIONS)
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
                    "diagnostics": sorted(self._diagnostics.values(), key=lambda d: d["name"]),
                    "missions": dict(sorted(self._missions.items()))}


def _keep_newest(items: dict, most: int) -> None:
    """Drop the entries added first (dicts keep insertion order) until `most` are left."""
    while len(items) > most:
        del items[next(iter(items))]


def _track(track: Track | None) -> dict | None:
    if track is None or track.pose is None:
        return None
    first = asdict(track.first) if track.first is not None else None
    return {"pose": asdict(track.pose), "first": first, "trail": list(track.trail)}
