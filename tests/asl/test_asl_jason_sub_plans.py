"""Sub-plans (Jason 3.3, from Jason(ER)): ``+!g <- body. { inner plans }``. The inner plans
are chosen only for the events of an intention whose top means runs their parent plan or one of
them, before the plans around them, and they see the parent plan's variables as they were when
it was chosen. Expected outputs are what a Jason 3.3 build prints for the same programs."""

from __future__ import annotations

import pickle
import re

import pytest
from asl_helpers import lines, run_source

from rason.asl.parser import AslSyntaxError, parse_source
from rason.asl.plans import PlanLibrary

NESTED = """\
!g(1).
!g(5).
+!g(N) : N > 2 & M = N * 2 <- !a(X); .print(N, " got ", X); !b; !c.
    {
    +!a(Y) <- Y = M + 1.
    +!b <- .print("b sees ", N, " ", M); !inner(N).
    +!inner(K) <- !deep.
        {
        +!deep <- .print("deep sees ", K, " ", N).
        }
    }
+!g(N) <- .print("outside ", N); !b; !deep.
+!b <- .print("root b").
+!c <- .print("root c").
-!deep <- .print("no deep outside").
"""


def test_inner_plans_serve_their_parent_and_see_its_variables() -> None:
    # g(1) runs the other plan: neither !b nor !deep finds an inner plan there; g(5)'s inner
    # plans see N and M (bound by the context), the nested one K and N; !c falls back to the
    # agent's own plan
    assert lines(run_source(NESTED)) == [
        "outside 1", "root b", "5 got 11", "no deep outside", "b sees 5 10", "deep sees 5 5",
        "root c"]


def test_a_failure_plan_among_the_inner_plans_handles_an_inner_goal() -> None:
    src = ("!g.\n!h.\n"
           "+!g <- !a; .print(after_a). { +!a <- .fail. -!a <- .print(recovered). "
           "+x <- .print(inner_x). }\n"
           "+!h <- .wait(100); +x; .print(h_done).\n"
           "+x <- .print(root_x).\n")
    # +x of another intention's body is not an event of the intention of !g
    assert lines(run_source(src, timeout=3.0)) == ["recovered", "after_a", "root_x", "h_done"]


def test_inner_plans_print_under_their_parent_and_stay_out_of_the_agents_library() -> None:
    src = ("!s.\n+!s <- .list_plans({+!g(_)}); !g(1).\n"
           "@top +!g(N) <- !a.\n"
           "    {\n"
           "    +!a <- .relevant_plans({+!a}, L); .print(L); .relevant_plans({+!g(_)}, [P]); "
           ".print(P).\n"
           "    @named +!b : N > 0.\n"
           "    }\n")
    text = run_source(src)
    # printed on several lines; an inner plan is named before its parent, with no url
    listed = text[text.index("[main] @top"):text.index("}\n") + 2]
    listed = re.sub(r"_\d+", "_N", re.sub(r"p__\d+", "p__N", listed))
    assert listed == (
        '[main] @top[source(self),url("file:main.asl")] +!g(N) {\n'
        "   <- !a.\n"
        "   @p__N[source(self)] +!a <- .relevant_plans({ +!a },L); .print(L); "
        ".relevant_plans({ +!g(_N) },[P]); .print(P).\n"
        "   @named[source(self)] +!b : (N > 0).\n"
        "}\n")
    out = lines(text)
    assert out[-2] == "[]"
    assert out[-1].startswith('{ @top[source(self),url("file:main.asl")] +!g(') and "+!a" not in out[-1]


def test_inner_plans_are_numbered_before_their_parent() -> None:
    lib = PlanLibrary()
    for plan in parse_source("+!g <- !a. { +!a. +!b. }\n+!h.\n").plans:
        lib.add(plan)
    g = lib.plans[0]
    assert g.sub_library is not None and g.scope is None
    inner = g.sub_library.plans
    assert int(inner[1].label_name()[3:]) == int(inner[0].label_name()[3:]) + 1
    assert int(g.label_name()[3:]) == int(inner[1].label_name()[3:]) + 1
    assert all(p.scope is g.sub_library for p in inner) and g.sub_library.father is lib
    assert lib.relevant(inner[0].trigger) == []


def test_a_plan_with_inner_plans_pickles_with_them() -> None:
    plan = parse_source("+!g <- !a. { +!a <- .print(x). }\n").plans[0]
    again = pickle.loads(pickle.dumps(plan))
    assert [str(p) for p in again.sub_plans] == [str(p) for p in plan.sub_plans]


def test_inner_plans_in_a_namespace_block_are_in_it() -> None:
    src = "{ begin namespace(ns) }\n+!g <- !a. { +!a <- +b. }\n{ end }\n"
    inner = parse_source(src).plans[0].sub_plans[0]
    assert str(inner.trigger) == "+!ns::a" and inner.body[0].term.functor == "ns::b"


@pytest.mark.parametrize("src", ["{ +!a. }\n", "b.\n{ +!a. }\n", "+!g. { +!a. \n"])
def test_inner_plans_must_follow_a_plan(src: str) -> None:
    with pytest.raises(AslSyntaxError):
        parse_source(src)
