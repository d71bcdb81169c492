"""Stop a harness's processes when the process that started them dies without stopping them.

Each :class:`rason.process.harness.RosHarness` starts one watcher, ``python -m
rason.process.reaper ID``, in a session of its own, its stdin a pipe whose only writer is the
harness's process. The pipe ends when that process ends, however it ends: SIGKILL, ``os._exit``
(an xdist worker its controller kills after a Ctrl-C, in the middle of its teardown), or the
harness closing it after its own teardown. The watcher then stops every process still carrying
``RASON_HARNESS_ID=ID`` in its environment (SIGINT, SIGTERM, then SIGKILL to each one's process
group) and exits; after a clean teardown it finds none. Standard library only (and
``rosnode_kit.polling``, which is too), so it starts fast.
"""

from __future__ import annotations

import os
import signal
import sys
from collections.abc import Iterable, Sequence

from rosnode_kit.polling import poll

#: the environment variable naming the harness that started a process (children inherit it)
HARNESS_ID = "RASON_HARNESS_ID"
#: the environment variable naming the pid of the process whose harness started a process
HARNESS_PARENT = "RASON_HARNESS_PARENT"
#: each signal sent to the groups left, with the seconds they get to end before the next
STOP_SIGNALS = ((signal.SIGINT, 5.0), (signal.SIGTERM, 2.0), (signal.SIGKILL, 2.0))


def processes_carrying(variable: str, value: str, skip: Iterable[int] = ()) -> dict[int, str]:
    """Running processes whose environment sets ``variable=value``: pid -> command line."""
    token = f"{variable}={value}\0".encode()
    skipped = set(skip)
    found = {}
    for name in os.listdir("/proc"):
        if not name.isdigit() or int(name) in skipped:
            continue
        try:
            with open(f"/proc/{name}/environ", "rb") as f:
                env = f.read()
            with open(f"/proc/{name}/cmdline", "rb") as f:
                cmd = f.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if token in b"\0" + env + b"\0":
            found[int(name)] = cmd
    return found


def stop_harness_processes(harness_id: str) -> list[str]:
    """Stop the process groups of every process carrying ``RASON_HARNESS_ID=harness_id``;
    the ones found ("pid: argv")."""
    found = processes_carrying(HARNESS_ID, harness_id, skip=[os.getpid()])
    for sig, grace in STOP_SIGNALS:
        left = processes_carrying(HARNESS_ID, harness_id, skip=[os.getpid()])
        if not left:
            break
        for pid in left:
            try:
                os.killpg(os.getpgid(pid), sig)
            except (ProcessLookupError, PermissionError):
                pass
        poll(lambda: not processes_carrying(HARNESS_ID, harness_id, skip=[os.getpid()]), grace,
             0.1)
    return [f"{pid}: {cmd[:120]}" for pid, cmd in found.items()]


def main(argv: Sequence[str] | None = None) -> int:
    """Wait for the end of stdin, then stop what the harness ``argv[0]`` left running."""
    args = list(sys.argv[1:] if argv is None else argv)
    if len(args) != 1:
        print("usage: python -m rason.process.reaper HARNESS_ID  (stdin: the harness's pipe)",
              file=sys.stderr)
        return 2
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # a Ctrl-C of the run is the harness's to act on
    sys.stdin.buffer.read()
    left = stop_harness_processes(args[0])
    if left:
        print("rason reaper: stopped what a harness left running:\n  " + "\n  ".join(left),
              file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
