"""The demo's and campaign's world, colours and vision options, without ROS: a world names its
colours file, the campaign passes world, colours and vision to every run, --vision needs the
stock profile."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from rason_diagnosis.__main__ import world_problem
from rason_diagnosis.campaign import main as campaign_main
from rason_diagnosis.drivers import SIM, STOCK, STOCK_RAW, VisionPath, wiring_for
from rason_diagnosis.paths import world_colours, world_file


def test_the_harsh_world_names_its_calibrated_colours():
    colours = world_colours(world_file("harsh"))
    assert colours == world_file("harsh").parent / "harsh_colours.yaml"
    assert colours.is_file()
    assert world_colours(world_file()) is None          # the case study: the default ranges


def test_a_world_naming_a_missing_colours_file_is_refused(tmp_path):
    world = tmp_path / "w.yaml"
    world.write_text(world_file().read_text() + "\nvision: {colours: nowhere.yaml}\n")
    assert "nowhere.yaml" in world_problem(world)
    (tmp_path / "nowhere.yaml").write_text("green: {lower: [50, 80, 40], upper: [70, 255, 255]}\n")
    assert world_problem(world) is None


def test_vision_paths_of_each_profile():
    assert wiring_for("sim") is SIM and wiring_for("stock") is STOCK
    assert wiring_for("stock", "nodelets") is STOCK
    raw = wiring_for("stock", "raw")
    assert raw is STOCK_RAW and raw.vision is VisionPath.RAW and not raw.vision_nodes
    assert raw.synthesizer_params == {"depth_input": "image"}
    assert raw.odom_reader_args == STOCK.odom_reader_args           # the injector's odometry
    with pytest.raises(ValueError, match="--drivers stock"):
        wiring_for("sim", "raw")


def test_demo_and_campaign_refuse_vision_under_sim_and_a_missing_colours_file(tmp_path):
    for module in ("rason_diagnosis", "rason_diagnosis.campaign"):
        done = subprocess.run([sys.executable, "-m", module, "--vision", "raw"],
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 2 and "--vision raw needs --drivers stock" in done.stderr
        done = subprocess.run([sys.executable, "-m", module, "--colours", str(tmp_path / "no")],
                              capture_output=True, text=True, timeout=60)
        assert done.returncode == 2 and "no such file" in done.stderr


def test_the_campaign_gives_every_run_its_world_colours_and_vision(tmp_path, monkeypatch):
    calls: list[list[str]] = []

    def fake_run(fault: str, seed: int, out: Path, extra=()) -> dict:
        calls.append(list(extra))
        return {"fault": fault, "seed": seed, "diagnosis": "unknown", "correct": False,
                "unknown_reason": "the helper could not find me", "orphans": 0}

    monkeypatch.setattr("rason_diagnosis.campaign.run_one", fake_run)
    harsh = world_file("harsh")
    campaign_main(["--runs", "1", "--faults", "odometry", "--world", str(harsh),
                   "--drivers", "stock", "--vision", "raw", "--out", str(tmp_path)])
    assert calls == [["--drivers", "stock", "--vision", "raw", "--world", str(harsh),
                      "--colours", str(world_colours(harsh))]]
    report = (tmp_path / "report.md").read_text()
    assert "unknown (the helper could not find me)" in report and "WRONG" not in report


def test_a_random_layout_of_the_harsh_world_keeps_its_colours(tmp_path):
    from rason_diagnosis.layouts import random_layout, write_world

    written = write_world(random_layout(3, (10.0, 10.0)), world_file("harsh"), tmp_path / "w.yaml")
    assert world_colours(written) == world_colours(world_file("harsh"))
    assert world_problem(written) is None
