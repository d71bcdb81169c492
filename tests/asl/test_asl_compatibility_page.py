"""The compatibility page tells the truth about the standard library: every internal action it
lists as implemented is registered, and every one it says fails with a reason does fail."""

from __future__ import annotations

import os
import re

from asl_helpers import lines, run_source

from rason.asl.ia import is_registered

PAGE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "jason-compatibility.md")


def _page() -> str:
    with open(PAGE, encoding="utf-8") as f:
        return f.read()


def test_every_action_the_page_lists_as_implemented_is_registered() -> None:
    text = _page()
    listed = re.search(r"Implemented: `([^`]*)`", text)
    assert listed is not None
    names = listed.group(1).split()
    assert len(names) > 100
    assert [n for n in names if not is_registered(n)] == []
    # the collection families are listed by member
    for family in ("set", "map", "queue"):
        members = re.search(rf"`\.{family}\.\*` \(([^)]*)\)", text)
        assert members is not None
        for member in re.findall(r"[a-z_]+", members.group(1)):
            if member != "priority":
                assert is_registered(f".{family}.{member}")


def test_actions_without_meaning_in_a_node_fail_naming_why() -> None:
    out = lines(run_source("!s.\n+!s <- .save_agent(\"x.asl\").\n"
                           "-!s[error_msg(M)] <- .print(M).\n"))
    assert len(out) == 1 and "node" in out[0]
