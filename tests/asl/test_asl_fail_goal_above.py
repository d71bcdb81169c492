"""``.fail_goal`` / ``.succeed_goal`` of a goal that has a caller (not at the bottom of its
intention), from another intention and from the goal's own intention, as observed on a Jason
3.3 build: the goal's means and those above it go at once, before any ``-!g`` runs."""

from __future__ import annotations

from asl_helpers import lines, run_source

#: a second intention pursues fetch(7) under carry: the first one fails fetch after a while
OTHER = """!boss.
+!boss <- !!carry; .wait(200); .fail_goal(fetch(_)); .print(boss_done).
+!carry <- !fetch(7); .print(carry_resumes).
+!fetch(N) <- .print(fetching, N); .wait(800); .print(fetched, N).
"""

#: one intention: job -> step(3) -> sub(3), and sub fails step, its caller's goal
OWN = """!job.
+!job <- !step(3); .print(job_resumes).
+!step(K) <- !sub(K).
+!sub(K) <- .print(sub, K); .fail_goal(step(K)); .print(sub_resumes).
"""


def test_other_intention_failure_plan_runs_then_the_caller_resumes() -> None:
    out = run_source(OTHER + "-!fetch(N) <- .print(gave_up, N).\n")
    assert lines(out) == ["fetching7", "boss_done", "gave_up7", "carry_resumes"]


def test_other_intention_without_applicable_failure_plan_dumps_only_the_caller() -> None:
    # -!fetch exists but does not apply: the dump no longer holds fetch's means
    out = run_source(OTHER + "-!fetch(N)[reason(R)] <- .print(never).\n")
    assert out.splitlines() == [
        "[main] fetching7",
        "[main] Could not finish intention:",
        "intention 2: ",
        "    +!carry[source(self)] <- ... !fetch(7); .print(carry_resumes) / {}",
        "",
        "[main] Found a goal for which there is no applicable plan: -!fetch(7)",
        "[main] boss_done",
    ]


def test_other_intention_without_any_failure_plan_goes_silently() -> None:
    assert run_source(OTHER).splitlines() == ["[main] fetching7", "[main] boss_done"]


def test_other_intention_failure_plan_of_the_caller_handles_it() -> None:
    out = run_source(OTHER + "-!carry <- .print(carry_failed).\n")
    assert lines(out) == ["fetching7", "boss_done", "carry_failed"]


def test_own_intention_failure_plan_runs_and_the_caller_is_lost() -> None:
    # the caller went on past !step(3) when .fail_goal returned: when -!step ends, Jason's
    # ClrInt gives up the caller's means as well
    assert lines(run_source(OWN + "-!step(K) <- .print(step_failed, K).\n")) == ["sub3", "step_failed3"]


def test_own_intention_two_levels_up_loses_every_caller() -> None:
    src = OWN.replace("!job.", "!root.\n+!root <- !job; .print(root_resumes).")
    assert lines(run_source(src + "-!step(K) <- .print(step_failed, K).\n")) == ["sub3", "step_failed3"]


def test_own_intention_caller_posting_the_goal_again_resumes_after_it() -> None:
    src = OWN.replace("+!job <- !step(3);", "+!job <- !step(3); !step(3);")
    src = src.replace("+!step(K) <-", "+!step(K) : not again <- +again;")
    src += "+!step(K) <- .print(second, K).\n"
    assert lines(run_source(src + "-!step(K) <- .print(step_failed, K).\n")) == [
        "sub3", "step_failed3", "job_resumes"]


def test_own_intention_without_applicable_failure_plan_dumps_and_runs_on() -> None:
    out = run_source(OWN + "-!step(K)[reason(R)] <- .print(never).\n")
    assert out.splitlines() == [
        "[main] sub3",
        "[main] Could not finish intention:",
        "intention 1: ",
        "    +!job[source(self)] <- ... .print(job_resumes) / {}",
        "",
        "[main] Found a goal for which there is no applicable plan: -!step(3)",
        "[main] job_resumes",
    ]


def test_own_intention_without_any_failure_plan_runs_on_silently() -> None:
    assert run_source(OWN).splitlines() == ["[main] sub3", "[main] job_resumes"]


def test_own_intention_failure_plan_of_a_lower_goal() -> None:
    src = OWN.replace("!job.", "!root.\n+!root <- !job; .print(root_resumes).")
    assert lines(run_source(src + "-!job <- .print(job_failed).\n")) == [
        "sub3", "job_failed", "root_resumes"]


def test_goal_failing_itself_from_its_own_plan() -> None:
    src = ("!job.\n+!job <- !step(3); .print(job_resumes).\n"
           "+!step(K) <- .print(step, K); .fail_goal(step(K)); .print(step_resumes).\n")
    assert lines(run_source(src + "-!step(K) <- .print(step_failed, K).\n")) == ["step3", "step_failed3"]
    assert lines(run_source(src)) == ["step3", "job_resumes"]


def test_succeed_goal_of_a_goal_with_a_caller() -> None:
    assert lines(run_source(OWN.replace(".fail_goal", ".succeed_goal"))) == ["sub3", "job_resumes"]
    src = OTHER.replace(".fail_goal", ".succeed_goal")
    assert lines(run_source(src)) == ["fetching7", "carry_resumes", "boss_done"]


def test_a_recursive_goal_is_failed_at_its_lowest_occurrence() -> None:
    # fetch(7) pursued twice, one under the other: both means go, the caller resumes
    src = OTHER.replace("+!fetch(N) <-", "+!fetch(N) : not twice <- +twice; !fetch(N); .print(outer_fetch).\n"
                        "+!fetch(N) <-")
    assert lines(run_source(src + "-!fetch(N) <- .print(gave_up, N).\n")) == [
        "fetching7", "boss_done", "gave_up7", "carry_resumes"]
