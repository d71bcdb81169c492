"""The case study across machines: a host per robot on a private LAN, and link cuts.

``./run.sh demo --hosts`` puts, as on two real TurtleBots and a workstation (docs/deployment.md, "Two real
TurtleBots and a workstation"):

* ``world`` (the workstation): ``roscore`` on port 11311 and the simulator (on real robots:
  only ``roscore``, and the operator's tools); the demo process itself watches from here;
* ``helper``: Helper's fault injector, motion decomposer, vision synthesizer and agent;
* ``faulty``: Faulty's fault injector, motion decomposer and agent.

Each is a network namespace with its own address (:data:`ADDRESSES`), ``ROS_IP`` set to it,
``ROS_MASTER_URI`` pointing at the world host, and docs/deployment.md's firewall (TCP in only from the
LAN, to 11311 on the world host and to the pinned ROS port range 40000-40999). A robot's nodes
are those of its ROS namespace (``/helper``, ``/faulty``), so ``RosHarness(placement=...)``
starts them on its host.

``--cut faulty@8s+5s`` takes Faulty's link down 8 simulated seconds after the agents started
(Faulty waits 4 s, then moves), for 5 s: ``ip link set eth0 down`` on the host, then ``up``.
"""

from __future__ import annotations

import re
import signal
import socket
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass

from rason.process import netns
from rason.process.harness import echo_line
from rason.process.interrupts import interrupt

#: The hosts of the case study, in address order: world = .1, helper = .2, faulty = .3.
HOSTS = ("world", "helper", "faulty")
#: The case study's private /24 (also docs/deployment.md's example of a robot LAN).
SUBNET = "10.211.0"
#: The simulation's second network: the simulator plays each robot's Kobuki and Kinect, which
#: on a real robot hang on its own USB ports; their traffic goes over this /24, which a link cut
#: leaves alone (a robot out of WiFi range still drives and sees).
DEVICE_BUS = "10.212.0"
ADDRESSES = {name: f"{SUBNET}.{i}" for i, name in enumerate(HOSTS, 1)}

_CUT = re.compile(r"^(?P<host>[a-z][a-z0-9]*)@(?P<at>\d+(?:\.\d+)?)s?\+(?P<for>\d+(?:\.\d+)?)s?$")


@dataclass(frozen=True)
class LinkCut:
    """A host's link down at ``at`` simulated seconds, for ``duration`` seconds."""

    host: str
    at: float
    duration: float

    @classmethod
    def parse(cls, text: str) -> LinkCut:
        """``HOST@ATs+DURATIONs``, e.g. ``faulty@8s+5s`` (the ``s`` may be left out)."""
        match = _CUT.match(text.strip())
        if not match:
            raise ValueError(f"link cut {text!r}: expected HOST@SECONDSs+SECONDSs, "
                             "e.g. faulty@8s+5s")
        cut = cls(match["host"], float(match["at"]), float(match["for"]))
        if cut.host not in HOSTS[1:]:
            raise ValueError(f"link cut {text!r}: the host must be one of {', '.join(HOSTS[1:])}")
        if cut.duration <= 0:
            raise ValueError(f"link cut {text!r}: the duration must be positive")
        return cut

    def __str__(self) -> str:
        return f"{self.host}@{self.at:g}s+{self.duration:g}s"


@dataclass(frozen=True)
class LinkEvent:
    """A link going down or up, at a simulated time."""

    t: float
    host: str
    up: bool


@dataclass(frozen=True)
class PresenceEvent:
    """An agent node noticing another agent's presence lapse or return (from its log)."""

    t: float        # simulated seconds, as the noticing node logged it
    observer: str   # the robot whose agent noticed
    agent: str      # the agent it is about
    present: bool   # False: lapsed (forgotten), True: heard (again)

    def as_dict(self) -> dict:
        return asdict(self)


# rospy log lines: "[INFO] [WALL, SIM]: agent faulty not heard for 3.5 s: forgotten",
#                  "[INFO] [WALL, SIM]: agent faulty present"
_PRESENCE_LINE = re.compile(r"\[(?:[\d.]+), (?P<t>[\d.]+)\]: agent (?P<agent>\w+) "
                            r"(?P<what>present|not heard)")


def presence_events(observer: str, lines: Sequence[str]) -> list[PresenceEvent]:
    """The presence changes an agent node logged."""
    events = []
    for line in lines:
        match = _PRESENCE_LINE.search(line)
        if match:
            events.append(PresenceEvent(float(match["t"]), observer, match["agent"],
                                        match["what"] == "present"))
    return events


class LoopbackRelay(threading.Thread):
    """A loopback port of this machine relayed to the same port on the world host's loopback.

    The mind inspector listens on the world host's 127.0.0.1 (it is the workstation's tool); the
    relay lets a browser on the machine running the demo open the same address. The listening
    socket is made on construction, before this process moves to the world host; the relay's
    connections to the inspector are made by its thread, started after the move.
    """

    def __init__(self, port: int):
        super().__init__(name="loopback-relay", daemon=True)
        try:
            self.listener = socket.create_server(("127.0.0.1", port))
        except OSError:          # taken here (another run's inspector): any free port
            self.listener = socket.create_server(("127.0.0.1", 0))
        self.port: int = self.listener.getsockname()[1]

    def run(self) -> None:
        while True:
            try:
                client, _ = self.listener.accept()
            except OSError:
                return  # closed
            try:
                server = socket.create_connection(("127.0.0.1", self.port), timeout=5)
            except OSError:
                client.close()
                continue
            server.settimeout(None)
            for a, b in ((client, server), (server, client)):
                threading.Thread(target=_pump, args=(a, b), daemon=True).start()

    def close(self) -> None:
        self.listener.close()


def _pump(source: socket.socket, sink: socket.socket) -> None:
    try:
        while data := source.recv(65536):
            sink.sendall(data)
    except OSError:
        pass
    finally:
        for sock in (source, sink):
            try:
                sock.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass


class CaseStudyLan:
    """The world, helper and faulty hosts of one run (made on entry, removed on exit).

    ``relay_port``: a loopback port to relay to the world host (see :class:`LoopbackRelay`;
    0 = any free port, then :attr:`relay_port` is the one chosen).
    """

    def __init__(self, relay_port: int | None = None) -> None:
        self.lan = netns.Lan(HOSTS, subnet=SUBNET, firewall=True, bus=DEVICE_BUS)
        self._relay_wanted = relay_port
        self.relay: LoopbackRelay | None = None

    @property
    def relay_port(self) -> int | None:
        return self.relay.port if self.relay else None

    @property
    def world(self) -> netns.Host:
        return self.lan.host("world")

    def placement(self) -> dict[str, netns.Host]:
        """ROS namespace -> host: a robot's nodes run on its own computer. The simulator and
        the nodes that talk to it in a robot's place (its fault injector: the Kobuki's side)
        use their host's address on the device bus."""
        placed = {f"/{robot}": self.lan.host(robot) for robot in HOSTS[1:]}
        placed["/sim"] = self.lan.bus_host("world")
        placed.update({f"/{robot}/fault_injector": self.lan.bus_host(robot)
                       for robot in HOSTS[1:]})
        return placed

    def __enter__(self) -> CaseStudyLan:
        # SIGTERM ends the run as Ctrl-C does (KeyboardInterrupt): every node is stopped and the
        # namespaces removed on the way out. A SIGKILLed run is cleaned at the next start.
        self._sigterm = None
        if threading.current_thread() is threading.main_thread():
            self._sigterm = signal.signal(signal.SIGTERM, interrupt)
        try:
            self.lan.create()
            if self._relay_wanted is not None:
                self.relay = LoopbackRelay(self._relay_wanted)   # on this machine's loopback
            netns.enter(self.world)   # this process watches the run from the workstation
            if self.relay:
                self.relay.start()
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc: object) -> None:
        if self.relay:
            self.relay.close()
        if threading.current_thread() is threading.main_thread():
            previous = {sig: signal.signal(sig, signal.SIG_IGN)
                        for sig in (signal.SIGINT, signal.SIGTERM)}   # finish the teardown
            try:
                self.lan.remove()
            finally:
                for sig, handler in previous.items():
                    signal.signal(sig, handler)
                if self._sigterm is not None:
                    signal.signal(signal.SIGTERM, self._sigterm)
        else:
            self.lan.remove()


class LinkCutter(threading.Thread):
    """Cuts and restores links at their times while a run goes on.

    A cut's time counts simulated seconds from ``start`` (the moment the agents are up), so the
    same cut hits the same step of the diagnosis however long the nodes took to start.
    """

    def __init__(self, lan: netns.Lan, cuts: Sequence[LinkCut], now: Callable[[], float],
                 start: float = 0.0):
        super().__init__(name="link-cutter", daemon=True)
        self.lan, self.cuts, self.now, self.start_t = lan, list(cuts), now, start
        self.events: list[LinkEvent] = []
        self.errors: list[str] = []
        self._done = threading.Event()

    def run(self) -> None:
        todo = sorted([(self.start_t + c.at, c.host, False) for c in self.cuts]
                      + [(self.start_t + c.at + c.duration, c.host, True) for c in self.cuts])
        while todo and not self._done.is_set():
            now = self.now()
            while todo and todo[0][0] <= now:
                _, host, up = todo.pop(0)
                self._set(host, up, now)
            time.sleep(0.02)

    def _set(self, host: str, up: bool, now: float) -> None:
        try:
            (self.lan.restore if up else self.lan.cut)(host)
            self.events.append(LinkEvent(round(now, 2), host, up))
            echo_line(f"[hosts] {now:6.2f} s (run +{now - self.start_t:.2f} s): link of {host} "
                      f"{'up' if up else 'DOWN'}")
        except netns.NetnsError as err:
            self.errors.append(str(err))

    def finish(self) -> None:
        """Stop cutting; restore every link still down (so teardown can reach every node)."""
        self._done.set()
        self.join(2)
        for cut in self.cuts:
            if not self.lan.link_up(cut.host):
                self._set(cut.host, True, self.now())
