"""Every script under catkin_ws/src/*/scripts answers ``--help`` with its parameters and exits 0,
without a roscore (ROS_MASTER_URI points at a port nobody listens on)."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest

from rason.process.harness import free_port

SRC = Path(__file__).resolve().parents[2] / "catkin_ws" / "src"
#: ROS nodes: their --help ends with the private parameter table (rosnode_kit.params)
NODES = {("kobuki_fault_injector", "fault_injector"), ("rason", "agent"), ("rason", "mas"),
         ("rason", "echo_decomposer"), ("rason", "mind_inspector"),
         ("rason", "motion_decomposer"), ("rason_vision", "robot_synthesizer"),
         ("rason_vision", "calibrate"), ("turtlebot_sim", "sim"),
         ("rason_diagnosis", "pose_synthesizer")}
#: command-line tools: their --help lists their options (argparse)
TOOLS = {("rason", "act"), ("rason", "asl_run"), ("rason_diagnosis", "campaign"),
         ("rason_diagnosis", "demo"), ("rason_diagnosis", "workstation"),
         ("rason_vision_tools", "record_bags")}
#: long enough for a slow import on a busy machine; a node that starts instead never exits
HELP_TIMEOUT = 60


def _scripts() -> set[tuple[str, str]]:
    return {(path.parent.parent.name, path.name) for path in SRC.glob("*/scripts/*")
            if path.is_file()}


def test_every_script_is_checked():
    assert _scripts() == NODES | TOOLS


@pytest.mark.parametrize(("package", "script"), sorted(NODES | TOOLS))
def test_help_prints_parameters_and_exits_0(package: str, script: str):
    env = {**os.environ, "ROS_MASTER_URI": f"http://127.0.0.1:{free_port()}"}
    out = subprocess.run(["rosrun", package, script, "--help"], capture_output=True, text=True,
                         timeout=HELP_TIMEOUT, env=env)
    assert out.returncode == 0, out.stderr
    assert "usage:" in out.stdout
    if (package, script) in NODES:
        assert "private parameters" in out.stdout, out.stdout
    else:
        assert "options:" in out.stdout, out.stdout
