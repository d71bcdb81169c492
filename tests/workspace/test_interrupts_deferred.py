"""``interrupts_deferred`` (the harness's guard around a spawn): a Ctrl-C or SIGTERM that comes
during the block takes effect when it ends, and every handler it swapped is put back, also when
a signal comes in the middle of the swap. Real signals (``signal.raise_signal``), no ROS."""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable, Iterator
from typing import Any

import pytest

from rason.process.harness import interrupts_deferred


class Terminated(Exception):
    """What the SIGTERM handler of these tests raises (the demo's raises KeyboardInterrupt)."""


def terminate(_signum: int, _frame: object) -> None:
    raise Terminated


@pytest.fixture
def handlers() -> Iterator[None]:
    """SIGINT: Python's default (KeyboardInterrupt); SIGTERM: :func:`terminate`; both as they
    were afterwards."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be set from the main thread")
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, terminate)
    yield
    for sig, handler in before.items():
        signal.signal(sig, handler)


def signal_after(monkeypatch: pytest.MonkeyPatch, when: Callable[[int, Any], bool],
                 sig: signal.Signals) -> list[bool]:
    """Make ``sig`` come right after the first ``signal.signal(s, h)`` for which ``when(s, h)``
    holds: a signal that arrives while the handlers are being swapped. The list it returns gets
    an item once the signal came."""
    real = signal.signal
    sent: list[bool] = []

    def swap(signum: int, handler: Any) -> Any:
        old = real(signum, handler)
        if not sent and when(signum, handler):
            sent.append(True)
            signal.raise_signal(sig)
        return old
    monkeypatch.setattr(signal, "signal", swap)
    return sent


def test_a_ctrl_c_in_the_block_is_raised_once_the_block_is_done(handlers):
    done = []
    with pytest.raises(KeyboardInterrupt), interrupts_deferred():
        signal.raise_signal(signal.SIGINT)
        done.append("rest of the block")
    assert done == ["rest of the block"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert signal.getsignal(signal.SIGTERM) is terminate


def swapping_in(signum: int, handler: Any) -> bool:
    """The block's own SIGINT handler is being set."""
    return signum == signal.SIGINT and handler is not signal.default_int_handler


def swapping_back(signum: int, handler: Any) -> bool:
    """SIGINT's own handler is being put back."""
    return signum == signal.SIGINT and handler is signal.default_int_handler


# SIGTERM right after the block's SIGINT handler is set (its handler raises): before, the
# block's SIGINT handler stayed, and every later Ctrl-C was swallowed without a word. Ctrl-C
# right after SIGINT's handler is back (it raises at once): before, SIGTERM kept the block's
# handler, and every later SIGTERM was swallowed.
@pytest.mark.parametrize(("when", "sig", "raised", "later", "later_raised"), [
    (swapping_in, signal.SIGTERM, Terminated, signal.SIGINT, KeyboardInterrupt),
    (swapping_back, signal.SIGINT, KeyboardInterrupt, signal.SIGTERM, Terminated),
], ids=["sigterm-while-swapping-in", "ctrl-c-while-swapping-back"])
def test_a_signal_in_the_middle_of_the_swap_leaves_every_handler_back(
        handlers, monkeypatch, when, sig, raised, later, later_raised):
    sent = signal_after(monkeypatch, when, sig)
    with pytest.raises(raised), interrupts_deferred():
        pass
    monkeypatch.undo()
    assert sent
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    assert signal.getsignal(signal.SIGTERM) is terminate
    with pytest.raises(later_raised):
        signal.raise_signal(later)


def test_outside_the_main_thread_the_block_runs_as_it_is(handlers):
    seen: list[object] = []

    def block() -> None:
        with interrupts_deferred():
            seen.append(signal.getsignal(signal.SIGINT))
    thread = threading.Thread(target=block)
    thread.start()
    thread.join()
    assert seen == [signal.default_int_handler]
