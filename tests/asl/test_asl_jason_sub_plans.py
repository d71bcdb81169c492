"""Sub-plans (Jason 3.3, from Jason(ER)): ``+!g <- body. { inner plans }``. The inner plans
are chosen only for the events of an intention whose top means runs their parent plan or one of
them, before the plans around them, and they see the parent plan's variables as they were when
it was chosen. Expected outputs are what a Jason 3.3 build prints for the same programs."""

from __future__ import annotations

import pickle
import re

import pytest
from asl_helpers import lines, run_agents, run_source

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


# ---------------------------------------------------------------- inner plans for belief events
# An external belief event (told, perceived) that an inner plan of a running plan handles makes
# a branch of that intention: the inner plan runs in a copy of the intention's stack, with the
# parent means' variables as they are now; the agent's own plans for the event run as well.
# ``.done`` in the branch ends the parent's goal (or event) in the intention itself.

SHOP = """\
+order(Id, Item)[source(B)] : price(Item, P) <: false <- .send(B, tell, quote(Id, P)).
  {
    +pay(Id, Sum) : Sum >= P <- .print("paid ", Sum, " for ", Item); !pack; .print("sent ", Id); .done.
    +pay(Id, Sum) <- .print("too little for ", Id).
    +cancel(Id) <- .print("cancelled ", Id); .done.
    +!pack <- .print("packing ", Item, " of ", B).
  }
+pay(Id, _) <- .print("payment seen ", Id).
price(tea, 3).
price(jam, 5).
"""

BUYER = """\
!go.
+!go <- .send(shop, tell, order(1, tea)); .send(shop, tell, order(2, jam)); .wait(300);
        .send(shop, tell, pay(2, 4)); .wait(100); .send(shop, tell, pay(1, 3)); .wait(100);
        .send(shop, tell, cancel(2)); .wait(100); .send(shop, achieve, show).
+quote(Id, P) <- .print("quote ", Id, " ", P).
"""


def test_a_told_belief_branches_the_intention_whose_inner_plan_handles_it() -> None:
    # each order's intention waits (<: false); a payment goes to the inner plans of the order
    # it names (Id is bound there), the agent's own +pay plan sees it too; an inner plan that
    # ends without .done ends only its branch (the order still waits: cancel(2) reaches it)
    shop = SHOP + "+!show <- .findall(I, .intention(I, _), L); .print(L).\n"
    text = run_agents({"shop": shop, "buyer": BUYER}, timeout=5.0)
    assert lines(text, "buyer") == ["quote 1 3", "quote 2 5"]
    assert lines(text, "shop") == [
        "payment seen 2", "too little for 2", "payment seen 1", "paid 3 for tea",
        "packing tea of buyer", "sent 1", "cancelled 2",
        # .done ended both orders' intentions; each branch was an intention; the buyer's
        # intentions take numbers from the same count (Jason 3.3 keeps the ended orders,
        # empty, among its pending intentions: [11,2,3] there)
        "[11]"]
    assert "dropwhenreturntohere" not in text


WATCHER = """\
!wait_for(3).
+!wait_for(N) <- !collect(N); .print("collected ", N).
+!collect(N) <- .print("collecting"); .wait(5000); .print("gave up").
  {
    +item(K) : .count(item(_), C) & C >= N <- .print("last item ", K); .done.
  }
"""

SENDER = """\
!go.
+!go <- .wait(200); .send(watcher, tell, item(a)); .send(watcher, tell, item(b)); .wait(200);
        .send(watcher, tell, item(c)).
"""


def test_done_in_a_branch_achieves_the_goal_in_the_intention_it_copies() -> None:
    # the first two items do not satisfy the inner plan's context: no branch; the third does,
    # and .done there ends !collect in the waiting intention, which goes on at once
    text = run_agents({"watcher": WATCHER, "sender": SENDER}, timeout=8.0)
    assert lines(text, "watcher") == ["collecting", "last item c", "collected 3"]


GUARD = """\
!guard.
+!guard <: false <- .print(guarding); .wait(1000); .print(relieved); .done.
  {
    +alarm <- .print(alarm); .wait(3000); .print(still_here).
  }
+visit[source(A)] <: gone(A) <- .print(visit_from(A)).
+!report <- .findall(s(I, S), .intention(I, S), L); .print(L).
"""

VISITOR = """\
!go.
+!go <- .wait(300); .send(guard, tell, alarm); .send(guard, tell, visit); .wait(300);
        .send(guard, achieve, report); .send(guard, tell, gone(visitor)); .wait(1500);
        .send(guard, achieve, report).
"""


def test_done_in_the_parent_plan_ends_its_branches_and_a_belief_plan_waits_for_its_condition() -> None:
    # the alarm's branch still waits when the guard's .done ends the goal: it goes too
    # (no still_here); the visit's plan waits for its goal condition, then is gone
    text = run_agents({"guard": GUARD, "visitor": VISITOR}, timeout=8.0)
    assert lines(text, "guard") == [
        "guarding", "alarm", "visit_from(visitor)",
        # (the visitor's intentions are numbered from the same count: Jason 3.3's lines)
        "[s(5,running),s(3,waiting[reason(wait(3)[time(3000)])]),"
        "s(4,waiting[reason(wait_goal_condition)]),s(1,waiting[reason(wait(1)[time(1000)])])]",
        "relieved", "[s(6,running)]"]


def test_the_agents_library_knows_the_keys_of_inner_belief_plans() -> None:
    lib = PlanLibrary()
    for plan in parse_source("+!g <- !a. { +!a. { +b(X) <- .done. } -c <- .done. +X <- .done. }\n"
                             "+!h.\n").plans:
        lib.add(plan)
    g = lib.plans[0]
    # +X: any added belief may branch an intention, none removed but -c
    assert lib.branch_keys == {("+", "", "b", 1, False), ("-", "", "c", 0, False),
                               ("+", "", None, 0, False)}
    assert lib.has_key(("+", "", "b", 1, False)) and lib.has_key(("+", "", "d", 0, False))
    assert lib.may_branch(("-", "", "c", 0, False)) and not lib.may_branch(("-", "", "d", 0, False))
    assert not lib.may_branch(("+", "!", "d", 0, False))
    assert g.sub_library is not None and g.sub_library.update_plans and not lib.update_plans
    lib.remove_by_label(g.label_name())
    assert lib.branch_keys == set() and not lib.has_key(("+", "", "b", 1, False))


NEWS = """\
!tell.
+!tell <- .wait(200); .send([reader, skimmer], tell, news(1)); .wait(100);
          .send([reader, skimmer], untell, news(1)); .wait(100);
          .send([reader, skimmer], tell, other).
"""

READER = """\
!read.
+!read <: false <- .print(started).
  {
    +X[source(A)] <- .print(inner, " ", X, " from ", A).
    -X <- .print(gone, " ", X).
    +other <- .print(other).
  }
"""

SKIMMER = """\
!read.
+!read <: false <- .print(started).
  {
    +X[source(A)] <- .print(inner, " ", X, " from ", A).
  }
"""


def test_an_inner_plan_for_any_belief_serves_every_belief_event_of_an_interested_intention() -> None:
    # as Jason 3.3: the reader's intention is interested in belief events (it has an inner
    # plan for +other), so +X and -X take news(1) too, and +X comes before +other; the
    # skimmer's inner plans are all for any belief: Jason counts no interest there, no branch
    text = run_agents({"news": NEWS, "reader": READER, "skimmer": SKIMMER}, timeout=5.0)
    assert lines(text, "reader") == [
        "started", "inner news(1) from news", "gone news(1)[source(news)]", "inner other from news"]
    assert lines(text, "skimmer") == ["started"]


# ---------------------------------------------------------------- plans told and asked
TUTOR = """\
!teach.
+!teach <- .send(learner, tellHow,
                 "@hail +!hail(N) <- !word(N); .print(done). { +!word(K) <- .print(hail, K, N). }");
           .send(learner, tellHow, "+!wave <- !arm. { +!arm <- .print(waving). }");
           .wait(200); .send(learner, achieve, hail(4)); .send(learner, achieve, wave);
           .wait(200); .send(learner, achieve, show).
"""

LEARNER = """\
+!show <- .list_plans({+!hail(_)}); .list_plans({+!wave}).
"""


def test_a_plan_told_as_text_arrives_with_its_inner_plans_and_the_tellers_source() -> None:
    # as in Jason: the inner plans come along, the told plan's label names the teller (the
    # inner ones are the learner's own: source(self)) and no file
    text = run_agents({"tutor": TUTOR, "learner": LEARNER}, timeout=5.0)
    out = re.sub(r"p__\d+", "p__N", text)
    assert sorted(lines(out, "learner")[:3]) == ["done", "hail44", "waving"]   # two intentions
    listed = out[out.index("[learner] @hail"):]
    assert listed == (
        "[learner] @hail[source(tutor)] +!hail(N) {\n"
        "   <- !word(N); .print(done).\n"
        "   @p__N[source(self)] +!word(K) <- .print(hail,K,N).\n"
        "}\n"
        "[learner] @p__N[source(tutor)] +!wave {\n"
        "   <- !arm.\n"
        "   @p__N[source(self)] +!arm <- .print(waving).\n"
        "}\n")


def test_plans_asked_for_come_without_their_inner_plans_as_in_jason() -> None:
    # Jason's askHow answers with .relevant_plans, whose plan terms have no inner plans: the
    # asker gets the plan alone, and its !inner finds no plan
    asker = "!ask.\n+!ask <- .send(tutor, askHow, {+!step(_)}); .wait(200); !step(2).\n"
    text = run_agents({"tutor": "+!step(N) <- !inner. { +!inner <- .print(inner, N). }\n",
                       "asker": asker}, timeout=5.0)
    assert not any(ln.startswith("inner") for ln in lines(text, "asker"))
    assert any("no relevant plan: +!inner" in ln for ln in lines(text, "asker"))
