"""More rason.asl features: mas2j, KQML performatives, .wait on events, atomic plans, ..."""

from __future__ import annotations

import io

from asl_helpers import RecordingArch, lines, run_source, run_until_idle
from hypothesis import given, settings
from hypothesis import strategies as st

from rason.asl import Agent, AslSyntaxError, LocalMas, VirtualClock, parse_mas2j


def test_mas2j_parsing(tmp_path) -> None:
    (tmp_path / "src").mkdir()
    (tmp_path / "src" / "bob.asl").write_text("")
    (tmp_path / "worker.asl").write_text("")
    text = """/* comment */ MAS demo {
        infrastructure: Centralised
        environment: Env
        agents: bob agentArchClass my.Arch;
                w worker.asl #3;
        aslSourcePath: "src";
    }"""
    proj = parse_mas2j(text, str(tmp_path / "demo.mas2j"))
    assert [a.name for a in proj.agents] == ["bob", "w1", "w2", "w3"]
    assert proj.agents[0].arch_class == "my.Arch"
    assert proj.agents[0].asl_path.endswith("src/bob.asl")
    assert proj.agents[1].asl_path.endswith("worker.asl")
    assert len(proj.notes) == 2


def test_mas2j_error() -> None:
    try:
        parse_mas2j("agents: a;", "x.mas2j")
    except AslSyntaxError as e:
        assert str(e).startswith("x.mas2j:1:1:")
    else:
        raise AssertionError("no error")


def _mas(**agents: str) -> tuple[LocalMas, io.StringIO]:
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    for name, src in agents.items():
        mas.add_agent(name, src)
    return mas, out


def test_kqml_performatives() -> None:
    mas, out = _mas(a="""!s.
+!s <- .send(b, askAll, v(X), L); .print(L);
       .send(b, untell, w(1));
       .send(b, askOne, none(Z), N); .print(N);
       .send(b, unachieve, loop); .print(done).""",
                    b="""v(1). v(2).
!loop.
+!loop <- .wait(100); !loop.
+w(X)[source(S)] <- .print("w ", X, " ", S).
-w(X)[source(S)] <- .print("-w ", X, " ", S).""")
    mas.agents["b"].receive(__import__("rason.asl", fromlist=["Message"]).Message("a", "b", "tell",
                            __import__("rason.asl", fromlist=["parse_literal"]).parse_literal("w(1)")))
    assert mas.run(timeout=60)
    text = out.getvalue()
    assert lines(text, "a") == ["[v(1)[source(b)],v(2)[source(b)]]", "false", "done"]
    assert lines(text, "b") == ["w 1 a", "-w 1 a"]


def test_wait_for_event_and_timeout() -> None:
    out = run_source("""!w. !t.
+!w <- .wait({+go}); .print("go seen").
+!t <- .print("adding"); +go; .wait({+never}, 50).
-!t[error(E)] <- .print("timeout ", E).""")
    assert lines(out) == ["adding", "go seen", "timeout wait_timeout"]


def test_atomic_plan_runs_without_interleaving() -> None:
    out = run_source("""!a. !b.
@x[atomic] +!a <- .print(a1); .print(a2); .print(a3).
+!b <- .print(b1); .print(b2).""")
    assert lines(out)[:3] == ["a1", "a2", "a3"]


def test_suspend_resume() -> None:
    out = run_source("""!a. !b.
+!a <- .print(a1); .suspend; .print(a2).
+!b <- .print(b1); .resume(a); .print(b2).""")
    assert sorted(lines(out)) == ["a1", "a2", "b1", "b2"]
    assert lines(out).index("a2") > lines(out).index("b1")


def test_return_values_and_test_goal_plans() -> None:
    out = run_source("""!m.
+!m <- !fact(5, 1, R); .print(R); ?twice(21, D); .print(D).
+!fact(0, A, A).
+!fact(N, A, R) : N > 0 <- !fact(N - 1, A * N, R).
+?twice(X, Y) <- Y = 2 * X.""")
    assert lines(out) == ["120", "42"]


@settings(max_examples=40, deadline=None)
@given(st.sampled_from([
    "!g.\n+!g <- X = f(Y); !h(X); .print(X).\n+!h(f(1)).",
    "!g.\n+!g : a(X) | true <- .nth(X, [1], Y); .print(Y).",
    "b(1).\n!g.\n+!g <- -+b(B + 1); ?b(C); .print(C).",
    "!g.\n+!g <- .send(x, tell, y); .fail; .print(1).\n-!g <- !g.",
]), st.integers(0, 3))
def test_odd_programs_never_crash(src: str, cut: int) -> None:
    arch = RecordingArch()
    ag = Agent("z", src, arch)
    run_until_idle(ag, 300 + cut)


def test_belief_events_from_a_body_share_the_intention() -> None:
    """Jason's default intBels=sameFocus: the +b plan runs on top of the intention that added b."""
    out = run_source("""!m. !other.
+!m <- +x; .print("after x").
+x <- .print("in x plan 1"); .print("in x plan 2").
+!other <- .print(o1); .print(o2); .print(o3); .print(o4).""")
    got = lines(out)
    assert got.index("in x plan 2") < got.index("after x")
    assert sorted(got) == sorted(["in x plan 1", "in x plan 2", "after x", "o1", "o2", "o3", "o4"])


def test_failure_in_belief_plan_reaches_the_goal() -> None:
    out = run_source("""!m.
+!m <- +x; .print("never").
+x <- .fail.
-!m[error(E)] <- .print("m failed ", E).""")
    assert lines(out) == ["m failed ia_failed"]
