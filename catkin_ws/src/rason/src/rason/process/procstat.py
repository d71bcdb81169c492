"""What the kernel says of a process (``/proc``): CPU time and resident memory, for benchmarks;
its TCP connections and its threads' scheduling slices, for tests."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path


def cpu_seconds(pid: int | str = "self") -> float:
    """User + system CPU seconds of a process (``rosrun`` execs the node, so its pid is the
    node's)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rss_mb(pid: int | str = "self") -> float:
    """Resident set size of a process, in MB."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024.0
    raise RuntimeError(f"no VmRSS for process {pid}")


@dataclass(frozen=True)
class TcpConnection:
    """One IPv4 TCP socket of a process, as ``/proc/PID/net/tcp`` lists it."""

    local_port: int
    remote_port: int
    established: bool


#: ``/proc/net/tcp``'s code for an established connection
_ESTABLISHED = "01"


def tcp_connections(pid: int) -> list[TcpConnection]:
    """The IPv4 TCP sockets process `pid` has open (found by the socket inodes of its fds)."""
    inodes = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:            # closed meanwhile
            continue
        if target.startswith("socket:["):
            inodes.add(target[len("socket:["):-1])
    connections = []
    for line in Path(f"/proc/{pid}/net/tcp").read_text().splitlines()[1:]:
        fields = line.split()
        if fields[9] in inodes:
            connections.append(TcpConnection(local_port=int(fields[1].split(":")[1], 16),
                                             remote_port=int(fields[2].split(":")[1], 16),
                                             established=fields[3] == _ESTABLISHED))
    return connections


def sched_slice(sched_file: str | Path) -> int:
    """The scheduling slice (ns) in a thread's ``sched`` file (``/proc/PID/task/TID/sched``;
    EEVDF kernels, 6.6 and later)."""
    for line in Path(sched_file).read_text().splitlines():
        if line.startswith("se.slice"):
            return int(line.split(":")[1])
    raise RuntimeError(f"no se.slice in {sched_file}: a kernel without EEVDF slices")
