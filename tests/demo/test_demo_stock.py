"""`./run.sh demo --drivers stock --fault odometry`: the case study under the real drivers' names.

The odometry fault is the one that silently did nothing under the stock names before the
injector could be wired to them (issue 35): the driver's own ``odom`` reached the decomposer
unfiltered. Here the simulator speaks the stock topics on wall time (no /clock), the injector
reads ``odom`` and publishes ``fault_injector/odom``, Helper's Kinect goes through Debian's
debayer and point-cloud nodelets, and Faulty must conclude ``odometry``. With ``--vision raw``
no nodelet runs: the synthesizer reads the Bayer image and the 16UC1 depth image with its
camera_info itself, and the diagnosis must be right too. (docs/drivers.md)
"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

pytestmark = [pytest.mark.ros, pytest.mark.demo]


def test_stock_demo_diagnoses_an_odometry_fault(tmp_path):
    out = tmp_path / "run"
    done = subprocess.run(
        [sys.executable, "-m", "rason_diagnosis", "--drivers", "stock", "--fault", "odometry",
         "--seed", "1", "--no-inspector", "--out", str(out), "--record"],
        capture_output=True, text=True, timeout=600)
    result = json.loads((out / "result.json").read_text())
    assert result["drivers"] == "stock"
    assert result["diagnosis"] == "odometry", done.stdout[-4000:]
    assert done.returncode == 0 and result["correct"] and not result["error"], done.stdout[-4000:]
    assert "wall (stock drivers)" in done.stdout
    info = subprocess.run(["rosbag", "info", str(out / "run.bag")], capture_output=True,
                          text=True, timeout=60)
    assert info.returncode == 0, info.stderr
    assert "/clock" not in info.stdout                      # wall time: nobody published one
    assert "/faulty/fault_injector/odom" in info.stdout     # what Faulty's nodes read
    injector_log = (out / "logs" / "faulty_fault_injector.log").read_text()
    assert "nothing on" not in injector_log                 # wired right: no miswiring warning
    assert "fault 'odometry' injected" in injector_log


def test_stock_demo_with_raw_vision_diagnoses_a_left_actuator_fault(tmp_path):
    out = tmp_path / "run"
    done = subprocess.run(
        [sys.executable, "-m", "rason_diagnosis", "--drivers", "stock", "--vision", "raw",
         "--fault", "left_actuator", "--seed", "1", "--no-inspector", "--out", str(out)],
        capture_output=True, text=True, timeout=600)
    result = json.loads((out / "result.json").read_text())
    assert (result["drivers"], result["vision"]) == ("stock", "raw")
    assert result["diagnosis"] == "left_actuator", done.stdout[-4000:]
    assert done.returncode == 0 and result["correct"] and not result["error"], done.stdout[-4000:]
    logs = sorted(p.name for p in (out / "logs").iterdir())
    assert not [name for name in logs if "nodelet" in name], logs     # no image pipeline
    assert [name for name in logs if "synthesizer" in name], logs
    assert result["location_s"] is not None                           # Helper saw Faulty
