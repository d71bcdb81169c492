"""The agent's perception table (thesis 5.2), without ROS."""

from __future__ import annotations

import pytest

from rason.asl import Literal
from rason.ros.perceptions import PerceptionFilter, PerceptionTable, parse_percept
from rosnode_kit import badinput
from rosnode_kit.badinput import BadInputLog, GlobalLimit


@pytest.fixture(autouse=True)
def no_process_limit(monkeypatch: pytest.MonkeyPatch) -> None:
    """These tests count per-group warnings on a fake clock: the process-wide limit (real time,
    tests/faults/test_log_flood.py) is lifted for them."""
    monkeypatch.setattr(badinput, "PROCESS_LIMIT", GlobalLimit(rate=1e9, burst=10**9))


def parse(text: str) -> str:
    """A strict stand-in parser for literals: name(args) with balanced parentheses."""
    text = text.strip()
    if not text or not text[0].islower() or text.count("(") != text.count(")"):
        raise ValueError(f"bad literal {text!r}")
    return text


def test_each_source_replaces_only_its_own_list():
    table = PerceptionTable(parse)
    table.update("cam_robot", ["robot(faulty,1,2,3)"])
    table.update("sonar_range", ["range(1)"])
    assert sorted(table.percepts()) == ["range(1)", "robot(faulty,1,2,3)"]
    table.update("cam_robot", [])
    assert table.percepts() == ["range(1)"]


def test_unchanged_table_reports_none():
    table = PerceptionTable(parse)
    table.update("a", ["p"])
    assert table.percepts() == ["p"]
    assert table.percepts() is None


def test_replace_mode_parses_only_the_newest_message_per_source():
    table = PerceptionTable(parse)
    for i in range(50):
        table.update("a", [f"p({i})"])
    assert table.percepts() == ["p(49)"]
    assert table.stats.parsed == 1


def test_queue_mode_parses_every_message():
    table = PerceptionTable(parse, mode="queue")
    for i in range(50):
        table.update("a", [f"p({i})"])
    assert table.percepts() == ["p(49)"]
    assert table.stats.parsed == 50


def test_malformed_perception_is_dropped_and_warned_once_the_rest_counts():
    warnings: list[str] = []
    table = PerceptionTable(parse, warn=warnings.append)
    for i in range(3):      # the malformed text again and again, with other news each time
        table.update("cam", ["robot(faulty,1", f"ok({i})"])
        assert table.percepts() == [f"ok({i})"]
    assert len(warnings) == 1
    assert "cam" in warnings[0] and "robot(faulty,1" in warnings[0]
    table.update("other", ["robot(faulty,1"])
    table.percepts()
    assert len(warnings) == 2


def test_duplicate_percepts_from_two_sources_appear_once():
    table = PerceptionTable(parse)
    table.update("a", ["p(1)", "q"])
    table.update("b", ["p(1)"])
    assert sorted(table.percepts()) == ["p(1)", "q"]


def test_filter_by_functor_arity_and_source():
    wanted = PerceptionFilter.from_lists(["robot/4", "battery"], ["cam_robot", "power"])
    table = PerceptionTable(parse, filter=wanted)
    assert not table.update("laser", ["robot(a,1,2,3)"])
    table.update("cam_robot", ["robot(a,1,2,3)", "robot(a,1)", "noise(7)"])
    table.update("power", ["battery(80)", "battery"])
    assert sorted(table.percepts()) == ["battery", "battery(80)", "robot(a,1,2,3)"]
    assert table.stats.filtered_messages == 1
    assert table.stats.filtered_literals == 2


def test_unknown_mode_is_an_error():
    with pytest.raises(ValueError, match="perception mode"):
        PerceptionTable(parse, mode="sometimes")


def test_a_source_silent_past_its_ttl_is_cleared_and_comes_back_when_heard():
    table = PerceptionTable(parse, ttl=lambda source: 0.5 if source == "cam" else 0.0)
    table.update("cam", ["robot(faulty,1,2,3)"], now=10.0)
    table.update("map", ["door(open)"], now=10.0)
    assert sorted(table.percepts()) == ["door(open)", "robot(faulty,1,2,3)"]
    assert table.expire(10.4) == []
    table.update("cam", ["robot(faulty,1,2,3)"], now=10.4)
    assert table.expire(10.8) == []                  # heard 0.4 s ago
    assert table.expire(11.0) == ["cam"]
    assert table.percepts() == ["door(open)"]          # a change: the agent gets - events
    assert table.expire(100.0) == []                 # map has no TTL; cam is already gone
    table.update("cam", ["robot(faulty,4,5,6)"], now=100.0)
    assert sorted(table.percepts()) == ["door(open)", "robot(faulty,4,5,6)"]


def test_a_clock_that_jumps_back_restarts_the_silence_and_queue_mode_expires_too():
    table = PerceptionTable(parse, mode="queue", ttl=lambda _source: 1.0)
    table.update("cam", ["p(1)"], now=50.0)
    assert table.expire(2.0) == []                   # simulation restarted: time went back
    assert table.expire(2.9) == []
    table.update("cam", ["p(2)"], now=2.9)
    assert table.expire(4.0) == ["cam"]              # the queued p(2) goes with its source
    assert table.percepts() == []


def test_a_ttl_that_is_not_a_number_is_warned_about_and_means_never():
    warnings: list[str] = []
    table = PerceptionTable(parse, warn=warnings.append, ttl=lambda _source: "soon")
    table.update("cam", ["p"], now=1.0)
    assert table.expire(1e9) == []
    assert warnings and "time to live" in warnings[0]


@pytest.mark.parametrize("text", ["robot(r, NaN, 1)", "robot(r, Infinity)", "robot(r, -Infinity)",
                                  "robot(r, 1e999)", "robot(r, [1, NaN])", "robot(r)[at(NaN)]"])
def test_nan_and_infinity_are_rejected_never_variables(text):
    warnings: list[str] = []
    table = PerceptionTable(parse_percept, warn=warnings.append)
    table.update("cam", [text, "ok(1)"])
    assert table.percepts() == [Literal("ok", (1.0,))]
    assert len(warnings) == 1 and "not a finite number" in warnings[0]


def test_a_flood_of_distinct_malformed_strings_is_logged_rarely_briefly_with_bounded_memory():
    warnings: list[str] = []
    clock = [0.0]
    table = PerceptionTable(parse_percept, warn=warnings.append, now=lambda: clock[0])
    for k in range(5000):
        clock[0] = k * 0.02                       # 50 Hz for 100 s
        table.update("cam", [f"robot(r, {k}, " + "x" * 3000, "ok(1)"])
        assert table.percepts() is not None
    assert 90 <= len(warnings) <= 101             # about one a second
    assert all(len(w) < 600 for w in warnings)    # shortened, not 3 KB each
    assert "held back" in warnings[-1]
    assert len(table.bad_input._seen) <= table.bad_input.remember
    assert len(table._cache) <= 4097


def test_bad_input_log_warns_once_per_input_and_once_per_period_per_group():
    logged: list[str] = []
    clock = [0.0]
    log = BadInputLog(logged.append, lambda: clock[0], period=1.0, remember=3)
    assert log.warn("a", "x", "x bad")
    assert not log.warn("a", "x", "x bad")       # same input: never again while remembered
    assert not log.warn("a", "y", "y bad")       # same group within the period
    assert log.warn("b", "y", "y bad")           # another group
    clock[0] = 1.5
    assert log.warn("a", "z", "z bad")
    assert logged == ["x bad", "y bad", "z bad (1 similar warnings held back)"]
    for k in range(10):
        log.warn("c", str(k), "w")
    assert len(log._seen) == 3 and len(log._groups) <= 3


def test_a_repeated_list_is_nothing_new_for_the_agent():
    table = PerceptionTable(parse=parse_percept, ttl=lambda _source: 1.0)
    assert table.update("cam", ["p(1)", "q"], now=0.0)
    assert table.percepts() is not None
    assert not table.update("cam", ["p(1)", "q"], now=0.5)     # the same list again
    assert not table.changed() and table.percepts() is None
    assert table.expire(1.2) == []                             # still heard: the TTL restarted
    assert table.update("cam", ["q", "p(1)"], now=0.6)         # another list
    assert [str(p) for p in table.percepts()] == ["q", "p(1)"]
    assert table.expire(2.0) == ["cam"] and table.percepts() == []
    assert table.update("cam", ["q", "p(1)"], now=2.1)         # back after its expiry: new
    assert [str(p) for p in table.percepts()] == ["q", "p(1)"]
