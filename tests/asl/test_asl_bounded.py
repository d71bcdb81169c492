"""Bounded resources: tail-recursion optimisation (Jason's ``tro``) and the intention depth limit."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from asl_helpers import RecordingArch, subprocess_env

from rason.asl import Agent, AgentOptions

LOOP = """n(0).
!loop.
+!loop : n(N) & N < 3000 <- -+n(N+1); !loop.
+!loop : n(N) <- .print("done ", N).
"""


def _run_tracking_depth(source: str, options: AgentOptions) -> tuple[list[str], int]:
    arch = RecordingArch()
    ag = Agent("a", source, arch, options=options)
    deepest = 0
    for _ in range(100_000):
        if not ag.step():
            break
        for i in ag.all_intentions():
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
    (i,) = ag.all_intentions()
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
    assert ag.all_intentions() == []
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
