"""Jason 3.3 behaviours observed on a Jason 3.3 build: the standard order of terms, intention
management corner cases, the ``.set``/``.map``/``.queue`` families, ``.fork``/``.join``,
``.done``, ``.belief`` and the directory facilitator in one process."""

from __future__ import annotations

from asl_helpers import lines, run_agents, run_source


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


# ------------------------------------------------------------------ sets, maps, queues
def test_sets_are_changed_in_place_and_kept_in_the_standard_order() -> None:
    assert run('.set.create(S); .set.add(S, b); .set.add(S, a); .set.add(S, f(1)); .set.add(S, 3); '
               '.set.add(S, "x"); .set.add(S, a); .print(S); '
               ".set.add(T, z); .print(T); .set.union(S, [k, b]); .set.remove(S, k); "
               ".set.copy(S, C); .set.add(C, new); .print(S, \" \", C); "
               ".set.intersection(S, [a, b, q]); .set.add_all(S, [y, x]); .set.difference(S, [y]); "
               ".set.to_list(S, L); .length(S, N); .print(L, N); "
               "for (.member(M, S)) { .print(m(M)) }; .type(S, set); "
               "+kept(C); .set.clear(S); ?kept(K); .print(S, \" \", K)") == [
        '{3,"x",a,b,f(1)}', "{z}", '{3,"x",a,b,f(1)} {3,"x",a,b,f(1),new}', "[a,b,x]3",
        "m(a)", "m(b)", "m(x)", '{} {3,"x",a,b,f(1),new}']


def test_maps_put_get_remove_and_backtrack_over_keys_and_values() -> None:
    assert run(".map.create(M); .map.put(M, k2, v2); .map.put(M, k1, 10); .map.put(M, f(x), [1,2]); "
               ".map.put(M, k1, 11); .print(M); .map.get(M, k1, V); .print(V); "
               "if (.map.get(M, nokey, _)) { .print(got) } else { .print(not_got) }; "
               ".map.get(M, nokey, D, default); .print(D); "
               ".findall(K, .map.key(M, K), Ks); .findall(X, .map.value(M, X), Vs); .print(Ks, Vs); "
               ".map.remove(M, k2, R); .map.copy(M, M2); .map.put(M2, zz, 1); .length(M, N); "
               ".print(R, \" \", M, \" \", M2, \" \", N); .map.clear(M); .print(M); .type(M, map)") == [
        "{f(x)->[1,2],k1->11,k2->v2}", "11", "not_got", "default", "[f(x),k1,k2][[1,2],11,v2]",
        "v2 {f(x)->[1,2],k1->11} {f(x)->[1,2],k1->11,zz->1} 2", "{}"]


def test_queues_fifo_and_priority_print_as_java_collections() -> None:
    assert run(".queue.create(Q); .queue.add(Q, c); .queue.add(Q, a); .queue.add(Q, b); .print(Q); "
               ".queue.head(Q, H); .queue.remove(Q, H2); .print(H, H2, \" \", Q); "
               ".queue.add_all(Q, [x, y]); .queue.to_list(Q, L); .length(Q, N); .print(L, N); "
               ".queue.create(P, priority); .queue.add(P, c); .queue.add(P, a); .queue.add(P, b); "
               ".print(P); .queue.remove(P, P1); .queue.to_list(P, PL); .print(P1, PL); "
               ".queue.copy(Q, Q2); .queue.add(Q2, w); .print(Q, \" \", Q2); .queue.clear(Q); "
               "if (.queue.head(Q, _)) { .print(nonempty) } else { .print(empty) }; .type(Q, queue)") == [
        "[c, a, b]", "cc [a, b]", "[a,b,x,y]4", "[a, c, b]", "a[b,c]", "[a, b, x, y] [a, b, x, y, w]",
        "empty"]


def test_belief_looks_only_at_stored_beliefs() -> None:
    assert run("+p(4); .findall(X, .belief(p(X)), L); .findall(X, .belief(q(X)), L2); "
               ".findall(X, .belief(r(X)), L3); .findall(X, .belief(p(X)[a]), L4); .print(L, L2, L3, L4)",
               "p(1). p(2)[a]. q(X) :- p(X). r(5) :- true.\n") == ["[4,1,2][][5][2]"]


# ------------------------------------------------------------------ .fork / .join / .done
def test_fork_and_waits_for_every_branch_fork_or_for_the_first() -> None:
    assert run(".print(begin); "
               ".fork(and, { .wait(100); .print(a1) }, { .print(b1); .wait(50); .print(b2) }); "
               ".print(after_and); .fork(or, { .wait(100); .print(o1) }, { .wait(30); .print(o2) }); "
               ".print(after_or); .wait(300); .print(end)") == [
        "begin", "b1", "b2", "a1", "after_and", "o2", "after_or", "end"]


def test_a_failing_and_branch_drops_the_others_and_fails_the_goal() -> None:
    assert run("!f; .print(after_f)",
               "+!f <- .fork(and, { .print(x1); .fail }, { .wait(100); .print(x2) }); .print(joined).\n"
               "-!f <- .print(f_failed).\n") == ["x1", "f_failed", "after_f"]


def test_failure_after_an_or_join_finds_no_failure_plan_below_the_fork() -> None:
    # as Jason: the intention that went on from an 'or' fork is still a branch of it
    out = run("!g; .print(after_g)",
              "+!g <- .fork(or, { .print(o1) }, { .wait(30); .print(o2) }); .print(joined); .fail.\n"
              "-!g <- .print(g_failed).\n")
    assert out[:2] == ["o1", "joined"] and out[2].startswith("No failure event was generated for +!g[")
    assert "g_failed" not in out and "after_g" not in out and "o2" not in out


def test_done_ends_a_goal_of_the_current_intention() -> None:
    # the bindings of a means ended by .done do not reach its caller; .done(G) for a goal of
    # another intention leaves the current one suspended (as Jason 3.3)
    assert run("!g; .print(after_g); !h; .print(after_h); !m(X); .print(m(X)); "
               "!!k; .wait(50); .done(k); .print(after_done_k)",
               "+!g <- .print(g1); .done; .print(g2).\n"
               "+!h <- !h2; .print(h_after_h2).\n+!h2 <- .print(h2a); .done(h); .print(h2b).\n"
               "+!m(X) <- X = 5; .done; .print(no).\n"
               "+!k <- .print(k1); .wait(100); .print(k2).\n") == [
        "g1", "after_g", "h2a", "after_h", "m(X)", "k1", "k2"]


# ------------------------------------------------------------------ directory facilitator
def test_directory_facilitator_in_one_process() -> None:
    out = run_agents({
        "bob": '!s.\n+!s <- .df_register("sell(book)"); .df_register(buy(pen), "shop"); .wait(300); '
               '.df_search("sell(book)", L); .print(L); .df_search(buy(pen), "other", L2); .print(L2); '
               ".df_search(nothing, L3); .print(L3); "
               '.df_deregister("sell(book)"); .df_search("sell(book)", L4); .print(L4).\n',
        "alice": '!s.\n+!s <- .wait(10); .df_register("sell(book)"); .df_subscribe("sell(book)"); '
                 ".df_subscribe(buy(pen)).\n"
                 "+provider(A, S)[source(Src)] <- .print(A, \" \", S, \" \", Src).\n",
        "carol": '!s.\n+!s <- .wait(100); .df_register("sell(book)").\n'})
    # the search lists names in the order of Jason's HashSet of names
    assert lines(out, "bob") == ["[carol,bob,alice]", "[bob]", "[]", "[carol,alice]"]
    told = lines(out, "alice")
    assert sorted(told[:3]) == ["alice sell(book) df", "bob buy(pen) df", "bob sell(book) df"]
    assert told[3:] == ["carol sell(book) df"]


# ------------------------------------------------------------------ namespaces
def test_a_namespace_block_puts_its_beliefs_plans_and_body_literals_in_the_namespace() -> None:
    src = ("{ begin namespace(ns1) }\nb(k(z)).\nc(1) :- b(_).\n"
           "+!g : b(Y) <- .print(in_ns1, \" \", foo(bar), \" \", Y); ?c(X); .print(X); +e(q); "
           ".findall(W, e(W), L); .print(L); !h.\n+!h <- .print(h_in_ns1).\n{ end }\n"
           "ns2::c(3).\ndefault::d(4).\n!s.\n"
           "+!s <- !ns1::g; .findall(B, ns1::b(B), L); .findall(E, ns1::e(E), L2); .print(L, L2); "
           "?ns2::c(Z); ?d(D); .print(Z, D); +ns3::e(5); .findall(N, .namespace(N), NS); .print(NS); "
           "if (ns1::b(k(z)) == b(k(z))) { .print(eq) } else { .print(neq) }; "
           ".sort([ns2::a, z, ns1::q, default::b, c], S); .print(S).\n")
    # arguments of internal actions stay in the default namespace (the findall inside finds
    # nothing); namespaces list in Jason's hash-map order; the order of terms compares the
    # namespace first
    assert lines(run_source(src)) == [
        "in_ns1 foo(bar) k(z)", "1", "[]", "h_in_ns1", "[k(z)][q]", "34",
        "[kqml,default,ns1,ns3,ns2]", "neq", "[b,c,z,ns1::q,ns2::a]"]


def test_a_bare_double_colon_names_the_current_namespace() -> None:
    # ``::lit`` is the namespace in effect: the default one at the top of a file, the block's
    # inside ``{ begin namespace(ns) }`` (as Jason 3.3 reads it)
    src = ("::b(1).\n{ begin namespace(ns1) }\nc(2).\n::d(3).\n{ end }\n!g1. !g2. !g3.\n"
           "+!g1 : ::b(X) <- .print(b, X, ::b(X)).\n"
           "+!g2 : ns1::c(Y) <- .print(c, Y).\n"
           "+!g3 : d(Z) <- .print(d, Z).\n"
           "+!g3 : ns1::d(Z) <- .print(nsd, Z).\n")
    assert lines(run_source(src)) == ["b1b(1)", "c2", "nsd3"]


def test_concurrent_and_or_operators_are_forks() -> None:
    # |&| binds tighter than |||; a chain of one operator is one fork. As in Jason, the
    # branches of the inner 'and' fork outlive the 'or' that o2 won: they join and go on too
    assert run(".print(begin); !a1 |&| !a2 |&| .print(a3); .print(after_and); !o1 ||| !o2; "
               ".print(after_or); !a1 |&| !a2 ||| !o2; .print(mixed)",
               "+!a1 <- .wait(100); .print(a1).\n+!a2 <- .wait(50); .print(a2).\n"
               "+!o1 <- .wait(100); .print(o1).\n+!o2 <- .wait(30); .print(o2).\n") == [
        "begin", "a3", "a2", "a1", "after_and", "o2", "after_or", "o2", "mixed", "a2", "a1", "mixed"]


def test_goal_states_through_waits_suspension_resumption_and_failure() -> None:
    # what Jason 3.3 posts, in its order (states go out at the start of the next cycle)
    out = run("!!g1; !!g2; .wait(100); .suspend(g1); .wait(50); .resume(g1); !h; .wait(400)",
              "+!g1 <- .wait(300); .print(g1_done).\n+!g2 <- .wait({+b}, 130).\n"
              "-!g2 <- .print(g2_failed).\n+!h <- .fail.\n-!h <- .print(h_failed).\n"
              "^!G[state(S)[reason(R)]] <- .print(G, \" \", S, \" \", R).\n")
    out = [ln.rstrip() for ln in out]
    ids = {name: ln.split("wait(")[1].split(")")[0] for ln in out for name in ("s", "g1", "g2")
           if ln.startswith(f"{name} waiting wait(")}
    assert out == [
        "s pending", "s executing", "g1 pending", "g2 pending", f"s waiting wait({ids['s']})[time(100)]",
        "g1 executing", "g2 executing", f"g1 waiting wait({ids['g1']})[time(300)]",
        f"g2 waiting wait({ids['g2']})[b]", "s executing", "g1 suspended suspend_ia",
        f"s waiting wait({ids['s']})[time(50)]", "g2 failed wait_timeout", "g2 executing has_failure_plan",
        "g2_failed", "g2 achieved", "g2 finished", "s executing", "g1 resumed resume_ia",
        f"g1 waiting wait({ids['g1']})[time(300)]", "h pending", "h executing", "h failed ia_failed",
        "h executing has_failure_plan", "h_failed", "h achieved", "h finished",
        f"s waiting wait({ids['s']})[time(400)]", "g1_done", "g1 executing", "g1 achieved", "g1 finished",
        "s executing", "s achieved", "s finished"]


# ------------------------------------------------------- intention numbers across the agents
# One count numbers the intentions of every agent of a run, as Jason's does: which suspended
# intention ``.resume`` takes first follows those numbers (the order of Jason's map of pending
# intentions, keyed by them), and so does which waiting group a santa-like agent serves next.

COUNTER = """\
round(0).
+!group(G) : .desire(work(_)) <- .print("waiting ", G); .suspend; !!group(G).
@lg[atomic] +!group(G) <- !!work(G).
+!work(G) : round(N) & N < 6 <- .print("working ", G); -+round(N+1); .wait(60); !!next.
+!work(_) <- .print(stop).
+!next <- .resume(group(_)).
"""

QUEUE = """\
!go.
+!go <- .send(counter, achieve, group(a)); .send(counter, achieve, group(b));
        .send(counter, achieve, group(c)); .send(counter, achieve, group(d)); .wait(20);
        .send(counter, achieve, group(e)).
"""


def test_one_resume_serves_the_waiting_group_the_numbers_of_all_agents_put_first() -> None:
    # each .resume(group(_)) binds its _ to the first suspended group it meets: one group a
    # round, e c d b here as on Jason 3.3 (numbered without the queue's intentions, the
    # counter's would be served d e b c)
    out = run_agents({"counter": COUNTER, "queue": QUEUE})
    assert lines(out, "counter") == [
        "working a", "waiting b", "waiting c", "waiting d", "waiting e",
        "working e", "working c", "working d", "working b"]


def test_a_wait_is_kept_under_its_reason_so_intention_lists_them_in_that_order() -> None:
    # Jason keys a waiting intention by the text of its reason (wait(2)[time(300)]): that
    # key's hash puts 3 before 2 here, as on Jason 3.3 (a key of number and time would not)
    out = run("!!w(300); !!w(600); .wait(50); .findall(I, .intention(I, waiting), L); .print(L)",
              "+!w(T) <- .wait(T).")
    assert out == ["[3,2]"]
