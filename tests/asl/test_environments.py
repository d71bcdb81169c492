"""Environments in Python (``environment:`` in ``.mas2j``, :mod:`rason.asl.environment`), and
the three Jason examples ported under ``examples/``.

The examples' agents are Jason's own files, which cannot be copied here: their tests run when
RASON_JASON_TREE names a Jason source tree and are reported as skipped otherwise. What they
compare with (``examples/<name>/expected.txt``) was printed by Jason 3.3 itself.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest
from asl_helpers import subprocess_env

from rason.asl.classdef import split_class_def
from rason.asl.environment import Environment
from rason.asl.mas2j import parse_mas2j
from rason.asl.parser import parse_literal

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
JASON_TREE = os.environ.get("RASON_JASON_TREE", "")
needs_jason_tree = pytest.mark.skipif(
    not JASON_TREE, reason="set RASON_JASON_TREE to a Jason source tree: the example's agents "
    "are Jason's files")


def _run(mas2j: Path, *flags: str, timeout: float = 90) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rason.asl", "run", str(mas2j), *flags],
                          capture_output=True, text=True, timeout=timeout, env=subprocess_env())


# ---------------------------------------------------------------- the contract, without agents
def test_an_agent_perceives_global_percepts_then_its_own_only_when_they_changed() -> None:
    env = Environment()
    env.add_percept("door(open)", "light(on)")
    env.add_percept("key(7)", agent="bob")
    assert [str(p) for p in env.percepts("bob") or []] == ["door(open)", "light(on)", "key(7)"]
    assert [str(p) for p in env.percepts("ann") or []] == ["door(open)", "light(on)"]
    assert env.percepts("bob") is None and env.percepts("ann") is None   # nothing changed
    env.add_percept("key(8)", agent="bob")                               # only bob's changed
    assert env.percepts("ann") is None
    assert [str(p) for p in env.percepts("bob") or []] == ["door(open)", "light(on)", "key(7)", "key(8)"]
    assert env.remove_percept("light(on)") and not env.remove_percept("light(on)")
    assert [str(p) for p in env.percepts("ann") or []] == ["door(open)"]
    env.clear_percepts("bob")                        # bob's own go, the global ones stay
    assert [str(p) for p in env.percepts("bob") or []] == ["door(open)"]
    env.clear_percepts()
    assert env.percepts("bob") == [] and env.percepts("ann") == []
    env.add_percept(parse_literal("~locked(door)"))
    assert env.contains_percept("~locked(door)") and not env.contains_percept("locked(door)")


def test_a_class_definition_gives_the_name_and_arguments_as_strings() -> None:
    env = parse_mas2j('MAS m { environment: m.Env(3, "x, y", no, [a,b], f(1,2)) agents: a; }').environment
    assert env is not None
    assert split_class_def(env) == ("m.Env", ["3", "x, y", "no", "[a, b]", "f(1, 2)"])
    assert split_class_def("pkg.mod.Env") == ("pkg.mod.Env", [])


# ---------------------------------------------------------------- a project with an environment
ENV_MODULE = '''
from rason.asl.environment import Environment


class Counter(Environment):
    def init(self, args):
        self.count = int(args[0])
        self.log(f"init {args}")
        self.add_percept(f"count({self.count})")
        self.add_percept("secret(42)", agent="bob")

    def execute_action(self, agent, action):
        self.log(f"{agent} does {action}")
        if action.functor == "boom":
            raise RuntimeError("bang")
        if action.functor != "inc":
            return False
        self.remove_percept(f"count({self.count})")
        self.count += 1
        self.add_percept(f"count({self.count})")
        self.inform_agents_changed()
        return True

    def stop(self):
        print("environment stopped", flush=True)
'''

ALICE = """
!go.
+!go <- inc; inc; fly.
-!go <- .print("fly failed"); !b.
+!b <- boom.
-!b <- .print("boom failed").
+count(N) : N >= 12 <- .print("saw ", N).
"""

BOB = """
+secret(S) <- .print("my secret ", S).
+count(N) : N >= 12 <- .print("saw ", N).
"""

PROJECT = 'MAS counting { environment: counting_env.Counter(10, "a b") agents: alice; bob; }'


def test_a_project_runs_on_its_python_environment(tmp_path: Path) -> None:
    (tmp_path / "counting_env.py").write_text(ENV_MODULE)
    (tmp_path / "agents").mkdir()
    (tmp_path / "agents" / "alice.asl").write_text(ALICE)
    (tmp_path / "agents" / "bob.asl").write_text(BOB)
    (tmp_path / "p.mas2j").write_text(PROJECT)
    out = _run(tmp_path / "p.mas2j", "--source-path", str(tmp_path / "agents"), "--timeout", "30")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0] == "[Counter] init ['10', 'a b']"
    assert lines[-1] == "environment stopped"           # stop() once the MAS is over
    assert [x for x in lines if x.startswith("[Counter] alice")] == [
        "[Counter] alice does inc", "[Counter] alice does inc", "[Counter] alice does fly",
        "[Counter] alice does boom"]
    assert "[alice] fly failed" in lines                  # False from execute_action: failure
    assert lines.index("[Counter] alice does fly") < lines.index("[alice] fly failed")
    # an exception in execute_action fails that action only, with a warning
    assert "[alice] boom failed" in lines
    assert "RuntimeError: bang" in out.stdout + out.stderr
    # everyone perceives the global count; only bob his own secret
    assert "[alice] saw 12" in lines and "[bob] saw 12" in lines
    assert [x for x in lines if "secret" in x] == ["[bob] my secret 42"]


def test_an_environment_that_cannot_be_found_or_started_is_a_clear_error(tmp_path: Path) -> None:
    (tmp_path / "a.asl").write_text("")
    (tmp_path / "p.mas2j").write_text("MAS p { environment: nowhere_env.Env agents: a; }")
    out = _run(tmp_path / "p.mas2j")
    assert out.returncode == 2 and "cannot import it from" in out.stderr
    assert "No module named 'nowhere_env'" in out.stderr
    (tmp_path / "broken_env.py").write_text(
        "from rason.asl.environment import Environment\n"
        "class Env(Environment):\n    def init(self, args):\n        raise ValueError('no world')\n")
    (tmp_path / "q.mas2j").write_text("MAS q { environment: broken_env.Env(9) agents: a; }")
    out = _run(tmp_path / "q.mas2j")
    assert out.returncode == 2 and "initialisation failed: ValueError: no world" in out.stderr
    (tmp_path / "r.mas2j").write_text("MAS r { environment: broken_env.Missing agents: a; }")
    out = _run(tmp_path / "r.mas2j")
    assert out.returncode == 2 and "module 'broken_env' has no 'Missing'" in out.stderr
    (tmp_path / "s.mas2j").write_text("MAS s { environment: os.path agents: a; }")
    out = _run(tmp_path / "s.mas2j")
    assert out.returncode == 2 and "not a subclass of rason.asl.environment.Environment" in out.stderr


# ---------------------------------------------------------------- Jason's examples
def _expected(name: str) -> list[str]:
    return (EXAMPLES / name / "expected.txt").read_text().splitlines()


def _jason_example(name: str) -> str:
    folder = Path(JASON_TREE) / "examples" / name
    assert folder.is_dir(), f"RASON_JASON_TREE={JASON_TREE}: no examples/{name} there"
    return str(folder)


@needs_jason_tree
def test_blocks_world_prints_what_jason_prints() -> None:
    out = _run(EXAMPLES / "blocks-world" / "blocks_world.mas2j",
               "--source-path", _jason_example("blocks-world"), "--timeout", "60")
    assert out.returncode == 0, out.stderr
    assert out.stdout.splitlines() == _expected("blocks-world")


@needs_jason_tree
def test_room_prints_what_jason_prints() -> None:
    # the porter locks and unlocks for ever: compare the first lines printed in 10 s
    out = _run(EXAMPLES / "room" / "room.mas2j", "--source-path", _jason_example("room"),
               "--timeout", "10")
    lines = out.stdout.splitlines()
    expected = _expected("room")
    assert len(lines) >= 10, out.stderr
    n = min(len(lines), len(expected))
    assert lines[:n] == expected[:n]


_JUG_LINE = re.compile(r"\[agent_simple\]            State: \((\d),(\d)\)"
                       r"|\[Jugs\] doing (\w+)\((\d)(?:,(\d))?\)"
                       r"|\[agent_simple\] Problem solved with (\d+) actions")


def _check_jugs_trace(lines: list[str]) -> None:
    """A water-jugs run is random: check that each line is one Jason prints and that the
    states shown follow from the actions, up to the solution (1 litre in the 3 litre jug)."""
    water = {5: 0, 3: 0}
    actions = 0
    for line in lines:
        m = _JUG_LINE.fullmatch(line)
        assert m is not None, line
        if m.group(1) is not None:
            assert (int(m.group(1)), int(m.group(2))) == (water[5], water[3]), line
        elif m.group(3) is not None:
            op, jug = m.group(3), int(m.group(4))
            actions += 1
            if op == "fill":
                water[jug] = jug
            elif op == "empty":
                water[jug] = 0
            else:
                other = 8 - jug
                v = min(water[jug], other - water[other])
                water[jug] -= v
                water[other] += v
        else:
            assert int(m.group(6)) == actions and water[3] == 1, line
            return
    raise AssertionError("no 'Problem solved' line")


def test_the_water_jugs_check_accepts_what_jason_printed() -> None:
    _check_jugs_trace(_expected("water-jugs"))
    with pytest.raises(AssertionError):
        _check_jugs_trace([x.replace("(5,3)", "(5,2)") for x in _expected("water-jugs")])


@needs_jason_tree
def test_water_jugs_prints_what_jason_prints() -> None:
    for seed in ("1", "2", "3"):
        out = _run(EXAMPLES / "water-jugs" / "water_jugs.mas2j",
                   "--source-path", _jason_example("water-jugs"), "--seed", seed, "--timeout", "60")
        assert out.returncode == 0, out.stderr
        _check_jugs_trace(out.stdout.splitlines())
