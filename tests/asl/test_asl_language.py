"""Terms, printing, unification and the parser of rason.asl."""

from __future__ import annotations

import pytest
from asl_helpers import lines, run_source

from rason.asl import AslSyntaxError, Literal, format_number, parse_literal, parse_term, term_str
from rason.asl.parser import parse_source
from rason.asl.unify import resolve, term_equals, unify


# ------------------------------------------------------------------ number printing
@pytest.mark.parametrize("value,text", [
    (3.0, "3"), (2.5, "2.5"), (1e18, "1000000000000000000"), (1e19, "1.0E19"),
    (1e-4, "1.0E-4"), (12345678.9, "1.23456789E7"), (0.1 + 0.2, "0.30000000000000004"),
    (9007199254740993.0, "9007199254740992"), (float("inf"), "Infinity"),
    (float("-inf"), "-Infinity"), (float("nan"), "NaN"), (-7.0, "-7"), (0.001, "0.001"),
    (-2.5e-7, "-2.5E-7"), (1e20, "1.0E20"), (-1.5e-5, "-1.5E-5"), (0.000999, "9.99E-4"),
    (1.7976931348623157e308, "1.7976931348623157E308"), (10000000.000000002, "1.0000000000000002E7"),
])
def test_number_printing(value: float, text: str) -> None:
    assert format_number(value) == text


@pytest.mark.parametrize("src,text", [
    ('f("\\"q\\"")', 'f(""q"")'),
    ("p[z,a,m]", "p[a,m,z]"),
    ("f(1+2)", "f(3)"),
    ("[1+1]", "[2]"),
    ("f(X+1)", "f((X+1))"),
    ("'Quoted Atom'", "'Quoted Atom'"),
    ("~p(1)[a]", "~p(1)[a]"),
    ("[a,b|T]", "[a,b|T]"),
    ("not a | b", "(not (a) | b)"),
    ("a & b", "(a & b)"),
    ("{ p(1) }", "{ p(1) }"),
    ("-7 div 2", "-3"),
    ("-7 mod 2", "-1"),
    ("7.5 div 2", "3"),
    ("2**3**2", "512"),
    ("-2**2", "4"),
    ("1/0", "Infinity"),
    ('"a\\tb"', '"a\\tb"'),
])
def test_term_printing(src: str, text: str) -> None:
    assert term_str(resolve(parse_term(src), {})) == text


def test_print_concatenates_and_strips_quotes() -> None:
    out = run_source('!s.\n+!s <- .print("a", 1, " ", f("x"), [1.5]); .print; .print("two\\nlines").')
    assert lines(out) == ['a1 f("x")[1.5]', "", "two"]
    assert "lines" in out.splitlines()


# ------------------------------------------------------------------ unification
def u(a: str, b: str) -> dict | None:
    s: dict = {}
    return s if unify(parse_term(a), parse_term(b), s) else None


def test_unify_basic() -> None:
    s = u("f(X, b)", "f(a, Y)")
    assert s is not None and term_str(resolve(parse_term("g(X,Y)"), s)) == "g(a,b)"
    assert u("g(C, C)", "g(1, 2)") is None
    assert u("h(1)", "h(1.0)") is not None
    assert u("p(a)", 'p("a")') is None
    s = u("[H|T]", "[1,2,3]")
    assert term_str(resolve(parse_term("T"), s)) == "[2,3]"
    assert u("[_, _]", "[1, 2, 3]") is None


def test_unify_annotations_subset() -> None:
    assert u("p(1)[a]", "p(1)[a,b]") is not None
    assert u("p(1)[a,b]", "p(1)[a]") is None
    assert u("p(1)", "p(1)[z]") is not None
    s = u("p[A|R]", "p[c,b,a]")
    assert term_str(resolve(parse_term("f(A,R)"), s)) == "f(a,[b,c])"
    s = u("note[k(1),k(2)]", "note[F|O]")
    assert term_str(resolve(parse_term("f(F,O)"), s)) == "f(k(1),[k(2)])"


def test_equality_ignores_annotation_order() -> None:
    assert term_equals(parse_term("p[a,b]"), parse_term("p[b,a]"), {})
    assert not term_equals(parse_term("p[z]"), parse_term("p"), {})
    assert not term_equals(parse_term("f(X)"), parse_term("f(Y)"), {})


# ------------------------------------------------------------------ parser
def test_parse_literal_for_bridge() -> None:
    lit = parse_literal("robot(faulty,-3.5,1.2,88)")
    assert isinstance(lit, Literal) and lit.functor == "robot"
    assert lit.args[1] == -3.5 and term_str(lit) == "robot(faulty,-3.5,1.2,88)"
    assert parse_literal("p[source(x)]").annots[0].functor == "source"


@pytest.mark.parametrize("text", ["robot(", "", "X", "1", "p(1) q", '"s"', "p(1)."])
def test_parse_literal_errors(text: str) -> None:
    with pytest.raises(AslSyntaxError):
        parse_literal(text)


def test_syntax_error_position() -> None:
    src = "// header\n!start.\n\n+!start <- .print(\"a\"); ;\n"
    with pytest.raises(AslSyntaxError) as ei:
        parse_source(src, "agent.asl")
    e = ei.value
    assert (e.file, e.line) == ("agent.asl", 4)
    assert e.col == 25
    assert str(e).startswith("agent.asl:4:25: ")


def test_syntax_error_at_eof() -> None:
    with pytest.raises(AslSyntaxError) as ei:
        parse_source("+!g <- .print(1)", "x.asl")
    assert str(ei.value).startswith("x.asl:1:")


def test_parse_program_structure() -> None:
    src = parse_source("""
        b(1). r(X) :- b(X) & X > 0.
        !g.
        @lab[atomic] +!g : r(Y) <- if (Y > 0) { .print(Y) } elif (Y < 0) { .print(n) } else { .print(z) };
                                  while (false) { .print(w) } for (.member(M, [1])) { .print(M) }.
        -!g[error(E)|R] <- -+b(2); !!h; ?b(Z); +c; -c.
        +?q(X) <- X = 1.
    """)
    assert len(src.beliefs) == 2 and len(src.goals) == 1 and len(src.plans) == 3
    p = src.plans[0]
    assert p.atomic and p.label_name() == "lab"
    assert [d.kind for d in p.body] == ["if", "while", "for"]
    assert [d.kind for d in src.plans[1].body] == ["delAddBel", "achieveNF", "test", "addBel", "delBel"]
    assert p.body[0].line == 4
