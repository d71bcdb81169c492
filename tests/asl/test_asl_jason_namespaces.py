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
        "!s.\n+!s <- .print(M::b(Z)); N = ns2; T = N::foo(1); .print(T); "
        "T = K::foo(V); .print(K, \" \", V); W = ns1::X; X = bar; .print(W).\n"))
    assert out == ["M::b(Z)", "ns2::foo(1)", "ns2 1", "ns1::bar"]


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
