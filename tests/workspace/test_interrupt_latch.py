"""``rason.process.interrupts``: a Ctrl-C or SIGTERM that code swallowed (``except
BaseException: pass`` around where it was raised) ends the run at the next check anyway, and
the check names where it had been raised. Real signals (``signal.raise_signal``), no ROS."""

from __future__ import annotations

import signal
import threading
from collections.abc import Iterator

import pytest

from rason.process.harness import interrupts_deferred
from rason.process.interrupts import (
    forget_interrupt,
    interrupt,
    interrupted,
    latch_interrupts,
    raise_if_interrupted,
)


@pytest.fixture
def latched() -> Iterator[None]:
    """The latch installed as a run's entry point installs it; handlers and record as they were
    afterwards."""
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be set from the main thread")
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    forget_interrupt()
    latch_interrupts()
    yield
    forget_interrupt()
    for sig, handler in before.items():
        signal.signal(sig, handler)


def swallowing_library(sig: signal.Signals) -> None:
    """Third-party code with a bare ``except`` around the moment the signal comes."""
    try:
        signal.raise_signal(sig)
    except BaseException:   # what the latch is there for
        pass


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_swallowed_interrupt_is_raised_again_naming_where(latched: None, sig: signal.Signals,
                                                           capsys: pytest.CaptureFixture[str]):
    swallowing_library(sig)
    with pytest.raises(KeyboardInterrupt):
        raise_if_interrupted()
    err = capsys.readouterr().err
    assert f"{sig.name} was swallowed" in err
    assert "test_interrupt_latch.py" in err and "(swallowing_library)" in err
    with pytest.raises(KeyboardInterrupt):    # every later check ends the run too, quietly
        raise_if_interrupted()
    assert capsys.readouterr().err == ""


def test_the_handler_raises_keyboard_interrupt_where_the_signal_comes(latched: None):
    assert signal.getsignal(signal.SIGINT) is interrupt
    assert signal.getsignal(signal.SIGTERM) is interrupt
    with pytest.raises(KeyboardInterrupt):
        signal.raise_signal(signal.SIGINT)
    record = interrupted()
    assert record is not None and record.signum == signal.SIGINT
    assert record.frames and "test_the_handler_raises" in record.frames[-1]


def test_no_check_raises_without_an_interrupt_or_after_it_was_forgotten(latched: None):
    raise_if_interrupted()                   # nothing happened: the run goes on
    swallowing_library(signal.SIGINT)
    forget_interrupt()                       # e.g. a --hold that Ctrl-C ended
    raise_if_interrupted()
    assert interrupted() is None


def test_an_interrupt_deferred_around_a_spawn_is_latched_too(latched: None,
                                                            capsys: pytest.CaptureFixture[str]):
    try:
        with interrupts_deferred():
            signal.raise_signal(signal.SIGINT)      # held back until the block ends
            assert interrupted() is None
    except KeyboardInterrupt:
        pass                                        # swallowed by whoever called the spawn
    with pytest.raises(KeyboardInterrupt):
        raise_if_interrupted()
    assert "SIGINT was swallowed after it was raised in a deferred handler" in capsys.readouterr().err


def test_a_sigint_inherited_as_ignored_stays_ignored():
    if threading.current_thread() is not threading.main_thread():
        pytest.skip("signal handlers can only be set from the main thread")
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        latch_interrupts()
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN
        assert signal.getsignal(signal.SIGTERM) is interrupt
    finally:
        for sig, handler in before.items():
            signal.signal(sig, handler)
