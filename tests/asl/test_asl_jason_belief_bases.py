"""Jason's own belief-base classes named in a ``.mas2j`` (``beliefBaseClass jason.bb.…``) as
rason's: ``TextPersistentBB`` keeps an agent's beliefs in ``AGENT.bb`` between runs, in Jason's
file format; ``ChainBB`` applies each class of its chain; ``IndexedBB`` changes nothing, as in
Jason 3.3. Expected files and lines are what a Jason 3.3 build writes and prints for the same
project (two runs, each ended by ``.stopMAS``)."""

from __future__ import annotations

import io
from pathlib import Path

import pytest
from asl_helpers import lines

from rason.asl import LocalMas, VirtualClock, load_mas2j
from rason.asl.hooks import HookLoadError
from rason.asl.jason_bb import index_pattern, jason_belief_base

BOB = """\
r(X) :- boss(X,_).
!start.
+!start <- .findall(B, boss(B,N), L); .print(L); +boss(1,"A"); +boss(2,"B"); +boss(1,"C");
           +other(x)[foo]; .findall(b(B,N), boss(B,N), L2); .print(L2); .stopMAS.
"""
CHAIN = ('MAS t { agents: bob beliefBaseClass jason.bb.ChainBB(jason.bb.TextPersistentBB, '
         'jason.bb.IndexedBB("boss(key,_)")); }\n')
#: what Jason 3.3 writes in bob.bb after either run
STORED = """\
// BB stored by TextPersistentBB for agent 'bob'

boss(1,"C")[source(self)].
boss(2,"B")[source(self)].
boss(1,"A")[source(self)].
other(x)[foo,source(self)].
"""


def run_project(folder: Path, mas2j: str) -> str:
    """Run the project once as ``python -m rason.asl run`` does (its stop included)."""
    (folder / "t.mas2j").write_text(mas2j)
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.load_project(load_mas2j(str(folder / "t.mas2j")))
    try:
        mas.run(timeout=10)
    finally:
        mas.stop()
    return out.getvalue()


def test_beliefs_are_kept_in_the_agents_file_between_runs(tmp_path: Path,
                                                          monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "bob.asl").write_text(BOB)
    monkeypatch.chdir(tmp_path)   # Jason's file is relative to the folder the run starts in
    first = lines(run_project(tmp_path, CHAIN), "bob")
    assert first == ["[]", '[b(1,"C"),b(2,"B"),b(1,"A")]']   # IndexedBB replaced nothing
    assert (tmp_path / "bob.bb").read_text() == STORED       # no rule, no kqml belief
    second = lines(run_project(tmp_path, CHAIN), "bob")
    assert second == ["[1,2,1]", '[b(1,"C"),b(2,"B"),b(1,"A")]']
    assert (tmp_path / "bob.bb").read_text() == STORED


def test_a_persistent_agent_without_a_file_starts_with_its_own_beliefs(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    (tmp_path / "amy.asl").write_text('seen(1).\n!s.\n+!s <- .findall(X, seen(X), L); .print(L).\n')
    monkeypatch.chdir(tmp_path)
    out = run_project(tmp_path, "MAS t { agents: amy beliefBaseClass jason.bb.TextPersistentBB; }\n")
    assert lines(out, "amy") == ["[1]"]
    assert (tmp_path / "amy.bb").read_text().splitlines()[2:] == ["seen(1)[source(self)]."]


def test_the_classes_of_a_chain_and_their_patterns() -> None:
    chain = jason_belief_base("jason.bb.ChainBB",
                              ["jason.bb.TextPersistentBB", 'jason.bb.IndexedBB("boss(key,_)")'])
    assert chain is not None and chain.persistent
    assert chain.unique_keys == {("boss", 2, False): (0,)}
    assert index_pattern("depot(_,_,_)") == (("depot", 3, False), ())
    assert jason_belief_base("jason.bb.DefaultBeliefBase", []) is not None
    assert jason_belief_base("jason.bb.JDBCPersistentBB", []) is None   # noted and ignored


def test_a_bad_index_pattern_names_the_project_line(tmp_path: Path) -> None:
    (tmp_path / "bob.asl").write_text("!s.\n+!s.\n")
    with pytest.raises(HookLoadError, match=r"t.mas2j:1: agent bob: beliefBaseClass .*IndexedBB"):
        run_project(tmp_path, 'MAS t { agents: bob beliefBaseClass jason.bb.IndexedBB("(("); }\n')
