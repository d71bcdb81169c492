"""Every ``FIX(Fn)`` in the case-study agents has its entry in docs/thesis-fixes.md, and back."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
AGENTS = REPO / "agents" / "diagnosis"
FIXES = REPO / "docs" / "thesis-fixes.md"


def _cited() -> set[str]:
    cited: set[str] = set()
    for agent in AGENTS.glob("*.asl"):
        text = agent.read_text(encoding="utf-8")
        assert "FIX:" not in text, f"{agent.name}: a FIX without its entry name FIX(Fn)"
        cited |= set(re.findall(r"FIX\((F\d+)\)", text))
    return cited


def _documented() -> set[str]:
    return set(re.findall(r"^## (F\d+) ", FIXES.read_text(encoding="utf-8"), flags=re.M))


def test_every_fix_in_the_agents_is_documented():
    missing = _cited() - _documented()
    assert not missing, f"FIX entries missing in docs/thesis-fixes.md: {sorted(missing)}"


def test_every_documented_fix_is_cited_and_complete():
    text = FIXES.read_text(encoding="utf-8")
    unused = _documented() - _cited()
    assert not unused, f"entries no agent cites: {sorted(unused)}"
    for entry in re.split(r"^## ", text, flags=re.M)[1:]:
        if not re.match(r"F\d+ ", entry):
            continue
        for field in ("**Thesis**", "**Bug**", "**Fix**"):
            assert field in entry, f"{entry.splitlines()[0]}: no {field}"


def test_agents_name_no_file_outside_the_repository():
    for agent in AGENTS.glob("*"):
        text = agent.read_text(encoding="utf-8")
        assert not re.search(r"(^|\s)/(work|tmp|home|root)/", text), agent.name
