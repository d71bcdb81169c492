"""What the two campaigns share (no ROS): one run's process with its result.json or a stand-in,
and the report's figures and table heads."""

from __future__ import annotations

import json
import sys

from rason_diagnosis.campaign_parts import fmt, mean, run_process, table_head

STAND_IN = {"fault": "odometry", "seed": 1, "error": "no result.json"}


def _writer(run_dir, result: dict) -> list[str]:
    """A run that writes `result` as run_dir/result.json and says so."""
    script = (f"import json, pathlib; d = pathlib.Path({str(run_dir)!r}); d.mkdir(); "
              f"(d / 'result.json').write_text(json.dumps({result!r})); print('written')")
    return [sys.executable, "-c", script]


def test_a_run_gives_its_result_json_and_its_output_goes_to_the_log(tmp_path):
    run_dir, log = tmp_path / "run", tmp_path / "run.log"
    result = run_process(_writer(run_dir, {"fault": "none", "correct": True}), run_dir, log,
                         timeout_s=120, stand_in=dict(STAND_IN))
    assert result == {"fault": "none", "correct": True, "orphans": 0}
    assert log.read_text() == "written\n"
    assert json.loads((run_dir / "result.json").read_text())["fault"] == "none"


def test_a_run_without_result_json_gives_the_stand_in(tmp_path):
    result = run_process([sys.executable, "-c", "raise SystemExit(3)"], tmp_path / "run",
                         tmp_path / "run.log", timeout_s=120, stand_in=dict(STAND_IN))
    assert result == {**STAND_IN, "orphans": 0}


def test_a_run_past_its_time_is_stopped_and_gives_the_stand_in(tmp_path):
    # the sentinel is the return itself: a run that never ends would hang the test
    result = run_process([sys.executable, "-c", "import time; time.sleep(3600)"],
                         tmp_path / "run", tmp_path / "run.log", timeout_s=0.5,
                         stand_in=dict(STAND_IN))
    assert result == {**STAND_IN, "orphans": 0}


def test_figures_and_table_heads():
    assert fmt(None) == "-" and fmt(1.234) == "1.23" and fmt(61.06, 0) == "61"
    assert mean([1.0, None, 2.0]) == 1.5 and mean([None]) is None and mean([]) is None
    assert table_head("a", "b c") == ["| a | b c |", "|---|---|"]
