"""Namespaces as Jason 3.3 reads them, beyond plain ``ns::lit``: variable namespaces
(``N::b(X)``, ``N::X``) and local namespaces (``{ namespace(ns, local) }``), each checked
against what a Jason 3.3 build prints for the same program."""

from __future__ import annotations

import io
import re

from asl_helpers import lines, run_source

from rason.asl import LocalMas, VirtualClock

SHARED_BELIEFS = "b(1).\nns1::b(2).\nns2::b(3).\nns2::c(4).\n"


def test_a_variable_namespace_queries_every_namespace_in_jasons_order() -> None:
    src = SHARED_BELIEFS + (
        "!s.\n+!s <- .findall(N, N::b(_), L); .print(L); .findall(N, N::c(_), L2); .print(L2); "
        ".findall(N, N::missing, L3); .print(L3); "
        "?ns1::b(Y); .print(Y); M = ns2; ?M::b(Z); .print(Z); "
        "if (Q::b(2)) { .print(found_in, \" \", Q) }.\n")
    assert lines(run_source(src)) == ["[default,ns1,ns2]", "[ns2]", "[]", "2", "3", "found_in ns1"]


def test_a_variable_namespace_in_contexts_rules_goals_and_belief_changes() -> None:
    src = SHARED_BELIEFS + (
        "ns1::r(X) :- b(X).\ns(N) :- N::b(3).\n!s.\n"
        "+!s : N::b(2) <- .print(ctx, \" \", N); !N::goal(1); ?s(S); .print(S); -ns2::b(_); "
        ".findall(K, K::b(_), L); .print(L); .findall(K, K::r(_), L2); .print(L2); "
        "M = ns3; +M::e(7); ?ns3::e(E); .print(E).\n"
        "+!X::goal(A) <- .print(goal_in, \" \", X, \" \", A).\n"
        "-X::b(V) <- .print(del, \" \", X, \" \", V).\n"
        "+X::e(V) : X == ns3 <- .print(added, \" \", X, \" \", V).\n")
    assert lines(run_source(src)) == [
        "ctx ns1", "goal_in ns1 1", "ns2", "del ns2 3", "[default,ns1]", "[ns1]",
        "added ns3 7", "7"]


def test_a_variable_namespace_prints_as_written_until_bound() -> None:
    out = lines(run_source(
        "!s.\n+!s <- .print(M::b(Z)); N = ns2; N::T = N::foo(1); .print(T, \" \", N::T); "
        "K::T = ns2::foo(V); .print(K, \" \", V); W = ns1::X; .print(bound, \" \", W).\n"
        "-!s <- .print(failed).\n"))
    # W = ns1::X fails: W is a variable of the default namespace, X one of ns1
    assert out == ["M::b(Z)", "foo(1) ns2::foo(1)", "ns2 1", "failed"]


def test_a_plain_variable_takes_only_literals_of_the_default_namespace() -> None:
    src = ("!s.\n+!s <- !t1; !t2; !t3; !t4; !t5.\n"
           "+!t1 <- X = ns1::foo(1); .print(bound, \" \", X).\n-!t1 <- .print(t1_fails).\n"
           "+!t2 <- p(X) = p(ns1::a); .print(bound, \" \", X).\n-!t2 <- .print(t2_fails).\n"
           "+!t3 <- X = default::foo; .print(t3, \" \", X).\n"
           "+!t4 <- ns1::Z = ns1::bar(2); .print(t4, \" \", Z); ns1::W = ns2::bar; .print(bound, \" \", W).\n"
           "-!t4 <- .print(t4_fails).\n"
           "+!t5 <- Y = N::X; .print(t5, \" \", N); N::V = 5; .print(t5, \" \", V); "
           "K::T = ns2::foo(1); .print(K, \" \", T, \" \", K::T); T = foo(A); .print(A).\n")
    # two free variables unify when their namespaces do (Y = N::X gives N = default); a number
    # has no namespace (N::V = 5 binds V)
    assert lines(run_source(src)) == [
        "t1_fails", "t2_fails", "t3 foo", "t4 bar(2)", "t4_fails", "t5 default", "t5 5",
        "ns2 foo(1) ns2::foo(1)", "1"]


def test_member_findall_and_belief_with_namespaced_literals() -> None:
    src = ("b(1).\nns1::b(2).\nns1::b(c).\nns1::b(ns2::d).\nns2::b(3).\nns1::q.\n!s.\n"
           "+!s <- .findall(N, .member(N::_, [ns1::a, b, ns2::c(1)]), L1); .print(L1); "
           ".findall(K::Y, .member(K::Y, [ns1::a, b, ns2::c(1), 3]), L2); .print(L2); "
           ".findall(X, .member(X, [ns1::a, b, default::e, ns2::f(1)]), L3); .print(L3); "
           ".findall(X, ns1::b(X), L4); .print(L4); .findall(N::B, N::b(B), L5); .print(L5); "
           ".findall(B, .belief(B), L6); .print(L6); .findall(B, .belief(ns1::B), L7); .print(L7); "
           ".findall(N::B, .belief(N::B) & N \\== kqml, L8); .print(L8); "
           ".findall(Q, Q, L9); .print(L9).\n")
    assert lines(run_source(src)) == [
        "[ns1,default,ns2]", "[ns1::a,b,ns2::c(1),3]", "[b,e]", "[2,c]", "[1,2,ns1::c,3]",
        "[b(1)[source(self)]]",
        "[q[source(self)],b(2)[source(self)],b(c)[source(self)],b(ns2::d)[source(self)]]",
        "[b(1)[source(self)],ns1::q[source(self)],ns1::b(2)[source(self)],ns1::b(c)[source(self)],"
        "ns1::b(ns2::d)[source(self)],ns2::b(3)[source(self)]]",
        "[b(1)[source(self)]]"]


def test_abolish_of_namespaced_beliefs() -> None:
    src = ("!s.\n+!s <- +ns3::z(1); +ns3::z(2); +z(3); .abolish(ns3::z(_)); "
           ".findall(N::z(V), N::z(V), L1); .print(L1); +ns3::z(4); .abolish(N::z(_)); "
           ".findall(N::z(V), N::z(V), L2); .print(L2); +ns3::y(1); +y(2); .abolish(X); "
           ".findall(N::y(V), N::y(V), L3); .print(L3).\n")
    # a free variable abolishes the default namespace's beliefs only
    assert lines(run_source(src)) == ["[z(3)]", "[]", "[ns3::y(1)]"]


ASKED = ("ns1::v(1).\nns1::v(3).\nv(2).\nns2::v(4).\n"
         "+!ns1::g(X)[source(S)] <- .print(ns1_g, \" \", X, \" \", S).\n"
         "+!g(X)[source(S)] <- .print(g, \" \", X, \" \", S).\n"
         "+N::w(X)[source(S)] <- .print(added, \" \", N, \" \", X, \" \", S).\n"
         "-N::w(X)[source(S)] <- .print(removed, \" \", N, \" \", X, \" \", S).\n")
ASKING = ("!s.\n"
          "+!s <- .send(bob, askOne, ns1::v(_), ns1::A1); .print(A1); "
          ".send(bob, askOne, ns1::v(_), N::A2); .print(N, \" \", A2); "
          ".send(bob, askAll, ns1::v(_), L1); .print(L1); "
          ".send(bob, askAll, K::v(_), L2); .print(L2); "
          ".send(bob, askOne, M::v(_), A3); .print(A3); "
          ".send(bob, askOne, ns1::missing, A4); .print(A4); "
          ".send(bob, askOne, ns2::v(_)); .wait(500); .findall(P::V, P::v(V)[source(bob)], L3); .print(L3); "
          ".send(bob, tell, ns1::w(1)); .send(bob, tell, [ns1::w(3), ns2::w(4)]); .send(bob, tell, w(2)); "
          ".send(bob, achieve, ns1::g(5)); .send(bob, achieve, g(6)); .wait(500); "
          ".send(bob, untell, ns1::w(1)); .wait(500); "
          ".send(bob, askAll, Q::w(_), L4); .print(L4); "
          ".send(bob, askOne, ns1::v(_), A5); .print(A5).\n"
          "-!s[error_msg(M)] <- .print(M).\n")


def test_messages_keep_the_namespace_of_their_content() -> None:
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("bob", ASKED, "bob.asl")
    mas.add_agent("alice", ASKING, "alice.asl")
    mas.run(timeout=10.0)
    text = out.getvalue()
    assert lines(text, "alice") == [
        "v(1)[source(bob)]", "ns1 v(1)[source(bob)]",
        "[ns1::v(1)[source(bob)],ns1::v(3)[source(bob)]]",
        "[v(2)[source(bob)],ns1::v(1)[source(bob)],ns1::v(3)[source(bob)],ns2::v(4)[source(bob)]]",
        "v(2)[source(bob)]", "false", "[4]",
        "[w(2)[source(bob)[source(alice)]],ns1::w(3)[source(bob)[source(alice)]],"
        "ns2::w(4)[source(bob)[source(alice)]]]",
        # an answer in ns1 does not go into a variable of the default namespace
        "reply of an ask message ('ns1::v(1)[source(bob)]') does not unify with fourth argument "
        "of .send ('A5')"]
    # the order between the messages' plans depends on scheduling (Jason's too)
    assert sorted(lines(text, "bob")) == [
        "added default 2 alice", "added ns1 1 alice", "added ns1 3 alice", "added ns2 4 alice",
        "g 6 alice", "ns1_g 5 alice", "removed ns1 1 alice"]


def test_an_unbound_variable_namespace_cannot_take_a_belief() -> None:
    out = run_source("!s.\n+!s <- +N::b(1).\n-!s[error_msg(M)] <- .print(failed, \" \", M).\n")
    assert lines(out) == ["failed cannot add N::b(1) as a belief"]


def test_a_local_namespace_gets_a_unique_name_private_to_its_file() -> None:
    src = ("{ begin namespace(priv, local) }\np(10).\n"
           "+!g <- ?p(X); .print(in_priv, \" \", X).\n{ end }\n"
           "{ namespace(hid, local) }\nhid::q(5).\n!s.\n"
           "+!s <- .findall(N, .namespace(N), NS); .print(NS); !priv::g; ?hid::q(Q); .print(Q); "
           ".findall(N, N::q(_), L); .print(L); .print(priv::p(1), \" \", hid::q(1)).\n")
    out = lines(run_source(src))
    # a variable never takes a local namespace: .namespace does not list them and N::q finds
    # nothing; the literals print under the unique names (#<n>priv, #<n>hid)
    assert out[:5] == ["[kqml,default]", "in_priv 10", "5", "[]", out[4]]
    m = re.fullmatch(r"#(\d+)priv::p\(1\) #(\d+)hid::q\(1\)", out[4])
    assert m is not None and int(m.group(2)) == int(m.group(1)) + 1


def test_the_same_local_namespace_in_two_files_is_two_namespaces(tmp_path) -> None:
    (tmp_path / "lib.asl").write_text("{ namespace(mine, local) }\nmine::v(lib).\n"
                                      "+!lib_v <- ?mine::v(X); .print(lib_sees, \" \", X).\n")
    (tmp_path / "main.asl").write_text(
        '{ include("lib.asl") }\n{ namespace(mine, local) }\nmine::v(main).\n!s.\n'
        "+!s <- ?mine::v(X); .print(main_sees, \" \", X); !lib_v.\n")
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("main", (tmp_path / "main.asl").read_text(), str(tmp_path / "main.asl"))
    mas.run(timeout=5.0)
    assert lines(out.getvalue()) == ["main_sees main", "lib_sees lib"]


def test_a_goal_of_a_free_namespace_is_posted_as_it_is() -> None:
    out = run_source("!s.\n+!s <- !X::goal(2); .print(after, \" \", X); !!Y::goal(3).\n"
                     "+!X::goal(A) <- .print(goal_in, \" \", X, \" \", A).\n")
    assert lines(out) == ["goal_in X<no-value> 2", "after X<no-value>", "goal_in X<no-value> 3"]


def test_unachieve_and_signal_keep_the_namespace_of_their_content() -> None:
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("bob", "+!ns1::long <- .print(long_started); .wait(2000); .print(long_done).\n"
                         "+N::s(X)[source(S)] <- .print(signal, \" \", N, \" \", X, \" \", S).\n", "bob.asl")
    mas.add_agent("alice", "!s.\n+!s <- .send(bob, achieve, ns1::long); .wait(300); "
                           ".send(bob, unachieve, ns1::long); .send(bob, signal, ns1::s(1)); .wait(3000); "
                           ".send(bob, askOne, ns1::s(_), A); .print(A).\n", "alice.asl")
    mas.run(timeout=10.0)
    # the goal is dropped before it ends; a signal is an event, not a belief
    assert lines(out.getvalue(), "bob") == ["long_started", "signal ns1 1 alice"]
    assert lines(out.getvalue(), "alice") == ["false"]


def test_namespace_properties_are_kept_per_agent_and_read_as_jason_reads_them() -> None:
    """``.namespace_set_prop``/``.namespace_get_prop``, as Jason 3.3 printed them (compiled
    agents keep them in an attribute of their own: the action once wrote the agent's ``__dict__``)."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("a", (
        "!s.\n+!s <- .namespace_set_prop(fam, colour, blue); .namespace_set_prop(fam, size(2), [1,2]);"
        " .namespace_set_prop(other, colour, red); .namespace_get_prop(fam, colour, C); .print(C);"
        " .namespace_get_prop(other, colour, D); .print(D); .namespace_get_prop(fam, gone, V, none);"
        " .print(V); .findall(K, .namespace_get_prop(fam, K), L); .print(L);"
        " if (.namespace_get_prop(fam, gone, W) & not .ground(W)) { .print(free) };"
        " .send(b, achieve, look).\n"), "a.asl")
    mas.add_agent("b", "+!look <- .namespace_get_prop(fam, colour, C, unset); .print(C).\n", "b.asl")
    mas.run(timeout=10.0)
    text = out.getvalue()
    assert lines(text, "a") == ["blue", "red", "none", "[size(2),colour]", "free"]
    assert lines(text, "b") == ["unset"]
