"""A Ctrl-C or SIGTERM that ends a run, remembered so that it cannot be lost.

Python turns SIGINT into KeyboardInterrupt in whatever the main thread runs at that moment.
Code that catches every exception there (a bare ``except:`` in a library) swallows it, and the
run goes on as if nobody had asked it to stop. A run's entry point calls
:func:`latch_interrupts`: its handler, :func:`interrupt`, records the signal and the frames it
was raised in, then raises KeyboardInterrupt as Python's own handler does. The harness's start
and wait steps and the run's own wait loops call :func:`raise_if_interrupted`, which raises it
again if it was swallowed, and names the place once on stderr.

Teardown never calls the check (it must finish), and an interruption that was acted on
(``--hold`` ended by Ctrl-C) is forgotten with :func:`forget_interrupt`.
"""

from __future__ import annotations

import signal
import sys
import threading
import traceback
from dataclasses import dataclass
from types import FrameType

#: how many of the innermost frames the note of a swallowed interrupt names
FRAMES_NAMED = 4


@dataclass(frozen=True)
class Interruption:
    """A signal that asked the run to end, and where its KeyboardInterrupt was raised
    (``file:line (function)``, innermost last; empty when it was deferred and raised later)."""

    signum: int
    frames: tuple[str, ...]

    def describe(self) -> str:
        name = signal.Signals(self.signum).name
        where = " <- ".join(reversed(self.frames)) if self.frames else "a deferred handler"
        return f"{name} was swallowed after it was raised in {where}"


class _Latch:
    """The process's one record (signal handlers belong to the process's main thread)."""

    recorded: Interruption | None = None
    reported: bool = False


def interrupt(signum: int, frame: FrameType | None) -> None:
    """Signal handler: record the interruption, then raise KeyboardInterrupt (as Ctrl-C does)."""
    stack = traceback.extract_stack(frame)[-FRAMES_NAMED:] if frame is not None else []
    _Latch.recorded = Interruption(signum, tuple(f"{f.filename}:{f.lineno} ({f.name})"
                                                 for f in stack))
    raise KeyboardInterrupt(f"signal {signum}")


def latch_interrupts() -> None:
    """Make SIGTERM, and SIGINT unless it is ignored, end the run through :func:`interrupt`.

    A SIGINT that the process inherited as ignored (started in the background without job
    control) stays ignored, as a shell's Ctrl-C is not meant for it. Main thread only."""
    if threading.current_thread() is not threading.main_thread():
        return
    if signal.getsignal(signal.SIGINT) is not signal.SIG_IGN:
        signal.signal(signal.SIGINT, interrupt)
    signal.signal(signal.SIGTERM, interrupt)


def raise_if_interrupted() -> None:
    """Raise KeyboardInterrupt again if the run was interrupted and goes on: the first one was
    swallowed. The first time, one line on stderr names where it had been raised."""
    recorded = _Latch.recorded
    if recorded is None:
        return
    if not _Latch.reported:
        _Latch.reported = True
        print(f"rason: {recorded.describe()}; ending the run", file=sys.stderr, flush=True)
    raise KeyboardInterrupt(f"signal {recorded.signum} (raised again)")


def forget_interrupt() -> None:
    """The interruption was acted on (a ``--hold`` ended by Ctrl-C): later checks pass."""
    _Latch.recorded = None
    _Latch.reported = False


def interrupted() -> Interruption | None:
    """The interruption recorded and not forgotten, if any."""
    return _Latch.recorded
