"""Jason 3.3 internal actions for control and program loading: ``.if_then_else``,
``.foreach``, ``.loop``, ``.include`` (and the ``include`` directive with a namespace),
``.internal_action``, ``.drop_future_intention``; how ``.print`` shows a free variable.
Each expected output is what a Jason 3.3 build prints for the same program."""

from __future__ import annotations

import io

from asl_helpers import lines, run_source

from rason.asl import LocalMas, VirtualClock

LIB = ('v(1).\n+!g <- ?v(X); .print(lib_g, " ", X).\n+!h <- ?::v(X); .print(lib_h, " ", X).\n'
       "!ini.\n+!ini <- .print(lib_ini).\n")


def run_files(tmp_path, main: str, timeout: float = 5.0) -> list[str]:
    (tmp_path / "lib.asl").write_text(LIB)
    (tmp_path / "main.asl").write_text(main)
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("main", main, str(tmp_path / "main.asl"))
    mas.run(timeout=timeout)
    return lines(out.getvalue())


def test_if_then_else_foreach_and_loop_as_actions() -> None:
    src = ("b(1). b(2). b(3).\nc(0).\n!s.\n"
           "+!s <- .if_then_else(b(2), {.print(yes)}, {.print(no)}); "
           ".if_then_else(b(9), {.print(yes)}, {.print(no)}); .if_then_else(b(9), {.print(yes)}); "
           ".if_then_else(b(X) & X > 1, {.print(then, X)}); .print(after_if, X); "
           ".foreach(b(Y), {.print(each, Y)}); .print(after_foreach, Y); "
           ".loop(c(Z) & Z < 3, {.print(loop, Z); -+c(Z+1)}); ?c(C); .print(c, C).\n")
    assert lines(run_source(src)) == [
        "yes", "no", "then2", "after_if2", "each1", "each2", "each3", "after_foreachY<no-value>",
        "loop0", "loop1", "loop2", "c3"]


def test_control_actions_check_their_arguments() -> None:
    src = ("!s.\n+!s <- .foreach(b(X), not_a_body).\n"
           "-!s[error(E), error_msg(M)] <- .print(E, \" \", M).\n")
    assert lines(run_source(src)) == [
        "wrong_arguments Wrong argument for internal action 'foreach': second argument must be a "
        "plan body term."]


def test_a_free_variable_prints_with_no_value() -> None:
    src = "b(1).\n!s.\n+!s <- .print(X); .print(f(Y)); Z = Y; .println(Z, \" \", a); .log(info, W).\n"
    assert lines(run_source(src)) == ["X<no-value>", "f(Y)", "Z<no-value> a", "W<no-value>"]


def test_internal_action_tells_internal_actions() -> None:
    src = ("!s.\n+!s <- if (.internal_action(.print)) { .print(a_yes) } else { .print(a_no) }; "
           "if (.internal_action(my.act(1))) { .print(b_yes) } else { .print(b_no) }; "
           "if (.internal_action(print)) { .print(c_yes) } else { .print(c_no) }.\n")
    assert lines(run_source(src)) == ["a_yes", "b_yes", "c_no"]


def test_include_action_adds_plans_beliefs_and_goals_in_a_namespace(tmp_path) -> None:
    out = run_files(tmp_path, (
        "!s.\n+!s <- .include(\"lib.asl\"); !g; .include(\"lib.asl\", libns); !libns::g; !libns::h; "
        ".include(\"lib.asl\", NS); .print(ns, \" \", NS); .wait(10); "
        ".findall(N, .namespace(N), L); .print(L).\n"))
    # the included file's initial goal !ini runs (in its namespace) after each include
    assert out[:5] == ["lib_ini", "lib_g 1", "lib_ini", "lib_g 1", "lib_h 1"]
    assert out[5].startswith("ns ns") and out[5][len("ns ns"):].isdigit()
    assert out[6] == "lib_ini"
    assert out[7].startswith("[kqml,default,") and "libns" in out[7] and out[5][3:] in out[7]


def test_include_directive_with_a_namespace(tmp_path) -> None:
    out = run_files(tmp_path, '{ include("lib.asl", inc) }\n!s.\n'
                    "+!s <- !inc::g; ?inc::v(X); .print(X); .findall(Y, v(Y), L); .print(L).\n")
    assert out == ["lib_ini", "lib_g 1", "1", "[]"]


def test_include_of_a_missing_file_fails_the_action(tmp_path) -> None:
    out = run_files(tmp_path, '!s.\n+!s <- .include("nowhere.asl").\n'
                    "-!s[error_msg(M)] <- .print(M).\n")
    assert out == ["the included file 'nowhere.asl' was not found"]


def test_drop_future_intention_drops_intentions_that_will_post_the_goal() -> None:
    src = ("!s.\n+!s <- !!w1; !!w2; .wait(20); .drop_future_intention(w(1)); .wait(300); .print(end).\n"
           "+!w1 <- .wait(100); !w(1); .print(w1_after).\n"
           "+!w2 <- .wait(100); !w(2); .print(w2_after).\n"
           "+!w(X) <- .print(w, X).\n")
    assert lines(run_source(src)) == ["w2", "w2_after", "end"]


def test_include_action_in_a_namespace_block_includes_in_that_namespace(tmp_path) -> None:
    out = run_files(tmp_path, '{ begin namespace(blk) }\n+!load <- .include("lib.asl").\n{ end }\n!s.\n'
                    "+!s <- !blk::load; !blk::g; .findall(N, .namespace(N), L); .print(L).\n")
    assert out == ["lib_ini", "lib_g 1", "[kqml,default,blk]"]
