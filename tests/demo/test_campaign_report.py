"""The campaign's report lists only the faults that ran and links only the plots written (no ROS:
the report functions on a small record set)."""

from __future__ import annotations

from rason_diagnosis.campaign import write_layout_report, write_plots, write_report
from rason_diagnosis.layouts import random_layout
from rason_diagnosis.scenario import FAULTS, Outcome

RUN = {"seed": 1, "diagnosis": "odometry", "expected": "odometry", "correct": True,
       "detection_s": 5.0, "location_s": 10.0, "diagnosis_s": 3.0, "total_s": 18.0,
       "wall_s": 60.0, "orphans": 0, "outcome": Outcome.RIGHT}
RESULTS = [{**RUN, "fault": "odometry"}, {**RUN, "fault": "odometry", "seed": 2},
           {**RUN, "fault": "none", "diagnosis": "no_fault", "expected": "no_fault"}]
NOT_RUN = [f for f in FAULTS if f not in ("odometry", "none")]


def test_the_report_lists_only_the_faults_that_ran(tmp_path):
    text = write_report(RESULTS, tmp_path, runs=2)
    assert "| odometry | 2/2 |" in text and "| none | 1/1 |" in text
    assert "0/0" not in text
    for fault in NOT_RUN:
        assert fault not in text
    assert (tmp_path / "report.md").read_text() == text


def test_the_report_links_only_the_plots_written(tmp_path):
    assert "![" not in write_report(RESULTS, tmp_path, runs=2)     # no plot written yet
    write_plots(RESULTS, tmp_path)
    text = write_report(RESULTS, tmp_path, runs=2)
    links = [line for line in text.splitlines() if line.startswith("![")]
    assert links == ["![odometry](plots/odometry.png)", "![none](plots/none.png)"]
    assert all((tmp_path / line.split("(")[1].rstrip(")")).is_file() for line in links)


def test_the_layout_report_links_its_plot_only_once_written(tmp_path):
    layouts = [random_layout(seed, (10.0, 10.0)) for seed in (1, 2)]
    text = write_layout_report(RESULTS, layouts, tmp_path)
    assert "plots/layouts.png" not in text
    for fault in NOT_RUN:
        assert f"| {fault} |" not in text
