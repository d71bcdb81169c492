"""Hosts on a private LAN made of Linux network namespaces, for runs across "machines" (root only).

A :class:`Lan` is one switch (a bridge in its own namespace) and one namespace per host, each
host plugged into the switch by a veth pair whose host end is ``eth0`` with the host's own
address (``10.211.0.0/24`` by default). Nothing is routed outside: traffic stays between the
namespaces of the run. A process runs on a host through ``ip netns exec`` (same pid, so the
harness's process-group teardown still works)::

    with Lan(["world", "helper"]) as lan:
        world = lan.host("world")
        argv = world.command(["roscore"])     # ip netns exec rason-1234-world roscore
        lan.cut("helper"); lan.restore("helper")

Namespaces are named ``rason-<pid>-<host>`` after the process that made them; :func:`clean_stale`
removes the sets (and the processes still inside) of processes that are gone, so a killed run is
cleaned at the next start while a run going on in parallel is left alone.
"""

from __future__ import annotations

import ctypes
import os
import re
import signal
import subprocess
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from rosnode_kit.polling import poll

#: Prefix of every namespace this module makes.
PREFIX = "rason"
#: The first three octets of the default private /24.
DEFAULT_SUBNET = "10.211.0"
#: The name of a host's interface inside its namespace (as on a robot: its one network card).
DEVICE = "eth0"
#: The name of a host's interface on the optional second network (see :class:`Lan` ``bus``).
BUS_DEVICE = "bus0"
#: The ROS master's port (roscore's default).
MASTER_PORT = 11311
#: The ports ROS 1 nodes listen on: every node's XML-RPC server and TCPROS server take an
#: ephemeral port (bind to port 0), so the host's ephemeral range is pinned to these.
ROS_PORTS = (40000, 40999)
_NAME = re.compile(rf"^{PREFIX}-(\d+)-([\w-]+)$")
_SWITCH = "lan"
_CLONE_NEWNET = 0x40000000


class NetnsError(RuntimeError):
    """An ``ip`` command failed (not root, no netns support, a name taken...)."""


@dataclass(frozen=True)
class Host:
    """One machine of the LAN: a namespace, its address and its one interface."""

    name: str        # the role: "world", "helper", "faulty", "robot7"...
    netns: str       # the namespace: rason-<pid>-<name>
    address: str     # its private IPv4 address on the LAN
    device: str = DEVICE

    def command(self, argv: Sequence[str]) -> list[str]:
        """``argv`` to run on this host (``ip netns exec`` execs it: the pid stays the same)."""
        return ["ip", "netns", "exec", self.netns, *argv]

    def env(self, master_uri: str) -> dict[str, str]:
        """The ROS variables of a node on this host, as on a real robot."""
        return {"ROS_IP": self.address, "ROS_MASTER_URI": master_uri}


def ip(*args: str, check: bool = True) -> str:
    """Run ``ip ARGS...``; its stdout (raises NetnsError with ip's message when it fails)."""
    done = subprocess.run(["ip", *args], capture_output=True, text=True, timeout=20)
    if check and done.returncode != 0:
        raise NetnsError(f"ip {' '.join(args)}: {done.stderr.strip() or done.returncode}")
    return done.stdout


def namespaces() -> list[str]:
    """Names of the network namespaces ``ip netns`` knows."""
    return [line.split()[0] for line in ip("netns", "list").splitlines() if line.strip()]


def _pid_alive(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    return True


def kill_inside(netns: str, grace: float = 3.0) -> list[int]:
    """Stop every process still running in ``netns`` (SIGTERM, then SIGKILL); their pids.

    This process itself is spared (it may have entered the namespace to watch the run)."""
    pids = [int(p) for p in ip("netns", "pids", netns, check=False).split()
            if int(p) != os.getpid()]
    for sig in (signal.SIGTERM, signal.SIGKILL):
        for pid in pids:
            try:
                os.kill(pid, sig)
            except ProcessLookupError:
                pass
        poll(lambda: not any(_pid_alive(p) for p in pids), grace, 0.05)
    return pids


def delete(netns: str) -> None:
    """Stop the processes inside ``netns`` and delete it (its veth ends go with it)."""
    kill_inside(netns)
    ip("netns", "delete", netns, check=False)


def clean_stale(keep_pid: int | None = None) -> list[str]:
    """Delete the namespaces of rason runs whose process is gone; the names deleted."""
    removed = []
    for name in namespaces():
        match = _NAME.match(name)
        if not match:
            continue
        owner = int(match.group(1))
        if owner == keep_pid or (owner != os.getpid() and _pid_alive(owner)):
            continue
        delete(name)
        removed.append(name)
    return removed


def ros_firewall(host: Host, subnets: Sequence[str], master: bool) -> None:
    """A robot's firewall for ROS 1 (docs/deployment.md, "Firewall"): the ephemeral port range pinned to
    :data:`ROS_PORTS`; TCP in only from the robot LAN (``subnets``: first three octets of each
    /24), only to those ports (and to :data:`MASTER_PORT` on the master's host); everything
    else in is dropped."""
    low, high = ROS_PORTS
    subprocess.run(host.command(["sysctl", "-q", "-w",
                                 f"net.ipv4.ip_local_port_range={low} {high}"]),
                   check=True, timeout=20)
    ports = f"{MASTER_PORT}, {low}-{high}" if master else f"{low}-{high}"
    sources = ", ".join(f"{subnet}.0/24" for subnet in subnets)
    rules = f"""table inet rason_ros {{
  chain input {{
    type filter hook input priority filter; policy drop;
    iif lo accept
    ct state established,related accept
    meta l4proto icmp accept
    ip saddr {{ {sources} }} tcp dport {{ {ports} }} accept
  }}
}}
"""
    done = subprocess.run(host.command(["nft", "-f", "-"]), input=rules, text=True,
                          capture_output=True, timeout=20)
    if done.returncode != 0:
        raise NetnsError(f"nft on {host.name}: {done.stderr.strip()}")


class Lan:
    """A switch and one namespace per host, made by :meth:`create`, removed by :meth:`remove`.

    Args:
        hosts: the host names, in address order (the first gets ``.1``).
        subnet: the first three octets of the private /24.
        firewall: give every host the ROS firewall of :func:`ros_firewall`, the first host
            as the master's (needs ``nft``, Debian's nftables).
        bus: the first three octets of a second /24 joining the same hosts through a second
            interface (``bus0``) and switch, which :meth:`cut` leaves alone (a simulation's
            stand-in for the cables between a robot and its devices); None: no second network.
    """

    def __init__(self, hosts: Iterable[str], subnet: str = DEFAULT_SUBNET,
                 firewall: bool = False, bus: str | None = None):
        names = list(hosts)
        if len(set(names)) != len(names) or not names:
            raise ValueError(f"host names must be distinct and not empty: {names}")
        if len(names) > 250:
            raise ValueError("a /24 holds at most 250 hosts here")
        for name in names:
            if not re.fullmatch(r"[a-z][a-z0-9]{0,9}", name):
                raise ValueError(f"host name {name!r}: lowercase letters and digits, at most 10")
        self.owner = os.getpid()
        self.subnet = subnet
        self.bus = bus
        self.firewall = firewall
        self.master = names[0]
        self.switch = f"{PREFIX}-{self.owner}-{_SWITCH}"
        self.hosts = {name: Host(name, f"{PREFIX}-{self.owner}-{name}", f"{subnet}.{i}")
                      for i, name in enumerate(names, 1)}
        self.created: list[str] = []

    def host(self, name: str) -> Host:
        try:
            return self.hosts[name]
        except KeyError:
            raise KeyError(f"no host {name!r} on this LAN (hosts: {', '.join(self.hosts)})") from None

    def bus_host(self, name: str) -> Host:
        """``name`` as seen on the second network (same namespace, its ``bus0`` address)."""
        if self.bus is None:
            raise ValueError("this LAN has no bus")
        host = self.host(name)
        index = host.address.rsplit(".", 1)[1]
        return Host(host.name, host.netns, f"{self.bus}.{index}", BUS_DEVICE)

    # -- life cycle ------------------------------------------------------------------------------
    def create(self) -> Lan:
        """Clean stale sets, then make the switch and plug every host in."""
        clean_stale()
        try:
            self._add_netns(self.switch)
            ip("-n", self.switch, "link", "add", "br0", "type", "bridge")
            ip("-n", self.switch, "link", "set", "dev", "br0", "up")
            if self.bus is not None:
                ip("-n", self.switch, "link", "add", "br1", "type", "bridge")
                ip("-n", self.switch, "link", "set", "dev", "br1", "up")
            ip("-n", self.switch, "link", "set", "dev", "lo", "up")
            for host in self.hosts.values():
                self.add(host)
        except BaseException:
            self.remove()
            raise
        return self

    def _add_netns(self, name: str) -> None:
        ip("netns", "add", name)
        self.created.append(name)

    def add(self, host: Host) -> None:
        """Make ``host``'s namespace and plug it into the switch (a host joining the LAN)."""
        self.hosts.setdefault(host.name, host)
        self._add_netns(host.netns)
        ip("link", "add", host.device, "netns", host.netns, "type", "veth",
           "peer", "name", self.port(host.name), "netns", self.switch)
        ip("-n", self.switch, "link", "set", "dev", self.port(host.name), "master", "br0")
        ip("-n", self.switch, "link", "set", "dev", self.port(host.name), "up")
        ip("-n", host.netns, "addr", "add", f"{host.address}/24", "dev", host.device)
        ip("-n", host.netns, "link", "set", "dev", "lo", "up")
        ip("-n", host.netns, "link", "set", "dev", host.device, "up")
        if self.bus is not None:
            bus = self.bus_host(host.name)
            ip("link", "add", bus.device, "netns", host.netns, "type", "veth",
               "peer", "name", f"b-{host.name}", "netns", self.switch)
            ip("-n", self.switch, "link", "set", "dev", f"b-{host.name}", "master", "br1")
            ip("-n", self.switch, "link", "set", "dev", f"b-{host.name}", "up")
            ip("-n", host.netns, "addr", "add", f"{bus.address}/24", "dev", bus.device)
            ip("-n", host.netns, "link", "set", "dev", bus.device, "up")
        if self.firewall:
            subnets = [self.subnet] + ([self.bus] if self.bus is not None else [])
            ros_firewall(host, subnets, master=host.name == self.master)

    def port(self, name: str) -> str:
        """The switch's end of ``name``'s veth pair."""
        return f"p-{name}"

    def remove(self) -> None:
        """Stop what still runs in the namespaces and delete them (hosts first, then the switch)."""
        for name in reversed(self.created):
            delete(name)
        self.created.clear()

    def __enter__(self) -> Lan:
        return self.create()

    def __exit__(self, *exc: object) -> None:
        self.remove()

    # -- link faults -----------------------------------------------------------------------------
    def cut(self, name: str) -> None:
        """Take ``name``'s link down (``ip link set eth0 down`` on the host): it is cut off."""
        host = self.host(name)
        ip("-n", host.netns, "link", "set", "dev", host.device, "down")

    def restore(self, name: str) -> None:
        """Bring ``name``'s link up again (its address and route come back with it)."""
        host = self.host(name)
        ip("-n", host.netns, "link", "set", "dev", host.device, "up")

    def link_up(self, name: str) -> bool:
        """True while ``name``'s interface is administratively up."""
        host = self.host(name)
        shown = ip("-n", host.netns, "-o", "link", "show", "dev", host.device)
        flags = shown.split("<", 1)[1].split(">", 1)[0].split(",")
        return "UP" in flags


def enter(host: Host) -> None:
    """Move the calling thread (and the threads it starts later) onto ``host``'s network.

    Call it from the main thread before anything networked starts (rospy, sockets): a process
    that observes a run, as a workstation would, joins the LAN this way.
    """
    libc = ctypes.CDLL(None, use_errno=True)
    fd = os.open(f"/run/netns/{host.netns}", os.O_RDONLY)
    try:
        if libc.setns(fd, _CLONE_NEWNET) != 0:
            err = ctypes.get_errno()
            raise NetnsError(f"setns({host.netns}): {os.strerror(err)}")
    finally:
        os.close(fd)
