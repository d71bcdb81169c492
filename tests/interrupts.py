"""Ending a test's child process as Ctrl-C in a terminal would, and saying why it did not end."""

from __future__ import annotations

import signal
from pathlib import Path


def sigint_as_in_a_terminal() -> None:
    """``preexec_fn`` for a run the test ends with Ctrl-C: SIGINT handled by default and not
    blocked, as a shell started from a terminal has it. A suite backgrounded without job control
    hands its children SIGINT ignored, and a child inherits its parent thread's signal mask.
    (Not why a demo once ran to its end after Ctrl-C under two xdist workers: see CHANGELOG.)"""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def signal_state(pid: int) -> str:
    """A process's blocked, ignored and caught signal masks (``/proc/PID/status``), for messages."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return "(gone)"
    return " ".join(line.replace("\t", "") for line in status.splitlines()
                    if line.startswith(("SigBlk", "SigIgn", "SigCgt")))
