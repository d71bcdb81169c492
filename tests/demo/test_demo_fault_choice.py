"""Which fault ``./run.sh demo`` injects without --fault, and what its first line says (no ROS)."""

from __future__ import annotations

from pathlib import Path

from rason_diagnosis.__main__ import start_line
from rason_diagnosis.scenario import FAULTS, INJECTED_FAULTS, NO_FAULT, default_fault

SEEDS = range(400)


def test_without_fault_the_demo_draws_a_real_fault_only():
    drawn = {default_fault(seed) for seed in SEEDS}
    assert NO_FAULT not in drawn
    assert drawn == set(INJECTED_FAULTS)         # every real fault can be drawn
    assert set(FAULTS) == {*INJECTED_FAULTS, NO_FAULT}


def test_the_same_seed_draws_the_same_fault():
    assert [default_fault(seed) for seed in SEEDS] == [default_fault(seed) for seed in SEEDS]


def test_first_line_names_the_drawn_fault_and_how_to_choose():
    line = start_line("odometry", 1234, Path("out/demo-odometry-1234"), drawn=True)
    assert line.startswith("[demo] fault odometry (drawn by seed 1234")
    for hint in ("--fault NAME", f"--fault {NO_FAULT}", "--seed 1234", *INJECTED_FAULTS):
        assert hint in line
    assert "out/demo-odometry-1234" in line


def test_first_line_of_a_chosen_fault_says_it_was_given():
    line = start_line(NO_FAULT, 7, Path("out/x"), drawn=False)
    assert line.startswith(f"[demo] fault {NO_FAULT} (given by --fault, seed 7)")
    assert "drawn" not in line
