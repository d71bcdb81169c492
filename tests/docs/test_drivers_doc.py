"""docs/drivers.md shows the robot-side rosrun lines that `./run.sh demo --drivers stock` starts,
with either `--vision` path (rason_diagnosis.drivers is their one home)."""

from __future__ import annotations

from pathlib import Path

import pytest

from rason_diagnosis.drivers import STOCK, STOCK_RAW, robot_side_lines

DOC = Path(__file__).resolve().parents[2] / "docs" / "drivers.md"


@pytest.mark.parametrize("wiring", [STOCK, STOCK_RAW], ids=["nodelets", "raw"])
def test_the_page_shows_every_line_the_stock_demo_starts(wiring):
    text = DOC.read_text(encoding="utf-8")
    for line in robot_side_lines(wiring):
        assert f"\n{line}\n" in text, line
