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


LOOPS = """\
c(1). c(2).
n(0).
!w.
!f.
!e.
+!w <- X = 0;
    while (n(N) & N < 2) { .intention(_, _, [im(_, _, B, _)|_], current); .print(w, B); -+n(N + 1) }.
+!f <- for (c(Y)) { Z = Y * 2; .intention(_, _, [im(_, _, B, _)|_], current); .print(f, B) }.
+!e <- .foreach(c(Y), { .intention(_, _, [im(_, _, B, _)|_], current); .print(e, B) }); .print(done).
"""


def _hidden(text: str) -> str:
    """Fresh variables and Java's identity hash of an iterator made alike."""
    return re.sub(r"@[0-9a-f]+,", "@H,", _fresh(text))


def test_a_running_loop_shows_the_hidden_arguments_jason_gives_it() -> None:
    # a while's next round is Jason's .loop(C,B,{U}), a for's .foreach(C,B,Iterator,{U}): U
    # the unifier before the loop as Java prints it (names as written), the iterator the
    # Java object of the condition's solutions; the loop's variables renamed as the body's,
    # the block of .foreach called as an action in braces. The three intentions take turns as
    # on Jason: .foreach as an action puts its block in place in the step that calls it
    body_w = ("{ .intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); .print(w,_N); -+n((_N+1)); "
              ".loop((n(_N) & (_N < 2)),.intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); "
              ".print(w,_N); -+n((_N+1)),{X=0}) }")
    body_e = ("{ .intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); .print(e,_N); "
              ".foreach(c(_N),{ .intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); .print(e,_N) },"
              "jason.asSyntax.Literal$1@H,{}); .print(done) }")
    body_f = ("{ .intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); .print(f,_N); "
              ".foreach(c(_N),(_N = (_N*2)); .intention(_N,_N,[im(_N,_N,_N,_N)|_N],current); "
              ".print(f,_N),jason.asSyntax.Literal$1@H,{}) }")
    assert [_hidden(ln) for ln in lines(run_source(LOOPS))] == [
        "w" + body_w, "e" + body_e, "f" + body_f, "w" + body_w, "e" + body_e, "f" + body_f, "done"]


def test_the_hidden_unifier_and_iterator_print_as_javas() -> None:
    # HashMap.clone's order (a table sized for the entries copied); the iterator's class
    # follows the condition: a conjunction, a disjunction, one solution, an action's own
    src = ("!g.\n+!g <- K = 1; L = 1; Z = f(Q); A = 2; Bb = 3; Cc = 4; Dd = 5;\n"
           "    while (L < 2) { .intention(_, _, [im(_, _, B, _)|_], current); .print(B); L = 7 }.\n"
           "-!g <- !h.\n"
           "+!h <- for (.member(M, [a]) & true) { !show }; for (.member(M, [a]) | false) { !show };\n"
           "    for (not false) { !show }; for (.range(I, 1, 1)) { !show }.\n"
           "+!show <- .intention(_, _, [_, im(_, _, B, _)|_], current); .print(B).\n")
    shown = [_hidden(ln) for ln in lines(run_source(src))]
    assert shown[0].endswith(",{Bb=3, Cc=4, Dd=5, A=2, Z=f(Q), K=1, L=1}) }")
    assert [re.search(r"jason\.[A-Za-z.]+\$\d", ln).group(0) for ln in shown[1:]] == [
        "jason.asSyntax.LogExpr$1", "jason.asSyntax.LogExpr$2", "jason.asSyntax.LogExpr$3",
        "jason.stdlib.range$1"]


def test_the_statements_called_as_actions_run_in_the_step_that_calls_them() -> None:
    # as on Jason 3.3: each of .if_then_else, .foreach and .loop tests its condition and puts
    # its block in place in one step, so the other intention's prints interleave so
    src = ("c(1).\n!a.\n!b.\n"
           "+!a <- .if_then_else(true, {.print(a1)}); .foreach(c(X), {.print(a2)});\n"
           "    .loop(c(Y) & Y < 2, {.print(a3); -+c(2)}); .print(a4).\n"
           "+!b <- .print(b1); .print(b2); .print(b3); .print(b4); .print(b5); .print(b6); "
           ".print(b7); .print(b8).\n")
    assert lines(run_source(src)) == [
        "a1", "b1", "b2", "a2", "b3", "b4", "b5", "a3", "b6", "b7", "b8", "a4"]


def test_a_plan_terms_jason_text_is_made_once() -> None:
    # like its source text, the text Jason prints is kept on the term once made
    term = parse_source(STATEMENTS, "main.asl").plans[0].as_term()
    assert term.jason is None
    shown = term_str(term)
    assert term.jason is not None and term.jason in shown and term_str(term) == shown
