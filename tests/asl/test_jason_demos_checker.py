"""The checker of Jason's demos (benchmarks/jason_demos.py) keeps its strict verdict and adds a
looser one for what changes from run to run of Jason itself: numbers (random offers,
milliseconds) and the order of list items (scheduling)."""

from __future__ import annotations

import importlib.util
import sys
from collections import Counter
from pathlib import Path

CHECKER = Path(__file__).resolve().parents[2] / "benchmarks" / "jason_demos.py"
_spec = importlib.util.spec_from_file_location("jason_demos_checker", CHECKER)
assert _spec is not None and _spec.loader is not None
demos = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = demos   # (its dataclass looks itself up there)
_spec.loader.exec_module(demos)


def test_numbers_become_hashes_and_list_items_are_sorted() -> None:
    line = 'Offers are [offer(105.42,p2),offer(-1e3,p1)] after 12 ms to p2 and "a,b"'
    assert demos.loosened(line) == 'Offers are [offer(#,p1),offer(#,p2)] after # ms to p2 and "a,b"'
    assert demos.loosened("CFP to [p1,pr,p2]") == demos.loosened("CFP to [pr,p2,p1]")
    assert demos.top_level_items('f(a,b),"x,y",c') == ["f(a,b)", '"x,y"', "c"]


def test_the_loose_verdict_does_not_hide_other_differences() -> None:
    jason = demos.per_agent("[c] winner is p3 with 104.4\n[c] CFP to [p1,p2]\n")
    ours = demos.per_agent("[c] CFP to [p2,p1]\n[c] winner is p3 with 100.7\n")
    assert not demos.same_lines(jason, ours)
    assert demos.same_lines(demos.loosen(jason), demos.loosen(ours))
    # another winner is another line: names are not numbers
    other = demos.per_agent("[c] CFP to [p2,p1]\n[c] winner is p1 with 100.7\n")
    assert not demos.same_lines(demos.loosen(jason), demos.loosen(other))
    missing = demos.per_agent("[c] CFP to [p2,p1]\n")
    assert not demos.same_lines(demos.loosen(jason), demos.loosen(missing))
    assert demos.loosen(jason)["c"] == Counter({"winner is p3 with #": 1, "CFP to [p1,p2]": 1})
