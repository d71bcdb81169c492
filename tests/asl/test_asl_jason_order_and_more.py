"""Jason 3.3 behaviours observed on a Jason 3.3 build: the standard order of terms, intention
management corner cases, the ``.set``/``.map``/``.queue`` families, ``.fork``/``.join``,
``.done``, ``.belief`` and the directory facilitator in one process."""

from __future__ import annotations

from asl_helpers import lines, run_source


def run(body: str, extra: str = "", timeout: float = 10.0) -> list[str]:
    """Run ``+!s <- body.`` (plus ``extra``) and return the printed lines."""
    return lines(run_source(f"!s.\n+!s <- {body}.\n{extra}", timeout=timeout))


# ------------------------------------------------------------------ standard order of terms
def test_structures_compare_argument_by_argument_before_arity() -> None:
    # f(a,a) comes before f(z): the first arguments decide; arity only breaks a prefix tie
    assert run(".sort([f(z), f(a,a), f(a), f], L); .print(L); "
               ".min([f(z), f(a,a)], Mi); .max([f(z), f(a,a)], Ma); .print(Mi, \" \", Ma); "
               "if (f(z) < f(a,a)) { .print(lt) } else { .print(ge) }") == [
        "[f,f(a),f(a,a),f(z)]", "f(a,a) f(z)", "ge"]


def test_order_of_kinds_numbers_strings_lists_literals_variables() -> None:
    assert run('.sort([g, X, [a], "s", 3, f(b), [], 1.5, ~f(a), f(a)[x], f(a)], L); .print(L)') == [
        '[1.5,3,"s",[],[a],f(a),f(a)[x],f(b),~f(a),g,X]']


def test_lists_compare_item_by_item_and_negation_after_functor() -> None:
    assert run(".sort([[b], [a,c], [a], [a,b,c]], L); .print(L); "
               ".sort([~a, a, ~b, b, ~a(1), a(1)], N); .print(N); "
               ".setof(Y, .member(Y, [g(b), f(z), g, f(a,a)]), S); .print(S)") == [
        "[[a],[a,b,c],[a,c],[b]]", "[a,a(1),~a,~a(1),b,~b]", "[f(a,a),f(z),g,g(b)]"]


# ------------------------------------------------------------------ intentions and failure
def test_intend_skips_intentions_held_by_suspend_but_desire_keeps_them() -> None:
    out = run("!!w1; !!w2; !!w3; .wait(100); .suspend(w2); .wait(50); "
              ".findall(G, .intend(G), I); .print(I); .findall(G, .desire(G), D); .print(D); "
              ".suspended(w2, R); .print(R); .resume(w2); .wait(20); "
              "if (.intend(w2)) { .print(back) }",
              "+!w1 <- .wait({+never}).\n+!w2 <- .wait(500).\n+!w3 <- .suspend.\n")
    assert out[0] == "[s[source(self)],w1[source(self)]]"
    assert out[1] == "[s[source(self)],w1[source(self)],w2[source(self)],w3[source(self)]]"
    # the reason names the waiting intention (its id) and what it waits for
    assert out[2].startswith("wait(") and out[2].endswith(")[time(500)]")
    assert out[3] == "back"


def test_drop_intention_of_its_own_intention_stops_it_without_failure() -> None:
    assert run("!g; .print(not_here)",
               "+!g <- .print(before); .drop_intention(g); .print(after).\n"
               "-!g <- .print(g_failed).\n-!s <- .print(s_failed).\n") == ["before"]


def test_subgoal_failing_inside_a_failure_plan_retries_that_failure_plan() -> None:
    # -!h's own subgoal fails with no plan for it: -!h is posted again (not -!g); when the
    # retry succeeds, +!h goes on after the deed that failed, then g after !h
    assert run("!g; .print(after_g)",
               "+!g <- !h; .print(after_h).\n-!g <- .print(g_failed).\n"
               "+!h <- .print(h_runs); .fail; .print(h_after_fail).\n"
               "-!h <- .print(h_failed); !k; .print(after_k).\n"
               "+!k : not tried <- +tried; .print(k_fails); .fail.\n+!k <- .print(k_ok).\n") == [
        "h_runs", "h_failed", "k_fails", "h_failed", "k_ok", "after_k", "h_after_fail",
        "after_h", "after_g"]


def test_failure_plan_that_fails_and_a_missing_plan_below_it() -> None:
    # -!h fails itself: the goal below h (g) handles it; then a goal with no plan inside -!g
    # posts -!g again, whose end lets -!h and then g go on
    assert run("!g; .print(after_g)",
               "+!g <- !h; .print(after_h).\n-!g[error(E)] <- .print(g_failed(E)); !z.\n"
               "+!z : not z <- +z; !nothing.\n+!z <- .print(z_ok).\n"
               "+!h <- .fail.\n-!h <- .print(h_failed); .fail.\n") == [
        "h_failed", "g_failed(ia_failed)", "g_failed(ia_failed)", "z_ok", "after_h", "after_g"]


def test_for_takes_each_solution_after_the_previous_pass() -> None:
    # the condition is evaluated lazily (a pass can change the next solutions); the beliefs
    # it iterates are those present when the loop started
    assert run("for (b(X)) { .print(X); -b(X+1) }; "
               "for (.member(X, [1,2,3]) & not d(X)) { .print(m(X)); +d(X+1) }; "
               ".findall(Y, d(Y), L); .print(L)", "b(1). b(2). b(3).\n") == [
        "1", "2", "3", "m(1)", "m(3)", "[4,2]"]
