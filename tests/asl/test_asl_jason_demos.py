"""Jason 3.3 behaviours the programs shipped with Jason (demos, examples) rely on: the
four-item ``=..``, a forked group in parentheses, a plan's ``code_line``. Each expected
output is what a Jason 3.3 build prints for the same program."""

from __future__ import annotations

from asl_helpers import lines, run_source


def test_univ_gives_and_takes_the_namespace() -> None:
    src = ("!s.\n+!s <- g(1)[a] =.. L; .print(L); g(1)[a] =.. [F, A, B]; .print(F, A, B); "
           "ns2::k(3) =.. K; .print(K); ~k(3) =.. N; .print(N); G =.. N; .print(G); "
           "X =.. [default, h, [1, 2], [b]]; .print(X); Z =.. [foo, [a]]; .print(Z).\n")
    assert lines(run_source(src)) == [
        "[default,g,[1],[a]]", "g[1][a]", "[ns2,k,[3],[]]", "[default,~k,[3],[]]", "~k(3)",
        "h(1,2)[b]", "foo(a)"]


def test_univ_takes_plans_apart_and_builds_them() -> None:
    src = ("!s.\n+!s <- {@lb +!p : c & d <- .print(x); !g} =.. L; .print(L); "
           "{@lc +b} =.. M; .print(M); "
           "P =.. [lab, {+!q(X)}, {X > 1}, {.print(X)}]; .print(P); .add_plan(P); !q(2); "
           "P2 =.. [lab2, {+!r}, true, {.print(r)}]; .add_plan(P2); !r.\n")
    assert lines(run_source(src)) == [
        "[lb,+!p,(c & d),.print(x); !g]", "[lc,+b,true,]", "@lab +!q(X) : (X > 1) <- .print(X).",
        "2", "r"]


def test_a_fork_in_parentheses_is_a_body_formula() -> None:
    src = ("!s.\n+!s <- !a |&| (!b ||| !c); .print(done).\n+!a <- .print(a).\n"
           "+!b <- .print(b).\n+!c <- .print(c).\n")
    assert lines(run_source(src)) == ["a", "b", "c", "done"]


def test_code_line_of_a_plan_is_its_label_or_what_follows_its_trigger() -> None:
    show = ".intention(1, _, [im(L, _, _, _)|_]); .print(L)"
    src = (f"!a.\n+!a\n   : true\n   <- {show}; !b.\n@lb\n+!b\n   <- {show}; !c.\n"
           f"+!c\n   <-\n   {show}.\n")
    shown = lines(run_source(src))
    assert [s.split("[")[1].split(",")[0] for s in shown] == [
        "code_line(3)", "code_line(5)", "code_line(9)"]
    assert shown[1].startswith("lb[")
