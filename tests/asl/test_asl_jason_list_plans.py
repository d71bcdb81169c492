"""``.list_plans`` prints what Jason 3.3 prints: with a goal's trigger term, one message per
plan whose trigger unifies with it; otherwise one message with every plan, grouped under
``// plans from FILE`` and ``// plans without file``. A body whose first deed is ``true`` has
no deed there (Jason's parser drops it from plans, not from plan terms). Expected outputs are
what a Jason 3.3 build printed for the same programs."""

from __future__ import annotations

import re

from asl_helpers import run_source

from rason.asl.parser import parse_source

PROGRAM = """\
!s.
+!s <- .list_plans({+!g(_)}); .print("---"); .list_plans({-!k}); .print("---");
       .add_plan("+!x <- true."); .add_plan({+!r <- true}); .list_plans.
@gp +!g(X) : X > 0 <- .print(X).
+!g(_) <- true.
@gq +!g(X)[foo] <- true; .print(q).
-!k[error(E)] <- .print(E).
"""


def _numbered(text: str) -> str:
    """Plan and variable numbers made alike (rason counts them per process)."""
    return re.sub(r"\b_\d+", "_N", re.sub(r"p__\d+", "p__N", text))


def test_the_listings_are_jasons() -> None:
    # the trigger term's literal takes a source(_) annotation, and a plan's own annotations
    # (error(E), foo) must be among it: -!k[error(E)] and +!g(X)[foo] are not listed
    url = 'url("file:main.asl")'
    assert _numbered(run_source(PROGRAM)) == (
        f'[main] @gp[source(self),{url}] +!g(X) : (X > 0) <- .print(X).\n'
        f'[main] @p__N[source(self),{url}] +!g(_N).\n'
        "[main] ---\n[main] ---\n"
        "[main] \n\n// plans from file:main.asl\n\n"
        f'@p__N[source(self),{url}] +!s <- .list_plans({{ +!g(_N) }}); .print("---"); '
        '.list_plans({ -!k }); .print("---"); .add_plan("+!x <- true."); '
        ".add_plan({ +!r <- true }); .list_plans.\n"
        f"@gp[source(self),{url}] +!g(X) : (X > 0) <- .print(X).\n"
        f"@p__N[source(self),{url}] +!g(_N).\n"
        f"@gq[source(self),{url}] +!g(X)[foo] <- .print(q).\n"
        f"@p__N[source(self),{url}] -!k[error(E)] <- .print(E).\n"
        "\n\n\n// plans without file\n\n"
        # the told plan's leading `true` goes, the plan term's stays
        "@p__N[source(self)] +!x.\n@p__N[source(self)] +!r <- true.\n\n")


def test_only_a_goals_trigger_term_filters_the_list() -> None:
    # Jason reads {+b(_)} as a body that adds b(_), and a plain atom is no trigger: both list all
    src = "!s.\n+!s <- .list_plans({+b(_)}); .list_plans(foo).\n+b(_) <- true.\n"
    out = run_source(src)
    assert out.count("// plans from file:main.asl") == 2


def test_a_first_deed_true_is_dropped_from_plans_but_not_from_plan_terms() -> None:
    plans = parse_source("+!n <- true.\n+!w <- true; .print(a); true.\n"
                         "+!t <- P = {+!q <- true; .print(a)}; .print(P).\n").plans
    assert [str(p) for p in plans] == [
        "+!n.", "+!w <- .print(a); true.",
        "+!t <- (P = { +!q <- true; .print(a) }); .print(P)."]


def test_an_included_file_found_from_the_current_folder_is_a_file_url(tmp_path, monkeypatch) -> None:
    # as Jason's SourcePath.fixPath: its plans' url and their group in the listing
    (tmp_path / "inc.asl").write_text("+!i <- .print(i).\n")
    monkeypatch.chdir(tmp_path)
    out = _numbered(run_source('{ include("inc.asl") }\n!s.\n+!s <- .list_plans.\n'))
    assert "\n// plans from file:inc.asl\n\n" in out
    assert '@p__N[source(self),url("file:inc.asl")] +!i <- .print(i).\n' in out
