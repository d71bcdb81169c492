"""Jason's agent options and directives that change what an agent shows or computes: the
``verbose`` levels (``[verbose=N]`` in ``.mas2j``, ``.verbose(N)``) and functions registered
with ``{ register_function(...) }`` or from Python. Each expected output of a program is what a
Jason 3.3 build prints for it."""

from __future__ import annotations

import subprocess
import sys

import pytest
from asl_helpers import lines, run_source, subprocess_env

from rason.asl import register_function


def _run_project(tmp_path, mas2j: str, agents: dict[str, str]) -> str:
    for name, src in agents.items():
        (tmp_path / f"{name}.asl").write_text(src)
    (tmp_path / "p.mas2j").write_text(mas2j)
    out = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(tmp_path / "p.mas2j"),
                          "--timeout", "20"],
                         capture_output=True, text=True, timeout=90, env=subprocess_env())
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_verbose_zero_prints_bare_text_and_keeps_the_warnings(tmp_path) -> None:
    out = _run_project(tmp_path, "MAS p { agents: quiet [verbose=0]; loud; }", {
        "quiet": "!s.\n+!s <- .wait(100); .print(a); .println(b); .printf(\"c%s\", x); "
                 ".log(info, hidden); .puts(\"hidden too\"); .log(warning, kept); "
                 ".verbose(1); .print(shown); .verbose(0); .print(d); !nowhere.\n",
        "loud": "!s.\n+!s <- .print(hello).\n"})
    assert out.splitlines()[:5] == ["[loud] hello", "ab", "cx", "[quiet] kept", "[quiet] shown"]
    assert out.splitlines()[5].startswith("d[quiet] No fail event was generated for +!nowhere")


def test_a_verbose_level_that_is_not_a_number_is_a_clear_error(tmp_path) -> None:
    (tmp_path / "a.asl").write_text("!s.\n+!s <- .print(x).\n")
    (tmp_path / "p.mas2j").write_text("MAS p { agents: a [verbose=loud]; }")
    out = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(tmp_path / "p.mas2j")],
                         capture_output=True, text=True, timeout=60, env=subprocess_env())
    assert out.returncode != 0
    assert "verbose=loud: a whole number" in out.stderr


def test_log_names_no_level_as_jasons_console_does() -> None:
    assert lines(run_source("!s.\n+!s <- .log(warning, w); .log(severe, s); .log(fine, f).\n")) == ["w", "s"]


def test_a_function_registered_with_a_rule_is_evaluated_in_expressions() -> None:
    src = ('{ register_function("rf.sum", 2, "sum") }\n'
           '{ register_function("rf.half", 1, "half") }\n'
           "sum(X, Y, Z) :- Z = X + Y.\nhalf(X, Y) :- Y = X / 2.\n!s.\n"
           "+!s <- X = rf.sum(2, 3) * 2; .print(X); .print(rf.half(rf.sum(1, 1))); "
           "if (rf.sum(1, 1) > 1) { .print(yes) }; .print(rf.sum(a, 1)).\n")
    assert lines(run_source(src)) == ["10", "1", "yes", "NaN"]


def test_a_rule_function_of_a_variable_bound_later_in_a_query_waits_for_it() -> None:
    # the query's action resolves its arguments first: rf.dist(N, 1) with N free has no value
    # yet (its rule leaves a term), and stays a term until N = 2 binds it; the compiled
    # modules once failed there (a TypeError instead), so Jason's demos/search failed its A*
    src = ('{ register_function("rf.dist", 2, "dist") }\n'
           "dist(A, B, D) :- D = math.abs(B - A).\np(2).\n!s.\n"
           "+!s <- .findall(X, (N = 2 & X = rf.dist(N, 1)), L); .print(L);\n"
           "       .findall(X, (p(N) & X = rf.dist(N, 1) + 1), L2); .print(L2).\n")
    assert lines(run_source(src)) == ["[1]", "[2]"]


def test_a_function_name_without_a_dot_is_refused_and_the_file_read_on(capfd) -> None:
    src = '{ register_function("nodot", 1, "half") }\n!s.\n+!s <- .print(nodot(4)).\n'
    assert lines(run_source(src)) == ["nodot(4)"]
    assert "The function nodot was not registered! A function must have a '.'" in capfd.readouterr().err


def test_a_function_written_in_python_is_evaluated_with_its_agent() -> None:
    register_function("py.scaled", 2, lambda agent, args: args[0] * args[1] + len(agent.name))
    src = "!s.\n+!s <- .print(py.scaled(3, 2)); Y = py.scaled(1, 1) + 1; .print(Y).\n"
    assert lines(run_source(src, name="abc"), "abc") == ["9", "5"]


def test_registering_one_of_jasons_functions_or_a_bad_name_is_an_error() -> None:
    for name in ("math.abs", ".mine", "plain"):
        with pytest.raises(ValueError):
            register_function(name, 1, lambda agent, args: 0.0)
