"""The reasoning cycle's modules compiled with mypyc (rason.asl.native): used when built from
the sources on disk, never when stale; and the same agents pass as plain Python."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from asl_helpers import subprocess_env

from rason.asl import native

HERE = Path(__file__).resolve().parent


def _in_use(extra_env: dict[str, str]) -> str:
    """What a fresh process loads: "True|False path-of-agent-module". The switch is whatever
    `extra_env` says, not this suite's own (RASON_NATIVE=0 ./run.sh test runs it too)."""
    code = "from rason.asl import native, agent; print(native.in_use(), agent.__file__)"
    env = {k: v for k, v in subprocess_env().items() if k != native.SWITCH}
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                          env={**env, **extra_env}, timeout=60).stdout.strip()


def test_the_setup_built_the_compiled_modules_and_agents_run_them() -> None:
    # setup.sh (run by ./run.sh) builds them; a missing build is a failed setup, not a skip
    assert os.path.isfile(os.path.join(native.build_folder(), "COMPLETE")), \
        "no build for these sources: python -m rason.asl native build"
    used, path = _in_use({}).split(" ", 1)
    assert used == "True" and path.startswith(native.build_folder()), path


def test_rason_native_0_runs_the_python_modules() -> None:
    used, path = _in_use({native.SWITCH: "0"}).split(" ", 1)
    assert used == "False" and path.endswith("agent.py"), path


def test_only_a_complete_build_of_these_very_sources_is_put_on_the_path(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(native, "BUILDS", str(tmp_path))
    monkeypatch.delenv(native.SWITCH, raising=False)
    other = tmp_path / "0badf00d"                       # built from other sources
    other.mkdir()
    (other / "COMPLETE").write_text("")
    assert native.native_path() == []
    current = Path(native.build_folder())
    assert current.parent == tmp_path and current.name != other.name
    current.mkdir()                                     # a build that did not finish
    assert native.native_path() == []
    (current / "COMPLETE").write_text("")
    assert native.native_path() == [str(current)]
    monkeypatch.setenv(native.SWITCH, "0")
    assert native.native_path() == []


def test_the_stamp_follows_every_compiled_module(tmp_path: Path,
                                                 monkeypatch: pytest.MonkeyPatch) -> None:
    source = Path(native.__file__).parent
    for name in native.COMPILED:
        (tmp_path / f"{name}.py").write_bytes((source / f"{name}.py").read_bytes())
    monkeypatch.setattr(native, "_HERE", str(tmp_path))
    first = native.source_stamp()
    assert first == native.source_stamp()
    for name in native.COMPILED:
        with open(tmp_path / f"{name}.py", "a", encoding="utf-8") as f:
            f.write("\n# edited\n")
        changed = native.source_stamp()
        assert changed != first
        first = changed


@pytest.mark.slow                   # the agent-language suite again: left out of --fast
def test_the_agent_language_suite_passes_as_plain_python_too() -> None:
    # the fallback when no C compiler is at hand: every other test of tests/asl, RASON_NATIVE=0
    args = ["-q", "-p", "no:cacheprovider", "--ignore", str(Path(__file__).resolve()), str(HERE)]
    code = ("import sys, pytest; from rason.asl import native; assert not native.in_use(); "
            f"sys.exit(pytest.main({args!r}))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env={**subprocess_env(), native.SWITCH: "0"}, cwd=HERE.parent.parent,
                          timeout=600)
    assert done.returncode == 0, done.stdout[-3000:] + done.stderr[-2000:]
    assert " passed" in done.stdout.splitlines()[-1]
