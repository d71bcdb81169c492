"""Bounded resources: tail-recursion optimisation (Jason's ``tro``) and the intention depth limit."""

from __future__ import annotations

import gc
import io
import subprocess
import sys
from pathlib import Path

from asl_helpers import RecordingArch, subprocess_env

from rason.asl import Agent, AgentOptions, ListTerm, Literal, LocalMas, Message, Var, VirtualClock, parse_term
from rason.asl.inspection import BeliefView, MindReader

LOOP = """n(0).
!loop.
+!loop : n(N) & N < 3000 <- -+n(N+1); !loop.
+!loop : n(N) <- .print("done ", N).
"""


def run_source_pair(a_source: str, b_source: str) -> list[str]:
    """Run agents ``a`` and ``b`` together; ``a``'s console lines."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("a", a_source)
    mas.add_agent("b", b_source)
    mas.run(timeout=30)
    return [line[4:] for line in out.getvalue().splitlines() if line.startswith("[a] ")]


def _run_tracking_depth(source: str, options: AgentOptions) -> tuple[list[str], int]:
    arch = RecordingArch()
    ag = Agent("a", source, arch, options=options)
    deepest = 0
    for _ in range(100_000):
        if not ag.step():
            break
        for i in ag.circ.all_intentions():
            deepest = max(deepest, len(i.ims))
    return arch.out, deepest


def test_a_loop_by_recursion_keeps_its_intention_flat() -> None:
    out, deepest = _run_tracking_depth(LOOP, AgentOptions())
    assert out == ["done 3000"]
    assert deepest == 1


def test_without_tro_the_same_loop_grows_one_means_per_iteration() -> None:
    out, deepest = _run_tracking_depth(LOOP, AgentOptions(tro=False))
    assert out == ["done 3000"]
    assert deepest == 3000


def test_the_simplest_endless_loop_stays_at_depth_one() -> None:
    arch = RecordingArch()
    ag = Agent("a", "!g.\n+!g <- !g.", arch)
    for _ in range(20_000):
        ag.step()
    (i,) = ag.circ.all_intentions()
    assert len(i.ims) == 1


RESULTS = """!start.
+!start <- !find(0, R); .print("found ", R); !wrap(3, W); .print("wrapped ", W);
           !both(a, X, Y); .print("both ", X, " ", Y).
+!find(N, R) : N < 50 <- !find(N+1, R).
+!find(N, N).
+!wrap(0, R) <- R = z.
+!wrap(N, R) : N > 0 <- R = s(Q); !wrap(N-1, Q).
+!both(a, X, Y) <- X = 1; !both(b, Y, _).
+!both(b, Y, Z) <- Y = 2; Z = 3.
"""


def test_tail_calls_pass_their_results_back_as_without_tro() -> None:
    expected = ["found 50", "wrapped s(s(s(z)))", "both 1 2"]
    for tro in (True, False):
        out, _ = _run_tracking_depth(RESULTS, AgentOptions(tro=tro))
        assert out == expected, tro


def test_a_goal_posted_by_a_failure_plan_is_no_tail_call_as_in_jason() -> None:
    src = """n(0).
!g.
+!g : n(N) & N < 500 <- -+n(N+1); .fail.
+!g : n(N) <- .print("recovered after ", N).
-!g <- !g.
"""
    out, deepest = _run_tracking_depth(src, AgentOptions())
    assert out == ["recovered after 500"]
    assert deepest == 1000   # +!g and its -!g per retry: the depth limit bounds this pattern


DEEP = """!start.
+!start <- !deep(0).
+!deep(N) <- !deep(N+1); .print("never").
-!start[error(E), error_msg(M)] <- .print("start failed: ", E); .print(M).
"""


def test_the_depth_limit_fails_the_intention_with_an_error_a_plan_can_handle(capsys) -> None:
    out, deepest = _run_tracking_depth(DEEP, AgentOptions(max_intention_depth=200))
    assert deepest <= 201
    assert out[-2] == "start failed: intention_too_deep"
    assert "depth limit of 200" in out[-1]
    assert not any("never" in line for line in out)
    assert any("warning: intention" in line and "depth limit of 200" in line for line in out)


def test_an_unhandled_depth_error_drops_the_intention_and_the_agent_goes_on() -> None:
    src = "!deep(0).\n!other.\n+!deep(N) <- !deep(N+1); .print(never).\n+!other <- .wait(5); .print(alive)."
    arch = RecordingArch()
    ag = Agent("a", src, arch, options=AgentOptions(max_intention_depth=100))
    for _ in range(5_000):
        ag.step()
        arch.clock.advance(0.001)
    assert "alive" in arch.out
    assert ag.circ.all_intentions() == []
    assert not any(line == "never" for line in arch.out)


def test_options_from_a_project_file() -> None:
    assert AgentOptions.from_options({}) == AgentOptions()
    opts = AgentOptions.from_options({"tro": "false", "max_intention_depth": "50"})
    assert opts == AgentOptions(tro=False, max_intention_depth=50)
    assert AgentOptions.from_options({"tro": True}, opts) == AgentOptions(True, 50)


def test_command_line_flags(tmp_path: Path) -> None:
    path = tmp_path / "count.asl"
    path.write_text("!g(0).\n+!g(N) : N < 300 <- !g(N+1).\n+!g(N) <- .print(done, N).\n"
                    "-!g(N)[error(E)] <- .print(E, \" at \", N).\n")

    def run(*flags: str) -> str:
        proc = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(path), *flags],
                              capture_output=True, text=True, env=subprocess_env(), timeout=60)
        assert proc.returncode == 0, proc.stderr
        return proc.stdout

    assert run("--max-intention-depth", "100") == "[count] done300\n"
    assert run("--no-tro", "--max-intention-depth", "100").endswith("[count] intention_too_deep at 99\n")
    assert run("--no-tro") == "[count] done300\n"


def test_a_tell_of_20000_literals_takes_a_few_cycles_and_no_deep_intention() -> None:
    n = 20_000
    arch = RecordingArch()
    ag = Agent("b", f"+v(K)[source(a)] : K == {n - 1} <- .count(v(_), C); .print(got, C).", arch)
    content = ListTerm(tuple(Literal("v", (float(k),)) for k in range(n)))
    ag.receive(Message("a", "b", "tell", content))
    cycles, deepest = 0, 0
    while ag.step():
        cycles += 1
        deepest = max([deepest, *(len(i.ims) for i in ag.circ.all_intentions())])
    assert arch.out == [f"got{n}"]
    assert cycles <= 5 and deepest <= 1
    assert ag.bb.size() == n


def test_a_tell_of_a_list_with_user_kqml_plans_still_goes_through_them() -> None:
    arch = RecordingArch()
    src = ("+!kqml_received(S, tell, C, _) : .list(C) <- .length(C, N); .print(list, N).\n"
           "+!kqml_received(S, P, C, M) <- .print(other).")
    ag = Agent("b", src, arch)
    ag.receive(Message("a", "b", "tell", ListTerm((Literal("x"), 2.0, Literal("y", (Var("Z"),))))))
    while ag.step():
        pass
    assert arch.out == ["list3"]


def test_a_tell_of_a_list_adds_only_its_ground_literals_with_the_senders_source() -> None:
    arch = RecordingArch()
    ag = Agent("b", "", arch)
    ag.receive(Message("a", "b", "tell", parse_term('[x, 2, "s", y(Z), [z], w(1)[k]]')))
    while ag.step():
        pass
    assert sorted(str(b) for b in ag.bb) == ["w(1)[k,source(a)]", "x[source(a)]"]


def test_belief_candidates_are_snapshots() -> None:
    arch = RecordingArch()
    ag = Agent("b", "v(1). v(2).", arch)
    snap = ag.bb.candidates(("v", 1, False))
    ag.bb.add(Literal("v", (3.0,)))
    ag.bb.remove(Literal("v", (1.0,), (Literal("source", (Literal("self"),)),)))
    assert [str(b) for b in snap] == ["v(1)[source(self)]", "v(2)[source(self)]"]
    assert [str(b) for b in ag.bb.candidates(("v", 1, False))] == ["v(3)", "v(2)[source(self)]"]


def test_an_answer_found_by_test_goal_recursion_reaches_the_asker() -> None:
    out = run_source_pair(
        "!go.\n+!go <- .send(b, askOne, count(N), A); .print(A).",
        "c(0).\n+?count(N) : c(C) & C < 40 <- -+c(C+1); ?count(N).\n+?count(N) : c(N).")
    assert out == ["count(40)[source(b)]"]


def test_the_warning_of_a_dropped_deep_intention_stays_short() -> None:
    arch = RecordingArch()
    ag = Agent("a", "!deep(0).\n+!deep(N) <- !deep(N+1); .print(never).", arch,
               options=AgentOptions(max_intention_depth=5000))
    while ag.step():
        pass
    text = "\n".join(arch.out)
    assert "depth limit of 5000" in text and "more intended means" in text
    assert len(text.splitlines()) < 130


def test_mind_snapshots_of_a_changing_percept_keep_only_the_current_beliefs() -> None:
    """A mind inspector snapshots an agent whose percept changes every cycle (a robot seen at
    50 Hz): the views of beliefs long gone must not pile up (they once grew for hours)."""
    arch = RecordingArch()
    ag = Agent("a", "b(1).\n", arch)
    reader = MindReader(ag)

    def views_alive() -> int:
        gc.collect()
        return sum(isinstance(o, BeliefView) for o in gc.get_objects())

    baseline = views_alive()
    for k in range(3000):
        arch.percepts = [parse_term(f"robot(faulty,{k % 640},{k * 7 % 480},{k})")]
        ag.step()
        state = reader.snapshot()
        assert state is not None
        assert [v.text for v in state.beliefs if v.group == "robot/4"] == \
            [f"robot(faulty,{k % 640},{k * 7 % 480},{k})"]
    del state
    assert views_alive() - baseline <= 2
