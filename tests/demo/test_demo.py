"""The cooperative fault diagnosis end to end: `./run.sh demo` for each fault and for none.

Each run is the real demo process: roscore, simulator, fault injectors, motion decomposers,
vision synthesizer and both agents, all started with rosrun; the fault injected with the real
service. The diagnosis Faulty reaches must be the injected fault.
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from rason_diagnosis.scenario import FAULTS, expected_diagnosis

pytestmark = [pytest.mark.ros, pytest.mark.demo]

SEEDS = {"both_actuators": 11, "odometry": 12, "left_actuator": 13, "right_actuator": 14,
         "none": 15}


@pytest.mark.parametrize("fault", FAULTS)
def test_demo_diagnoses_the_injected_fault(fault, tmp_path):
    out = tmp_path / "run"
    record = ["--record"] if fault == "none" else []
    done = subprocess.run(
        [sys.executable, "-m", "rason_diagnosis", "--fault", fault, "--seed", str(SEEDS[fault]),
         "--out", str(out), *record], capture_output=True, text=True, timeout=600)
    result = json.loads((out / "result.json").read_text())
    assert result["diagnosis"] == expected_diagnosis(fault), done.stdout[-4000:]
    assert done.returncode == 0, done.stdout[-4000:]
    assert result["correct"] and not result["error"]
    assert (out / "run.png").stat().st_size > 10_000
    if fault != "none":
        for step in ("detection_s", "location_s", "diagnosis_s"):
            assert result[step] is not None and result[step] > 0, result
    assert f"diagnosis      : {expected_diagnosis(fault)}" in done.stdout
    if record:
        info = subprocess.run(["rosbag", "info", str(out / "run.bag")], capture_output=True,
                              text=True, timeout=60)
        assert info.returncode == 0, info.stderr
        assert "/faulty/jason/action" in info.stdout and "/jason/messages" in info.stdout
