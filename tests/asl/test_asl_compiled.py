"""Plan compilation: a compiled body literal builds exactly the term ``resolve`` builds."""

from __future__ import annotations

import math

import pytest
from asl_helpers import lines, run_source

from rason.asl import parse_literal, parse_term, plans, term_str
from rason.asl.unify import compile_resolve, resolve

SHAPES = ["value(X+1)[source(self)]", "p(X, Y - 2.5, 3 * Z, a, \"s\")", "q(X * Y)", "r(2 + 3)",
          "~n(X)[a, b(1)]", "w(X)"]
BINDINGS = [{}, {"X": 1.0}, {"X": 4.0, "Y": -1.5, "Z": 2.0},
            {"X": "text", "Y": 1.0, "Z": 1.0},
            {"X": parse_term("f(Y)"), "Y": 7.0, "Z": math.inf},
            {"X": parse_term("V"), "V": 3.0, "Y": math.nan, "Z": 0.0},
            {"X": parse_term("[1, Y]"), "Y": parse_term("g(h)")}]


@pytest.mark.parametrize("text", SHAPES)
@pytest.mark.parametrize("binding", BINDINGS, ids=range(len(BINDINGS)))
def test_compiled_literal_equals_resolved_literal(text, binding):
    lit = parse_literal(text)
    built = compile_resolve(lit)
    assert built is not None
    expected, got = resolve(lit, binding), built.build(binding)
    assert term_str(got) == term_str(expected)
    assert got == expected or "nan" in term_str(expected).lower()


@pytest.mark.parametrize("text", ["p(X / 2)", "p(f(X))", "p([X])", "p(X)[source(A)]", "p(X)[a|T]",
                                  "math.abs(X)", "p(1, a)"])
def test_other_shapes_are_left_to_resolve(text):
    assert compile_resolve(parse_literal(text)) is None


PROGRAM = """
!go(0).
+!go(X) : X < 3 <- -+v(X * 2); +w(X + 1, "s"); !go(X + 1).
+!go(X) <- .findall([A, B], w(A, B), L); ?v(V); .print(V, " ", L).
"""


def test_a_program_prints_the_same_with_and_without_compiled_deeds(monkeypatch):
    compiled = lines(run_source(PROGRAM))
    monkeypatch.setattr(plans, "compile_resolve", lambda term: None)
    assert lines(run_source(PROGRAM)) == compiled == ['4 [[3,"s"],[2,"s"],[1,"s"]]']


BELIEFS = """
value(3). value(12). value("x"). pair(1, 2). pair(5, 5). pair(a, 7).
twice(X, Y) :- pair(X, Y) & X == Y.
"""
CONTEXTS = ["value(X) & X < 10", "value(X) & X >= 10", "value(X) & 4 > X", "pair(X, Y) & X < Y",
            "pair(X, X) & X > 1", "pair(1, Y) & Y <= 2", "pair(X, Y) & Y > Z", "twice(X, Y) & X > 0",
            "value(X) & X < N", "missing(X) & X < 1"]


@pytest.mark.parametrize("text", CONTEXTS)
@pytest.mark.parametrize("binding", [{}, {"X": 12.0}, {"N": 4.0}, {"X": 5.0, "Z": 1.0}],
                         ids=["free", "X=12", "N=4", "X=5,Z=1"])
def test_compiled_context_finds_the_first_solution(text, binding):
    from rason.asl import Agent, AgentArch, WallClock
    from rason.asl.logic import compile_context, first_solution

    ag = Agent("c", BELIEFS, AgentArch(WallClock()))
    context = parse_term(text)
    compiled = compile_context(context)
    assert compiled is not None
    expected = first_solution(ag, context, dict(binding))
    got = compiled.solve(ag, dict(binding))
    assert (got is None) == (expected is None)
    if got is not None:   # the same answer (fresh variable names of rules may differ)
        assert term_str(resolve(context, got)) == term_str(resolve(context, expected))


@pytest.mark.parametrize("text", ["value(X)", "X < 3", "value(X) & X == 3", "value(X)[source(self)] & X < 3",
                                  "value(f(X)) & X < 3", ".my_name(N) & N < 3", "value(X) & X + 1 < 3"])
def test_other_contexts_are_left_to_first_solution(text):
    from rason.asl.logic import compile_context
    assert compile_context(parse_term(text)) is None


@pytest.mark.parametrize(("held", "new"), [
    (["v(1)[source(self)]"], "v(2)[source(self)]"),                      # in place, number keys
    (["v(1)[source(self)]", "v(5)[source(self)]"], "v(2)[source(self)]"),
    (["v(1)[source(self)]"], "v(1)[source(self)]"),                      # the same arguments
    (["v(1)[source(self)]", "v(2)[source(self)]"], "v(2)[source(self)]"),  # held by the second
    (["v(1)[source(self)]", "v(1, 2)[source(self)]"], "v(3)[source(self)]"),
    (["v(1)[source(ag)]", "v(4)[source(self)]"], "v(2)[source(self)]"),  # not the first entry
    (["v(1)[source(ag),source(self)]"], "v(2)[source(self)]"),           # keeps source(ag)
    (["v(a)[source(self)]"], "v(b)[source(self)]"),                      # atoms
    (["v(f(1))[source(self)]"], "v(2)[source(self)]"),                   # a structure: unindexed
    (["v(1, x)[source(self)]", "v(1, y)[source(self)]"], "v(1, z)[source(self)]"),  # one bucket
    ([], "v(2)[source(self)]"),
])
def test_replace_in_place_leaves_the_belief_base_as_remove_then_add(held, new):
    """-+b's one-call update of the belief base gives what removing then adding gives: the
    same events' literals, the same beliefs in the same order, the same first-argument index."""
    from rason.asl.beliefs import BeliefBase

    def base() -> BeliefBase:
        bb = BeliefBase()
        for text in reversed(held):
            bb.add(parse_literal(text), front=True)
        return bb

    lit = parse_literal(new)
    fast, slow = base(), base()
    got = fast.replace_first_holding(lit)
    want = (slow.remove_first_holding(lit), slow.add(lit, front=True))
    assert [term_str(x) if x is not None else None for x in got] == \
        [term_str(x) if x is not None else None for x in want]
    assert [term_str(b) for b in fast] == [term_str(b) for b in slow]
    probes = [parse_literal(t) for t in ("v(1)", "v(2)", "v(5)", "v(a)", "v(b)", "v(1, z)")]
    probes += [parse_term("1"), parse_term("2")]
    for key in {(b.functor, len(b.args), b.neg) for b in slow} | {("v", 1, False), ("v", 2, False)}:
        for first in probes:
            assert [term_str(b) for b in fast.candidates_by_first(key, first)] == \
                [term_str(b) for b in slow.candidates_by_first(key, first)]
