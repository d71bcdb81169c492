"""Plan texts as Jason 3.3 prints them, and plan-body terms run as deeds.

Jason's parser turns the statements of a body into internal actions, and rason prints them so
wherever a plan shows (``.print`` of a plan term, ``.relevant_plans``, ``.plan_label``,
``.list_plans``, ``.intention``, askHow answers): ``if``/``elif``/``else`` as nested
``.if_then_else(C,Then,Else)``, ``for`` as ``.foreach``, ``while`` as ``.loop``, blocks without
braces, and the branches that ``|&|``/``|||`` make without braces (a ``.fork`` written with
``{...}`` keeps them). Terms that travel as text between nodes keep rason's own source text
(statements and operators), which rason reads back as the same term. A plan-body term ``{a; b}``
used as a deed runs its deeds in place. Expected lines are what a Jason 3.3 build printed for the
same programs (2026-11-27)."""

from __future__ import annotations

import re

from asl_helpers import lines, run_agents, run_source

from rason.asl import parse_term_text, term_str, term_text
from rason.asl.parser import parse_source

STATEMENTS = """\
!s.
@p1 +!g(X) <- if (X > 1) { .print(1); .print(2) } elif (X < 0) { .print(neg) } else { .print(3) };
    for (.member(Y, [1, 2])) { .print(Y) }; while (X < 3) { .print(w) };
    !a |&| !b; !c ||| !d; .fork(and, {!e}, {!f}).
@p2 +!h <- if (a) { } else { .print(x) }; if (b) { .print(y) } else { }; while (a) { }.
@p3 +!k <- {.print(a); .print(b)} |&| !c; !a |&| (!b ||| !c); (!b ||| !c) |&| !d.
+!s <- .relevant_plans({+!g(_)}, L); .print(L); .plan_label(P, p2); .print(P);
    .list_plans({+!k}); Q = {+!q <- if (a) {b} else {c}}; .print(Q); .term2string(Q, S); .print(S).
"""


def _fresh(text: str) -> str:
    """Fresh variable numbers made alike (rason counts them its own way)."""
    return re.sub(r"\b_\d+", "_N", re.sub(r"p__\d+", "p__N", text))


def test_statements_and_forks_print_as_jasons_internal_actions() -> None:
    url = 'url("file:main.asl")'
    assert [_fresh(ln) for ln in lines(run_source(STATEMENTS))] == [
        f"[{{ @p1[source(self),{url}] +!g(_N) <- .if_then_else((_N > 1),.print(1); .print(2),"
        ".if_then_else((_N < 0),.print(neg),.print(3))); .foreach(.member(_N,[1,2]),.print(_N)); "
        ".loop((_N < 3),.print(w)); .fork(and,!a,!b); .fork(or,!c,!d); .fork(and,{ !e },{ !f }) }]",
        # an empty then part prints empty, an empty else part not at all
        f"{{ @p2[source(self),{url}] +!h <- .if_then_else(a,,.print(x)); .if_then_else(b,.print(y)); "
        ".loop(a,) }",
        f"@p3[source(self),{url}] +!k <- .fork(and,.print(a); .print(b),!c); "
        ".fork(and,!a,.fork(or,!b,!c)); .fork(and,.fork(or,!b,!c),!d).",
        "{ +!q <- .if_then_else(a,b,c) }",
        "{ +!q <- .if_then_else(a,b,c) }",
    ]


def test_an_intentions_body_shows_the_statements_as_jason_does() -> None:
    # the then part runs in place of the if (Jason's .if_then_else puts it in the body)
    src = ("!s.\n+!s <- if (true) { .intention(_, _, [im(_, _, B, _)|_], current); .print(B) }; "
           "if (x) { .print(a) } else { .print(b) }; !a |&| !b.\n+!a <- true.\n+!b <- true.\n")
    [shown, _] = lines(run_source(src))
    assert _fresh(shown) == ("{ .intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); .print(_N); "
                             ".if_then_else(x,.print(a),.print(b)); .fork(and,!a,!b) }")


def test_an_askhow_answer_prints_as_jasons() -> None:
    out = run_agents({
        "ha": "+!g(X) <- if (X > 1) { .print(big) } else { .print(small) }; !a ||| !b.\n",
        "hb": "!s.\n+!s <- .send(ha, askHow, {+!g(_)}, L); .print(L).\n",
    })
    assert [_fresh(ln) for ln in lines(out, "hb")] == [
        '[{ @p__N[source(ha),url("file:ha.asl")] +!g(_N) <- '
        ".if_then_else((_N > 1),.print(big),.print(small)); .fork(or,!a,!b) }]"]


def test_the_text_sent_between_nodes_reads_back_as_the_same_plan() -> None:
    # Jason's printed form does not read back (".print(1); .print(2)" as an argument):
    # messages carry rason's source text, statements and fork operators as written
    for plan in parse_source(STATEMENTS, "main.asl").plans:
        term = plan.as_term()
        wire = term_text(term)
        back = parse_term_text(wire)
        assert back == term and term_str(back) == term_str(term) and term_text(back) == wire
    forks = parse_source(STATEMENTS, "main.asl").plans[2].as_term()
    assert "{ .print(a); .print(b) } |&| !c; !a |&| (!b ||| !c); (!b ||| !c) |&| !d" in term_text(forks)


def test_a_plan_body_term_as_a_deed_runs_its_deeds_in_place() -> None:
    src = ("!h.\n+!h <- {.print(x); .print(y)}; X = 1; {.print(X)}; {}; .print(end);\n"
           "    {.print(p)} |&| {.print(q); .print(r)}; .relevant_plans({+!h}, L); .print(L).\n")
    out = lines(run_source(src))
    assert out[:7] == ["x", "y", "1", "end", "p", "q", "r"]
    # as Jason's parser makes it: the deeds are part of the body, no block is left
    assert _fresh(out[7]) == (
        '[{ @p__N[source(self),url("file:main.asl")] +!h <- .print(x); .print(y); (_N = 1); '
        ".print(_N); .print(end); .fork(and,.print(p),.print(q); .print(r)); "
        ".relevant_plans({ +!h },_N); .print(_N) }]")
