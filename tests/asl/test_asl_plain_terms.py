"""The plain-term reader (messages and percepts without the grammar) reads exactly what the
grammar reads: the same term for every text it accepts, nothing the grammar rejects."""

from __future__ import annotations

import re

from draws import examples
from hypothesis import example, given, settings
from hypothesis import strategies as st

from rason.asl import ListTerm, Literal, Var, parse_term, parse_term_text, term_text
from rason.asl.parser import AslSyntaxError, parse_term_by_grammar, read_plain_term
from rason.asl.terms import merge_annots, term_str

names = st.from_regex(r"[a-z][A-Za-z0-9_]{0,5}", fullmatch=True)
numbers = st.floats(allow_nan=False, allow_infinity=False) | st.integers(-10**9, 10**9).map(float)
strings = st.text(st.characters(exclude_categories=("Cs",)), max_size=8)
variables = st.from_regex(r"[A-Z][A-Za-z0-9_]{0,4}", fullmatch=True).map(Var)


def _literal(args: st.SearchStrategy, annots: st.SearchStrategy) -> st.SearchStrategy:
    return st.builds(lambda f, a, n, neg: Literal(f, tuple(a), merge_annots((), n), None, neg),
                     names | st.sampled_from(["not", "div", "true", "X", "a b"]), args, annots,
                     st.booleans())


def _extend(children: st.SearchStrategy) -> st.SearchStrategy:
    return st.one_of(
        _literal(st.lists(children, max_size=3), st.lists(children, max_size=2)),
        st.builds(lambda items, tail: ListTerm(tuple(items), tail if items else None),
                  st.lists(children, max_size=3), st.none() | st.none() | variables))


terms = st.recursive(st.one_of(numbers, strings, variables, _literal(st.just([]), st.just([]))),
                     _extend, max_leaves=10)

# text as a person or a synthesizer may write it: spaces, operators, quotes, brackets, tails
ALPHABET = [*"ab_XY01.-~+*/()[]{},|\"'\\ :;!?&<=>\n", "not", "e5"]
fuzz_text = st.lists(st.sampled_from(ALPHABET), max_size=24).map("".join)


@st.composite
def edited_terms(draw: st.DrawFn) -> str:
    """A printed term with one character inserted, deleted or replaced."""
    text = term_text(draw(terms))
    at = draw(st.integers(0, len(text)))
    piece = draw(st.sampled_from(ALPHABET))
    edit = draw(st.sampled_from(["insert", "delete", "replace"]))
    if edit == "insert":
        return text[:at] + piece + text[at:]
    if edit == "delete":
        return text[:at] + text[at + 1:]
    return text[:at] + piece + text[at + 1:]


def _same(x: object, y: object) -> bool:
    """Equal terms, fresh variable names (``_`` reads as a new ``_N`` each time) aside."""
    fresh = re.compile(r"\b_\d+\b")
    return x == y or fresh.sub("_", term_str(x)) == fresh.sub("_", term_str(y))


@settings(max_examples=examples(500), deadline=None)
@given(terms)
def test_what_the_reader_accepts_of_printed_terms_equals_the_grammars_term(term) -> None:
    text = term_text(term)
    plain = read_plain_term(text)
    if plain is not None:
        assert plain == parse_term_by_grammar(text, exact=True) == term, text
    assert parse_term_text(text) == term, text


@settings(max_examples=examples(1500), deadline=None)
@given(fuzz_text | edited_terms())
@example("f(1 -2)")
@example("[a [b], -0, 1e5]")
@example("p(a)[b][c]")
@example("1.5.3")
@example("_")
def test_arbitrary_text_reads_as_the_grammar_reads_it(text: str) -> None:
    plain = read_plain_term(text)
    for exact in (False, True):
        try:
            expected = parse_term_by_grammar(text, exact=exact)
        except AslSyntaxError:
            assert plain is None, f"{text!r}: the grammar rejects it, the reader read {plain!r}"
            continue
        if plain is not None:
            assert _same(plain, expected), f"{text!r}: {plain!r} != {expected!r}"
        assert _same(parse_term(text, exact=exact), expected)


def test_messages_and_percepts_of_a_fleet_take_the_plain_reader() -> None:
    # the shapes that travel often: without the reader they cost a full grammar parse
    for text in ["ping(12,1795440318228595968)", "seen(dock, 1.5)", "battery(90)",
                 'robot(faulty,-3.5,1.2E-4,88)[source(camera)]', '[a,"b c",[1,2],~d(x)]',
                 "ask(X, position(R, Y))"]:
        assert read_plain_term(text) == parse_term_by_grammar(text), text
    for text in ["f(X)[|T]", "[a|T]", "'Quoted'", '"a\\"b"', "1+2", ".print(x)", "a::b", "f()"]:
        assert read_plain_term(text) is None, text
