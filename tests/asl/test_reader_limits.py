"""Every reader of terms refuses texts nested or sized past rason.asl.limits (#37 item 2).

Deep and wide texts of random shapes go to each reader: the plain-term reader, the grammar
(a term, a belief and a plan of a program), parse_term/parse_term_text (messages),
parse_percept (perceptions) and a program file. Each either reads a term within the limits or
raises AslSyntaxError naming the limit; none recurses out of the stack (a term 100,000 deep
once crashed an agent node with SIGSEGV). Run in a thread, as the nodes' readers are.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
from draws import examples
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rason.asl import AslSyntaxError, parse_term, parse_term_text
from rason.asl.agent import load_agent_source
from rason.asl.limits import MAX_SOURCE_CHARS, MAX_TERM_CHARS, MAX_TERM_DEPTH, deeper_than
from rason.asl.parser import parse_source, parse_term_by_grammar, read_plain_term
from rason.ros.perceptions import parse_percept

#: Shapes of one level of nesting (``%s``: the level below); plain and grammar-only ones.
LEVELS = ["f(%s)", "[%s]", "[a|%s]", "g(1, [b, %s])", "p[%s]", "(%s)", "-(%s)", "not (%s)",
          "1 + (%s)", "a & %s", "%s ** 2", "x(\"(\", %s)", "ns::f(%s)", "~h(%s)"]
#: Parentheses that only group: a level of the text, not of the term read from it.
GROUPING = "(%s)"
#: The levels that nest the term one deeper.
DEEPER = [shape for shape in LEVELS if shape != GROUPING]
LIMITS = settings(max_examples=examples(60), deadline=None,
                  suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def nested(shapes: list[str], leaf: str = "1") -> str:
    text = leaf
    for shape in shapes:
        text = shape % text
    return text


def in_thread(fn: Callable[[], Any]) -> Any:
    """``fn()`` in a new thread (a node's subscriber thread): its result or its exception."""
    out: list[Any] = []

    def run() -> None:
        try:
            out.append(("ok", fn()))
        except BaseException as err:       # reported to the test below
            out.append(("raised", err))
    thread = threading.Thread(target=run)
    thread.start()
    thread.join()
    return out[0]


def readers(text: str) -> dict[str, Callable[[], Any]]:
    return {
        "plain": lambda: read_plain_term(text),
        "grammar": lambda: parse_term_by_grammar(text),
        "parse_term": lambda: parse_term(text),
        "message": lambda: parse_term_text(text),
        "percept": lambda: parse_percept(f"seen({text})"),
        "belief": lambda: parse_source(f"b({text}).", "fuzz.asl"),
        "plan": lambda: parse_source(f"+!g <- X = {text}; .print(X).", "fuzz.asl"),
    }


def check_readers(text: str, deep: bool | None) -> None:
    """Each reader reads ``text`` within the limits or refuses it with AslSyntaxError;
    ``deep`` True: every one must refuse (the plain reader by leaving it to the grammar)."""
    for name, read in readers(text).items():
        kind, value = in_thread(read)
        if kind == "raised":
            assert isinstance(value, AslSyntaxError), (name, repr(value)[:300])
            continue
        assert not deep or (name == "plain" and value is None), (name, text[:80])
        terms = value.beliefs + [p.body[0].term for p in value.plans] \
            if name in ("belief", "plan") else [value]
        for term in terms:
            assert not deeper_than(term, MAX_TERM_DEPTH + 2), (name, text[:80])


@LIMITS
@given(st.lists(st.sampled_from(DEEPER), min_size=MAX_TERM_DEPTH + 5, max_size=3000),
       st.lists(st.booleans(), max_size=3000))
def test_deep_texts_are_refused_by_every_reader(shapes: list[str], grouped: list[bool]) -> None:
    # grouping parentheses among the levels make the text deeper, never the term
    levels = [level for shape, group in zip(shapes, grouped + [False] * len(shapes), strict=False)
              for level in ([shape, GROUPING] if group else [shape])]
    check_readers(nested(levels), deep=True)


@LIMITS
@given(st.lists(st.sampled_from(LEVELS), max_size=MAX_TERM_DEPTH + 40))
def test_texts_around_the_depth_limit_are_read_or_refused(shapes: list[str]) -> None:
    check_readers(nested(shapes), deep=None)


@LIMITS
@given(st.integers(1, 20_000), st.sampled_from(["f(%s)", "[%s]", "p(%s, q)"]),
       st.sampled_from(["1", "a", "\"s\"", "X", "g(1,2)"]))
def test_wide_texts_within_the_size_limit_are_read(width: int, shape: str, item: str) -> None:
    text = shape % ", ".join([item] * width)
    for name in ("plain", "parse_term", "message", "percept"):
        kind, value = in_thread(readers(text)[name])
        assert kind == "ok" and value is not None, (name, repr(value)[:300])


def test_the_deep_term_of_the_issue_is_refused_quickly_by_each_reader() -> None:
    text = "f(" * 100_000 + "1" + ")" * 100_000        # about 300 kB
    check_readers(text, deep=True)
    with pytest.raises(AslSyntaxError, match="nested deeper than 200 levels"):
        parse_term_text(text)


def test_texts_past_the_size_limits_are_refused(tmp_path: Path) -> None:
    long_term = "[" + ",".join(["1"] * (MAX_TERM_CHARS // 2)) + "]"
    for read in (parse_term, parse_term_text, lambda t: parse_percept(f"p({t})")):
        with pytest.raises(AslSyntaxError, match="longer than the limit of 1000000"):
            read(long_term)
    path = tmp_path / "huge.asl"
    path.write_text("b(1).\n" * (MAX_SOURCE_CHARS // 6 + 1))
    with pytest.raises(AslSyntaxError, match=r"huge\.asl:1:1: program of .* longer than the limit"):
        parse_source(load_agent_source(path), str(path))


def test_a_deep_program_file_is_refused_with_its_place(tmp_path: Path) -> None:
    path = tmp_path / "deep.asl"
    path.write_text("ok(1).\n+!g <- X = " + nested(["f(%s)"] * 5000) + ".\n")
    with pytest.raises(AslSyntaxError, match=r"deep.asl:2:\d+: term nested deeper than 200"):
        parse_source(load_agent_source(path), str(path))
