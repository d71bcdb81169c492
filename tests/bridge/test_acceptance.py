"""The allow-list of internal actions a remote message may cause (rason.ros.acceptance),
without ROS: which contents call code, and which are let through."""

from __future__ import annotations

from rason.asl import parse_term_text
from rason.asl.terms import Literal
from rason.ros.acceptance import PLAN_TERM, RemoteActions, code_in


def calls(text: str) -> list[str]:
    return sorted(code_in(parse_term_text(text)))


def test_internal_actions_are_found_anywhere_in_a_term():
    assert calls("p(1, [a, \"x.y\"], q(Z))[source(bob)]") == []
    assert calls(".stopMAS") == [".stopMAS"]
    assert calls(".add_plan({+pwn <- .print(x)})") == [".add_plan", PLAN_TERM]
    assert calls("not .stopMAS") == [".stopMAS"]
    assert calls("p & (q | .my_name(N))") == [".my_name"]
    assert calls("{p(X) :- .list_files(\".\", F)}") == [PLAN_TERM]     # a rule: code
    assert calls("f([1, g(h(.count(p, N)))])") == [".count"]
    assert calls("X > math.abs(-1)") == ["math.abs"]
    assert calls("ns::p(.stopMAS)") == [".stopMAS"]
    assert calls("N::p(.stopMAS)") == [".stopMAS"]


def test_a_deep_term_is_walked_without_recursion():
    depth = 50_000
    term = parse_term_text("[" * 10 + "x" + "]" * 10)
    for _ in range(depth):                  # built here: the readers refuse such depths
        term = Literal("f", (term,))
    assert list(code_in(Literal(".stopMAS", (term,)))) == [".stopMAS"]


def test_nothing_is_allowed_by_default_and_the_list_is_explicit():
    none = RemoteActions()
    some = RemoteActions.of([" .my_name ", "", ".count"])
    assert none.refusal("askOne", parse_term_text("secret(X)")) is None
    assert "calls .my_name (not in ~remote_internal_actions)" in (
        none.refusal("askOne", parse_term_text(".my_name(N)")) or "")
    assert some.refusal("askOne", parse_term_text(".my_name(N)")) is None
    assert some.refusal("askAll", parse_term_text(".count(p, N) & .stopMAS")) is not None
    assert some.refusal("tell", parse_term_text("{+!g <- .print(x)}")) == \
        "its content holds a plan term"
    # plans and triggers are installed or looked up, never run: the trust policy decides
    for performative in ("tellHow", "untellHow", "askHow"):
        assert none.refusal(performative, parse_term_text("{+!g <- .stopMAS}")) is None
