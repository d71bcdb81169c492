"""Every term reads back from its exact text as an equal term (property test): ``term_text``
is how terms travel between processes; ``term_str`` stays Jason's display form."""

from __future__ import annotations

import math

from draws import examples
from hypothesis import given, settings
from hypothesis import strategies as st

from rason.asl import ListTerm, Literal, Var, parse_term, parse_term_text, term_str, term_text
from rason.asl.terms import merge_annots

# text of every kind: quotes, backslashes, newlines, non-ASCII (no lone surrogates: not UTF-8)
texts = st.text(st.characters(exclude_categories=("Cs",)), max_size=12)
plain_names = st.from_regex(r"[a-z][A-Za-z0-9_]{0,6}", fullmatch=True)
functors = st.one_of(
    plain_names,
    st.from_regex(r"[A-Z_][A-Za-z0-9_]{0,6}", fullmatch=True),   # uppercase: must be quoted
    st.sampled_from(["not", "div", "mod", "true", "false", ".print", "a.b"]),
    texts.filter(bool),
)
numbers = st.floats(allow_nan=False, allow_infinity=False) | st.integers(-10**6, 10**6).map(float)
variables = st.from_regex(r"[A-Z][A-Za-z0-9_]{0,5}", fullmatch=True).map(Var)


def _literal(draw_args: st.SearchStrategy, draw_annots: st.SearchStrategy) -> st.SearchStrategy:
    return st.builds(
        lambda f, args, annots, tail, neg: Literal(f, tuple(args), merge_annots((), annots), tail, neg),
        functors, draw_args, draw_annots, st.none() | variables, st.booleans())


def _extend(children: st.SearchStrategy) -> st.SearchStrategy:
    ground_annots = st.lists(_literal(st.lists(children, max_size=2), st.just([])).map(
        lambda lit: Literal(lit.functor, lit.args, (), None, lit.neg)), max_size=3)
    return st.one_of(
        _literal(st.lists(children, max_size=3), ground_annots),
        st.builds(lambda items, tail: ListTerm(tuple(items), tail if items else None),
                  st.lists(children, max_size=4), st.none() | variables),   # ([|T] is just T)
    )


terms = st.recursive(st.one_of(numbers, texts, variables, _literal(st.just([]), st.just([]))),
                     _extend, max_leaves=12)


@settings(max_examples=examples(400), deadline=None)
@given(terms)
def test_every_printed_term_parses_back_to_an_equal_term(term) -> None:
    text = term_text(term)
    assert parse_term_text(text) == term, text


@settings(max_examples=examples(200), deadline=None)
@given(numbers)
def test_numbers_round_trip_exactly(x: float) -> None:
    y = parse_term_text(term_text(x))
    assert term_text(x) == term_str(x)
    assert (y == x and math.copysign(1, y) == math.copysign(1, x)) or x == 0


def test_examples_of_text_that_needs_escaping_or_quoting() -> None:
    cases = {
        'say("he said \\"hi\\"")': Literal("say", ('he said "hi"',)),
        'p("back\\\\slash","line\\nbreak","été ☃")': Literal("p", ("back\\slash", "line\nbreak", "été ☃")),
        "reason('Robot lost','it\\'s','X'(1)[|T])": Literal("reason", (Literal("Robot lost"), Literal("it's"),
                                                           Literal("X", (1.0,), (), Var("T")))),
        "f(-3,[a,-1.5|T])[b,source(x)]": Literal("f", (-3.0, ListTerm((Literal("a"), -1.5), Var("T"))),
                                                  (Literal("b"), Literal("source", (Literal("x"),)))),
    }
    for text, term in cases.items():
        assert term_text(term) == text
        assert parse_term_text(text) == term


def test_jason_display_and_source_reading_are_unchanged() -> None:
    # Jason's toString does not escape, and its parser keeps an atom's quotes and a double
    # backslash: the display form and .asl sources behave as in Jason
    term = Literal("f", ('say "hi"', Literal("'Quoted'")))
    assert term_str(term) == "f(\"say \"hi\"\",'Quoted')"
    assert parse_term("f('Quoted', \"a\\\\b\")") == Literal("f", (Literal("'Quoted'"), "a\\\\b"))
