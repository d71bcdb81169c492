"""``./run.sh campaign --mission``'s report, runs.csv and plots from a small set of mission
results, and which runs it asks for (no ROS: the report functions on records shaped like the
mission's result.json; the runs themselves are ``./run.sh mission`` processes, tested in
tests/demo/test_mission.py)."""

from __future__ import annotations

import csv
import json

import pytest

from rason_diagnosis import mission_campaign as mc
from rason_diagnosis.campaign import main as campaign_main


def _run(fault: str, seed: int, mode: mc.Mode, total: float | None, by: list[str | None],
         errors: list[float | None], closest: float = 1.0, **more) -> dict:
    points = [{"x": 0.0, "y": 0.0, "reached_by": b, "at_s": None, "error_m": e}
              for b, e in zip(by, errors, strict=True)]
    completed = all(by)
    return {"fault": fault, "seed": seed, "mode": mode.value, "completed": completed,
            "waypoints": points, "total_s": total, "min_robot_distance_m": closest,
            "diagnosis": None if fault == "none" else fault, "wall_s": 90.0, "orphans": 0,
            **({} if completed else {"reason": "no_recovery"}), **more}


R, B = mc.Mode.RECOVERY, mc.Mode.BASELINE
RESULTS = [
    _run("none", 1, R, 50.0, ["faulty"] * 4, [0.01, 0.02, 0.01, 0.02]),
    _run("none", 2, R, 60.0, ["faulty"] * 4, [0.01, 0.01, 0.01, 0.01]),
    _run("both_actuators", 1, R, 100.0, ["faulty", "helper", "helper", "helper"],
         [0.05, 0.1, 0.4, 0.2], closest=0.3),        # one error over the bar, a contact
    _run("both_actuators", 2, R, 90.0, ["helper"] * 4, [0.05, 0.1, 0.1, 0.2]),
    _run("both_actuators", 1, B, 30.0, ["faulty", None, None, None], [0.05, None, None, None]),
]


def test_a_run_is_timed_against_the_fault_free_mission_of_its_seed():
    reference = mc.fault_free_times(RESULTS)
    assert reference == {1: 50.0, 2: 60.0}
    first = mc.figures(RESULTS[2], reference)
    assert first.relative_time == 2.0 and first.by_faulty == 1 and first.by_helper == 3
    assert first.max_error_m == 0.4 and not first.within_bar and first.contact
    assert mc.figures(RESULTS[3], reference).relative_time == 1.5
    assert mc.figures(RESULTS[3], reference).within_bar
    assert not mc.figures(RESULTS[3], reference).contact
    touching = {**RESULTS[3], "min_robot_distance_m": 0.354}     # 2 x the body radius, rounded
    assert mc.figures(touching, reference).contact
    baseline = mc.figures(RESULTS[4], reference)
    assert not baseline.completed and baseline.not_reached == 3 and not baseline.within_bar
    # a seed without its own fault-free run: the mean of those that ran
    other = mc.figures({**RESULTS[3], "seed": 9}, reference)
    assert other.relative_time == round(90.0 / 55.0, 2)


def test_the_report_shows_each_fault_with_and_without_recovery(tmp_path):
    mc.write_plots(RESULTS, tmp_path)
    text = mc.write_report(RESULTS, tmp_path)
    table = {line.split(" | ")[0].lstrip("| ") + "/" + line.split(" | ")[1]: line
             for line in text.splitlines() if line.startswith("| ") and " | " in line}
    assert "| 2/2 | 2/2 | 55.0 (60.0) | 1.00 (1.00) |" in table["none/recovery"]
    assert "| 2/2 | 1/2 | 95.0 (100.0) | 1.75 (2.00) |" in table["both_actuators/recovery"]
    assert table["both_actuators/recovery"].endswith("| 0.300 | 1 | 1 / 7 / 0 |")
    assert "| 0/1 | 0/1 | - (-) | - (-) |" in table["both_actuators/baseline"]
    assert table["both_actuators/baseline"].endswith("| 1 / 0 / 3 |")
    assert "none/baseline" not in table and "odometry" not in text
    assert "![completion, time and errors per fault](plots/mission.png)" in text
    assert (tmp_path / "plots" / "mission.png").stat().st_size > 10_000
    assert "| baseline | both_actuators | 1 |" in text and "faulty, -, -, -" in text
    assert (tmp_path / "report.md").read_text() == text


def test_runs_csv_and_report_only_read_back_the_kept_results(tmp_path, capsys):
    for r in RESULTS:
        where = mc.run_dir(tmp_path, mc.Mode(r["mode"]), r["fault"], r["seed"])
        where.mkdir(parents=True)
        (where / "result.json").write_text(json.dumps({k: v for k, v in r.items()
                                                       if k not in ("mode", "orphans")}))
    assert campaign_main(["--mission", "--report-only", "--out", str(tmp_path)]) == 0
    with open(tmp_path / "runs.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(RESULTS)
    both = next(r for r in rows if r["fault"] == "both_actuators" and r["mode"] == "recovery"
                and r["seed"] == "1")
    assert both["relative_time"] == "2.0" and both["by_helper"] == "3"
    assert both["contact"] == "True" and both["within_bar"] == "False"
    assert "| both_actuators | baseline | 0/1 |" in (tmp_path / "report.md").read_text()


def test_the_campaign_runs_every_fault_and_seed_in_the_modes_asked(tmp_path, monkeypatch):
    asked: list[tuple[str, str, int, tuple[str, ...]]] = []

    def fake_run(mode, fault, seed, out, extra=()):
        asked.append((mode.value, fault, seed, tuple(extra)))
        return _run(fault, seed, mode, 50.0, ["faulty"] * 4, [0.01] * 4)

    monkeypatch.setattr(mc, "run_one", fake_run)
    world = tmp_path / "w.yaml"
    world.write_text("{}")
    assert campaign_main(["--mission", "--baseline", "--runs", "2", "--first-seed", "5",
                          "--faults", "none", "odometry", "--world", str(world),
                          "--out", str(tmp_path / "c")]) == 0
    assert sorted(asked) == sorted((m, f, s, ("--world", str(world)))
                                   for m in ("recovery", "baseline") for f in ("none", "odometry")
                                   for s in (5, 6))
    asked.clear()
    assert campaign_main(["--mission", "--no-recovery", "--runs", "1", "--faults", "odometry",
                          "--out", str(tmp_path / "d")]) == 0
    assert asked == [("baseline", "odometry", 1, ())]
    for kept in ("runs.csv", "report.md", "plots/mission.png"):
        assert (tmp_path / "d" / kept).is_file()


@pytest.mark.parametrize("args", [["--hosts"], ["--layouts", "random"], ["--drivers", "stock"],
                                  ["--no-recovery", "--baseline"]])
def test_options_that_do_not_apply_to_the_mission_are_refused(args, tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        campaign_main(["--mission", *args, "--out", str(tmp_path)])
    assert exit_.value.code == 2
    assert "--" in capsys.readouterr().err


def test_the_recovery_flags_need_the_mission(tmp_path, capsys):
    with pytest.raises(SystemExit):
        campaign_main(["--baseline", "--out", str(tmp_path)])
    assert "go with --mission" in capsys.readouterr().err
