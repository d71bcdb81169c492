"""Internal actions written in Python by a user (``@internal_action("my.act")``), loaded by
module name: in-process, by ``python -m rason.asl run --internal-actions`` and by the agent
node's ``~internal_actions`` parameter."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from agent_nodes import start_agent

from rason.asl import LocalMas, ModuleLoadError, internal_action, load_modules

MODULE = '''
from rason.asl import Literal, internal_action


@internal_action("geo.double")
def double(ctx, args):
    """geo.double(X, Y): Y is 2 * X."""
    return ctx.unify(args[1], 2 * args[0])


@internal_action("geo.is_small")
def is_small(ctx, args):
    """geo.is_small(X): true below 10 (usable in a plan's context)."""
    return isinstance(args[0], float) and args[0] < 10


@internal_action("geo.colours")
def colours(ctx, args):
    """geo.colours(C): one answer per colour (backtracking)."""
    for name in ("green", "orange"):
        s = dict(ctx.s)
        if ctx.unify(args[0], Literal(name)):
            yield ctx.s
        ctx.s = s
'''

AGENT = """
!go(4).
+!go(N) : geo.is_small(N) <- geo.double(N, D); .print("double ", D);
    .findall(C, geo.colours(C), L); .print("colours ", L).
+!go(N) <- .print("too big ", N).
"""


def write(tmp_path: Path) -> Path:
    (tmp_path / "geo_actions.py").write_text(MODULE)
    agent = tmp_path / "geo.asl"
    agent.write_text(textwrap.dedent(AGENT))
    return agent


def test_cli_option_loads_the_module(tmp_path: Path):
    agent = write(tmp_path)
    done = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(agent), "--timeout", "5",
                           "--internal-actions", "geo_actions"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr
    assert "[geo] double 8" in done.stdout
    assert "[geo] colours [green,orange]" in done.stdout
    assert "unknown internal action" not in done.stderr


def test_without_the_module_the_action_is_unknown(tmp_path: Path):
    agent = write(tmp_path)
    done = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(agent), "--timeout", "5"],
                          cwd=tmp_path, capture_output=True, text=True, timeout=60)
    assert "warning: unknown internal action geo.double/2" in done.stdout + done.stderr
    assert "double 8" not in done.stdout


def test_cli_reports_a_module_that_does_not_load(tmp_path: Path):
    agent = write(tmp_path)
    (tmp_path / "broken_actions.py").write_text("import no_such_module_here\n")
    for module in ("no_such_module_xyz", "broken_actions"):
        done = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(agent),
                               "--internal-actions", module],
                              cwd=tmp_path, capture_output=True, text=True, timeout=60)
        assert done.returncode == 2
        assert f"cannot load internal actions from module '{module}'" in done.stderr
        assert "Traceback" not in done.stderr


def test_in_process_registration_and_load_modules(tmp_path: Path, monkeypatch):
    @internal_action("test_user_ia.triple")
    def triple(ctx, args):
        return ctx.unify(args[1], 3 * args[0])

    (tmp_path / "more_user_ias.py").write_text(
        "from rason.asl import internal_action\n"
        "@internal_action('test_user_ia.neg')\n"
        "def neg(ctx, args):\n    return ctx.unify(args[1], -args[0])\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    assert load_modules(["more_user_ias"]) == ["test_user_ia.neg"]
    assert load_modules(["more_user_ias"]) == []          # already there
    lines: list[str] = []

    class Out:
        def write(self, text: str) -> None:
            lines.append(text)

        def flush(self) -> None:
            pass

    mas = LocalMas(out=Out())
    mas.add_agent("calc", "!go. +!go <- test_user_ia.triple(2, X); test_user_ia.neg(X, Y); "
                          ".print(X, \" \", Y).")
    assert mas.run(timeout=5)
    assert "[calc] 6 -6\n" in lines


def test_names_need_a_dot_and_bad_modules_raise():
    with pytest.raises(ValueError, match="has no dot"):
        internal_action("nodot")
    with pytest.raises(ModuleLoadError, match="no_such_module_abc"):
        load_modules(["no_such_module_abc"])


@pytest.mark.ros
def test_agent_node_parameter_loads_the_module(ros, tmp_path: Path):
    agent = write(tmp_path)
    proc = start_agent(ros, tmp_path, "geo", AGENT, ns="/ia1",
                       cwd=tmp_path, internal_actions=["geo_actions"])
    proc.wait_for_line(r"\[geo\] double 8", timeout=20)
    proc.wait_for_line(r"\[geo\] colours \[green,orange\]", timeout=5)
    bad = ros.rosrun("rason", "agent", "geo2", str(agent), ns="/ia2",
                     params={"internal_actions": "[no_such_module_xyz]"}, cwd=tmp_path)
    assert bad.wait(20) == 2
    assert "cannot load internal actions from module 'no_such_module_xyz'" in bad.output()
