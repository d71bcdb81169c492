"""Goal conditions (Jason 3's ``+!g : context <: condition <- body``): the goal is achieved
once the condition holds, whether the body is done or not; a body done first waits for it.
Expected outputs are what a Jason 3.3 build prints for the same programs."""

from __future__ import annotations

import re

import pytest
from asl_helpers import lines, run_agents, run_source

from rason.asl.parser import AslSyntaxError, parse_source


def test_a_goal_ends_when_its_condition_holds_done_or_not() -> None:
    src = ("!top1.\n!top2.\n!top3.\n"
           "+!top1 <- !g1(5); .print(after_g1).\n"
           "+!g1(X) <: done(X) <- .print(start1); .wait(100); +done(X); .print(after_add); "
           ".wait(100); .print(not_reached).\n"
           "+!top2 <- !g2; .print(after_g2).\n"
           "+!g2 : true <: done2 <- .print(start2); !!trig.\n"
           "+!trig <- .wait(300); .print(adding_done2); +done2.\n"
           "+!top3 <- !g3; .print(after_g3).\n"
           "+!g3 <: false <- .print(start3); .wait(50); .print(end3).\n")
    # g1: its own +done(5) satisfies it (the rest of its body never runs); g2: its body ends
    # first and it waits for done2; g3 (<: false) never ends
    assert lines(run_source(src, timeout=3.0)) == [
        "start1", "start2", "start3", "end3", "after_g1", "adding_done2", "after_g2"]


def test_a_goal_waiting_for_its_condition_is_suspended_with_that_reason() -> None:
    src = ("!top.\n+!top <- !!g(1); .wait(50); .suspended(g(X), R); .print(X, \" \", R); "
           "+done(1); .wait(50); .print(end).\n"
           "+!g(X) <: done(X) <- .print(g, X).\n"
           "+done(_) <- .print(no_intention_left, \" \", 0).\n")
    out = lines(run_source(src, timeout=3.0))
    assert out[:2] == ["g1", "1 wait_goal_condition"] and out[-1] == "end"


def test_a_goal_condition_prints_with_its_plan_but_not_in_plan_terms() -> None:
    # as Jason 3.3: .list_plans shows it; the plan terms of .relevant_plans leave it out
    src = ("!s.\n+!s <- .list_plans({+!g(_)}); .relevant_plans({+!g(_)}, [P|_]); .print(P).\n"
           "@gp +!g(X) : ok <: done(X) <- .print(X).\n")
    out = lines(run_source(src))
    assert out[0] == '@gp[source(self),url("file:main.asl")] +!g(X) : ok <: done(X) <- .print(X).'
    assert "<:" not in out[1] and out[1].startswith('{ @gp[source(self),url("file:main.asl")] +!g(')


def test_a_plan_for_a_belief_event_may_have_a_goal_condition_too() -> None:
    # as Jason's parser (its contract-net-protocol-er example has one on +cfp); how such a plan
    # waits: tests/asl/test_asl_jason_sub_plans.py
    plan = parse_source("+b[source(A)] : ok <: c(A) <- .print(x).\n").plans[0]
    assert str(plan) == "+b[source(A)] : ok <: c(A) <- .print(x)."


def test_a_body_that_ends_before_its_condition_waits_in_a_compiled_agent_too() -> None:
    # the body's last deed runs, then the intention waits; compiled code once read the
    # intention's state as it was before that deed (an internal error instead of the wait)
    src = ("!k.\n+!k <- !g; .print(after).\n+!g <: done <- .print(started); !!d.\n"
           "+!d <- .wait(50); +done.\n")
    assert lines(run_source(src, timeout=3.0)) == ["started", "after"]


def test_a_plan_given_as_text_keeps_its_goal_condition_which_a_plan_term_cannot_hold() -> None:
    # as Jason 3.3: .add_plan and tellHow of a plan as text keep `<:` (it acts, it is not
    # printed in plan terms); inside `{ ... }` it is a syntax error (Jason's parser has no
    # goal condition in a plan term)
    src = ("!s.\n+!s <- .add_plan(\"+!k <: done_k <- .print(k).\"); !!w; .wait(100); "
           ".print(adding); +done_k; .wait(100); .relevant_plans({+!k}, L); .print(L).\n"
           "+!w <- !k; .print(after_k).\n")
    out = lines(run_source(src, timeout=3.0))
    assert out[:3] == ["k", "adding", "after_k"]
    assert re.fullmatch(r"\[\{ @p__\d+\[source\(self\)\] \+!k <- \.print\(k\) \}\]", out[3])
    told = lines(run_agents({
        "a": '!s.\n+!s <- .send(b, tellHow, "@q +!n <: false <- .print(n).");\n'
             "  .send(b, achieve, go).\n",
        "b": "+!go <- .wait(100); !!n; .wait(100); .suspended(n, R); .print(R);\n"
             "  .relevant_plans({+!n}, L); .print(L).\n"}, timeout=3.0), "b")
    assert told == ["n", "wait_goal_condition", "[{ @q[source(a)] +!n <- .print(n) }]"]
    with pytest.raises(AslSyntaxError):
        parse_source("+!s <- P = { +!g <: c <- b }.\n")
