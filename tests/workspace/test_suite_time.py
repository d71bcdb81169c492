"""The suite-time benchmark's arithmetic (benchmarks/suite_time.py): a JUnit XML summed by module
and kind, and the replay of its times on workers."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

BENCHMARKS = Path(__file__).resolve().parents[2] / "benchmarks"
_spec = importlib.util.spec_from_file_location("suite_time", BENCHMARKS / "suite_time.py")
assert _spec is not None and _spec.loader is not None
suite_time = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = suite_time   # (its dataclasses look themselves up there)
_spec.loader.exec_module(suite_time)

JUNIT = """<?xml version="1.0" encoding="utf-8"?>
<testsuites><testsuite name="pytest" tests="5">
<testcase classname="tests.demo.test_mission" name="test_a" time="50.0"/>
<testcase classname="tests.demo.test_mission" name="test_b" time="40.0"/>
<testcase classname="tests.demo.test_readme_commands" name="test_page[x]" time="2.0"/>
<testcase classname="tests.workspace.test_param_typos" name="test_c" time="3.0"/>
<testcase classname="tests.asl.test_asl_lalr" name="test_d[1]" time="0.5"/>
</testsuite></testsuites>
"""


@pytest.fixture
def tests(tmp_path: Path) -> list:
    (tmp_path / "junit.xml").write_text(JUNIT)
    return suite_time.read_junit(tmp_path / "junit.xml")


def test_modules_are_summed_with_their_kind(tests: list) -> None:
    modules = suite_time.by_module(tests)
    mission = modules["tests/demo/test_mission.py"]
    assert (mission.tests, mission.seconds, mission.longest) == (2, 90.0, 50.0)
    kinds = {path: m.kind for path, m in modules.items()}
    assert kinds == {"tests/demo/test_mission.py": suite_time.Kind.END_TO_END,
                     "tests/demo/test_readme_commands.py": suite_time.Kind.END_TO_END,
                     "tests/workspace/test_param_typos.py": suite_time.Kind.ROS,
                     "tests/asl/test_asl_lalr.py": suite_time.Kind.PURE}


def test_phases_come_from_the_durations_output(tests: list, tmp_path: Path) -> None:
    modules = suite_time.by_module(tests)
    (tmp_path / "log").write_text(
        "1.50s teardown tests/workspace/test_param_typos.py::test_c\n"
        "1.25s call     tests/workspace/test_param_typos.py::test_c\n"
        "0.50s teardown tests/workspace/test_param_typos.py::test_c[other]\n")
    suite_time.add_phases(modules, tmp_path / "log")
    assert dict(modules["tests/workspace/test_param_typos.py"].phases) == \
        {"teardown": 2.0, "call": 1.25}


def test_the_replay_gives_each_unit_to_the_first_idle_worker() -> None:
    assert suite_time.makespan([10.0, 3.0, 3.0, 3.0], 2) == 10.0
    assert suite_time.makespan([3.0, 3.0, 3.0, 10.0], 2) == 13.0   # the 10 s last
    assert suite_time.makespan([3.0, 3.0, 3.0, 10.0], 1) == 19.0


def test_the_end_to_end_group_is_one_unit_and_light_ones_can_leave_it(tests: list) -> None:
    grouped = suite_time.units_of(tests)
    assert sorted(grouped.group) == [2.0, 40.0, 50.0] and sorted(grouped.others) == [0.5, 3.0]
    assert grouped.loadgroup() == [92.0, 3.0, 0.5]
    light_out = suite_time.units_of(tests, light=10.0)
    assert sorted(light_out.group) == [40.0, 50.0]
    assert sorted(light_out.others) == [0.5, 2.0, 3.0]
    assert light_out.longest_first() == [90.0, 3.0, 2.0, 0.5]
