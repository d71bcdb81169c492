"""Fuzzing the parser: random and mutated programs raise only AslSyntaxError."""

from __future__ import annotations

import glob
import os

from asl_helpers import CONFORMANCE
from draws import examples
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from rason.asl import AslSyntaxError, parse_literal
from rason.asl.parser import parse_source


def _read(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        return f.read()


PROGRAMS = [_read(p) for p in sorted(glob.glob(os.path.join(CONFORMANCE, "*", "*.asl")))]
TOKENS = ["+", "-", "!", "!!", "?", "-+", "<-", ":-", ":", ".", ";", ",", "(", ")", "[", "]", "{", "}",
          "|", "&", "not", "if", "elif", "else", "while", "for", "@", "~", "=", "==", "\\==", "<", ">=",
          "**", "div", "mod", "X", "_", "a", "p(1)", ".print", "\"s\"", "'q'", "1.5e3", "\n", " ",
          "//c\n", "/*", "*/", "\\"]

FUZZ = settings(max_examples=examples(150), deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _check(text: str) -> None:
    try:
        parse_source(text, "fuzz.asl")
    except AslSyntaxError as e:
        assert str(e).startswith("fuzz.asl:")


@FUZZ
@given(st.lists(st.sampled_from(TOKENS), max_size=40))
def test_token_soup(tokens: list[str]) -> None:
    _check(" ".join(tokens))


@FUZZ
@given(st.text(max_size=120))
def test_random_text(text: str) -> None:
    _check(text)
    try:
        parse_literal(text)
    except AslSyntaxError:
        pass


@st.composite
def mutated(draw) -> str:
    src = draw(st.sampled_from(PROGRAMS))
    for _ in range(draw(st.integers(1, 4))):
        n = len(src)
        i = draw(st.integers(0, n))
        j = draw(st.integers(i, min(n, i + 12)))
        op = draw(st.sampled_from(["delete", "insert", "dup", "swap"]))
        if op == "delete":
            src = src[:i] + src[j:]
        elif op == "insert":
            src = src[:i] + draw(st.sampled_from(TOKENS)) + src[i:]
        elif op == "dup":
            src = src[:j] + src[i:j] + src[j:]
        else:
            k = draw(st.integers(0, n))
            src = src[:i] + src[k:k + 3] + src[j:]
    return src


@FUZZ
@given(mutated())
def test_mutated_conformance_programs(src: str) -> None:
    _check(src)


def test_deep_nesting_is_a_syntax_error_or_parses() -> None:
    _check("!g.\n+!g <- X = " + "(" * 3000 + "1" + ")" * 3000 + ".")
    _check("p(" + "[" * 5000 + ").")
