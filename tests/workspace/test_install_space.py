"""The workspace installs (``catkin_make install``) and the demo runs from the install space alone.

Nothing in the packages may find files through the source tree: the agents and worlds come from
``share/rason_diagnosis`` through the ROS package path, the Python packages from the install
space's ``dist-packages``. The demo runs in a clean environment that sources only the install
space's ``setup.bash`` (and the venv), from a folder outside the repository.
"""

from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.ros

REPO = Path(__file__).resolve().parents[2]


def _clean_env() -> dict[str, str]:
    """Only what a fresh login shell has: no ROS, no workspace, no PYTHONPATH."""
    keep = ("HOME", "LANG", "LC_ALL", "TERM", "USER")
    env = {k: v for k, v in os.environ.items() if k in keep}
    env["PATH"] = "/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin"
    return env


def test_demo_runs_from_the_install_space(tmp_path):
    build, install = tmp_path / "build", tmp_path / "install"
    venv_bin = Path(sys.executable).parent
    make = subprocess.run(
        ["catkin_make", "--source", str(REPO / "catkin_ws" / "src"), "--build", str(build),
         f"-DCATKIN_DEVEL_PREFIX={tmp_path / 'devel'}", f"-DCMAKE_INSTALL_PREFIX={install}",
         f"-DPYTHON_EXECUTABLE={sys.executable}", "-DCATKIN_ENABLE_TESTING=OFF", "install"],
        cwd=tmp_path, env={**_clean_env(), "PATH": f"{venv_bin}:{_clean_env()['PATH']}"},
        capture_output=True, text=True, timeout=600)
    assert make.returncode == 0, make.stdout[-3000:] + make.stderr[-3000:]
    assert (install / "share" / "rason_diagnosis" / "agents" / "diagnosis" / "faulty.asl").is_file()
    assert (install / "share" / "rason_diagnosis" / "agents" / "examples" / "square.asl").is_file()

    out = tmp_path / "run"
    script = " && ".join([
        f"source {shlex.quote(str(venv_bin / 'activate'))}",
        f"source {shlex.quote(str(install / 'setup.bash'))}",
        "rosrun rason_diagnosis demo --fault odometry --seed 12 --quiet "
        f"--inspector-port 0 --out {shlex.quote(str(out))}",
    ])
    run = subprocess.run(["bash", "-c", script], cwd=tmp_path, env=_clean_env(),
                         capture_output=True, text=True, timeout=400)
    assert "diagnosis      : odometry" in run.stdout and "CORRECT" in run.stdout, \
        run.stdout[-3000:] + run.stderr[-3000:]
    assert run.returncode == 0
    # the mind inspector ran from the install space too (it serves its page from the package)
    assert "[demo] mind inspector: http://127.0.0.1:" in run.stdout, run.stdout[-3000:]
    assert list(install.glob("lib/python3*/dist-packages/rason/inspector/static/app.js"))
    # The package path the demo used was the install space's, not the source tree.
    where = subprocess.run(["bash", "-c", f"source {shlex.quote(str(install / 'setup.bash'))} && "
                            "rospack find rason_diagnosis"], env=_clean_env(),
                           capture_output=True, text=True, timeout=60)
    assert where.stdout.strip() == str(install / "share" / "rason_diagnosis")
    assert (out / "run.png").is_file()
