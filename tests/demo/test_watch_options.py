"""The demo's and the mission's watch options (pure logic, no ROS): one home for
``--inspector/--no-inspector``, ``--inspector-port`` and ``--hold``, the result block printed
once, and the wall time taken before a hold kept."""

from __future__ import annotations

import argparse

import pytest

from rason.inspector.main import InspectorParams
from rason_diagnosis.scenario import WallClock, Watch, add_watch_options


def _parse(*argv: str, what: str = "run") -> argparse.Namespace:
    parser = argparse.ArgumentParser()
    add_watch_options(parser, what)
    return parser.parse_args(argv)


@pytest.mark.parametrize("what", ["run", "mission"])
def test_the_help_names_what_is_watched(what):
    parser = argparse.ArgumentParser()
    add_watch_options(parser, what)
    text = " ".join(parser.format_help().split())
    assert f"watch the {what} in the mind inspector" in text
    assert f"the inspector still serves the {what}'s history" in text


@pytest.mark.parametrize(("argv", "port"), [
    ((), InspectorParams().port),
    (("--inspector-port", "0"), 0),
    (("--no-inspector", "--inspector-port", "0"), None),
])
def test_the_port_is_none_without_an_inspector(argv, port):
    assert Watch.of(_parse(*argv), print, "demo").port == port


def test_without_hold_the_run_gets_no_hold_and_the_block_is_printed_once():
    shown: list[str] = []
    watch = Watch.of(_parse(), shown.append, "demo")
    assert watch.hold_callback() is None
    watch.print_once("result")
    watch.print_once("result")
    assert shown == ["result"]


def test_with_hold_the_run_gets_the_print_then_hold_callback():
    shown: list[str] = []
    watch = Watch.of(_parse("--hold"), shown.append, "mission")
    assert watch.hold_callback() == watch.print_then_hold
    watch.print_once("before the hold")
    watch.print_once("at the end")          # what main does after the run: nothing again
    assert shown == ["before the hold"]


def test_the_wall_clock_keeps_its_first_reading():
    clock = WallClock(started=0.0)
    first = clock.stop()
    assert first > 0 and clock.stop() == first
