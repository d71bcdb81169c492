"""The cooperative fault diagnosis end to end: `./run.sh demo` with no fault (recorded), and
with faults in two user worlds.

Each run is the real demo process: roscore, simulator, fault injectors, motion decomposers,
vision synthesizer and both agents, all started with rosrun; the fault injected with the real
service. The diagnosis Faulty reaches must be the injected fault. A demo run costs about a
minute, so each of the other faults is checked end to end by a run that also checks something
else (:data:`COVERED_ELSEWHERE`); every fault is checked by one demo run of the suite.
"""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import warnings
from pathlib import Path

import pytest
import rosbag
from interrupts import sigint_as_in_a_terminal, signal_state
from polling import wait_until

from rason.process.harness import processes_left_by
from rason.ros.auth import AUTH_PARAMETER
from rason_diagnosis.scenario import FAULTS, expected_diagnosis

pytestmark = [pytest.mark.ros, pytest.mark.demo]

REPO = Path(__file__).resolve().parents[2]

SEEDS = {"none": 15}
#: What an agent node or a decomposer started without a key says (rason.ros.node, decomposer).
UNSIGNED = "no ~auth_key_file"

#: The faults whose demo run is another test's run, which asserts the diagnosis too: the file
#: that runs it and the text there that asks for that fault.
COVERED_ELSEWHERE = {
    "both_actuators": ("tests/inspector/test_inspector_browser.py", '"--fault", "both_actuators"'),
    "odometry": ("tests/workspace/test_install_space.py", "--fault odometry"),
    # tests/demo/test_manual.py runs the case study's rosrun commands, which inject this one
    "left_actuator": ("docs/case-study.md", "fault: 'left_actuator'"),
    "right_actuator": ("tests/demo/test_demo.py", '("facing", "right_actuator", 21)'),
}


def test_every_fault_has_an_end_to_end_run():
    assert set(FAULTS) == set(SEEDS) | set(COVERED_ELSEWHERE)
    root = Path(__file__).resolve().parents[2]
    for fault, (where, asks) in COVERED_ELSEWHERE.items():
        assert asks in (root / where).read_text(), (fault, where)


@pytest.mark.parametrize("fault", sorted(SEEDS))
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
    # signed end to end: no agent node nor decomposer of the run went without the run's key
    # (the console streams the agents' warnings; every node's log is in logs/), and the key
    # was not left in the output folder
    logs = {p.name: p.read_text() for p in (out / "logs").glob("*.log")}
    assert {"faulty_agent.log", "helper_motion_decomposer.log"} <= set(logs), sorted(logs)
    assert UNSIGNED not in done.stdout, done.stdout[-4000:]
    assert [name for name, text in logs.items() if UNSIGNED in text] == []
    assert not [p for p in out.rglob("*") if p.suffix == ".key"]
    if record:
        info = subprocess.run(["rosbag", "info", str(out / "run.bag")], capture_output=True,
                              text=True, timeout=60)
        assert info.returncode == 0, info.stderr
        assert "/faulty/jason/action" in info.stdout and "/jason/messages" in info.stdout
        assert_signed(out / "run.bag")


def assert_signed(bag_file: Path) -> None:
    """Every action, its feedback and every agent message in the bag carries a signature."""
    kinds: dict[str, int] = {}
    with rosbag.Bag(str(bag_file)) as bag:
        for topic, msg, _ in bag.read_messages(topics=[
                "/faulty/jason/action", "/faulty/jason/event", "/jason/messages"]):
            kinds[topic] = kinds.get(topic, 0) + 1
            if topic == "/jason/messages":
                assert msg.signature, msg
            else:
                assert msg.parameters and msg.parameters[-1].startswith(AUTH_PARAMETER), msg
    assert set(kinds) == {"/faulty/jason/action", "/faulty/jason/event", "/jason/messages"}, \
        kinds


@pytest.mark.parametrize("world,fault,seed", [("facing", "right_actuator", 21),
                                              ("flank", "left_actuator", 22)])
def test_demo_in_a_user_world(world, fault, seed, tmp_path):
    """`./run.sh demo --world FILE --json` in layouts other than the thesis': Faulty behind
    Helper's view on its left with its yaw near +-180 (a turn across the wrap), and Faulty's
    flank self-occluded at the start. Right diagnosis; the search starts with the full sweep.
    How long locating takes is a measurement (`./run.sh campaign --layouts random`), not
    asserted: on a loaded machine the synthesizer drops frames, the sweep may miss Faulty and
    the careful search finds it (docs/thesis-fixes.md, F9)."""
    from rason_diagnosis.paths import world_file

    out = tmp_path / "run"
    done = subprocess.run(
        [sys.executable, "-m", "rason_diagnosis", "--fault", fault, "--seed", str(seed),
         "--world", str(world_file(world)), "--out", str(out), "--quiet", "--json",
         "--no-inspector"],
        capture_output=True, text=True, timeout=600)
    printed = json.loads(done.stdout[done.stdout.index('{\n  "fault"'):])
    assert printed["diagnosis"] == fault, done.stdout[-4000:]
    assert done.returncode == 0
    assert printed["location_s"] is not None, printed
    search = helper_turns(out / "logs" / "helper_motion_decomposer.log")
    assert search and search[0] == "turn(360)", search
    assert printed["total_s"] is not None


def helper_turns(log: Path) -> list[str]:
    """Helper's turn actions as its motion decomposer logged them, e.g. ``turn(360)``."""
    return re.findall(r"motion_decomposer: (turn(?:_to)?\([-\d.]+\)) of helper", log.read_text())


@pytest.mark.parametrize(("sig", "started"), [(signal.SIGTERM, 1), (signal.SIGINT, 4)])
def test_an_interrupted_demo_leaves_no_process_behind(tmp_path, sig: int, started: int):
    # interrupted while roscore starts (1 process of the run up) or while the nodes start (4)
    # Ctrl-C as from a terminal: a suite started in the background (`cmd &` without job
    # control) hands its children SIGINT ignored, and the demo rightly keeps ignoring it then
    demo = subprocess.Popen([sys.executable, "-m", "rason_diagnosis", "--fault", "none",
                             "--quiet", "--no-inspector", "--out", str(tmp_path / "run")],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            preexec_fn=sigint_as_in_a_terminal)
    try:
        def up() -> bool:
            assert demo.poll() is None, demo.stdout.read() if demo.stdout else ""
            return len(processes_left_by(demo.pid)) >= started
        wait_until(up, f"the demo's first {started} processes", timeout=120)
        signals = signal_state(demo.pid)
        demo.send_signal(sig)
        out, _ = demo.communicate(timeout=90)
    finally:
        if demo.poll() is None:
            demo.kill()
    assert demo.returncode == 130, f"{out[-3000:]}\nthe demo's signals when sent: {signals}"
    assert "interrupted: every node of the run was stopped" in out
    assert processes_left_by(demo.pid) == []
    swallowed = [line for line in out.splitlines() if "was swallowed after it was raised" in line]
    if swallowed:   # the latch ended the run anyway; say where, for the cause still unknown
        warnings.warn(f"the demo's interrupt was swallowed: {swallowed[0]}", stacklevel=1)


@pytest.mark.skipif(os.geteuid() != 0, reason="./run.sh runs setup.sh before each command as "
                                               "root only")
def test_an_interrupt_during_setup_ends_the_run_before_it_starts(tmp_path):
    """SIGINT sent to ``./run.sh demo`` alone (its pid, not its group) while setup runs: the
    run ends 130 once setup is done, and no node starts. Before, bash let setup finish (it
    never got the signal, so it ended well), took the interrupt as handled and started the
    demo, which ran to its end and exited 0."""
    demo = subprocess.Popen(["./run.sh", "demo", "--fault", "none", "--quiet", "--no-inspector",
                             "--out", str(tmp_path / "run")], cwd=REPO, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True,
                            preexec_fn=sigint_as_in_a_terminal)
    try:
        assert demo.stdout is not None
        seen = [demo.stdout.readline()]
        while "==> setup:" not in seen[-1]:     # setup runs (its steps take seconds)
            assert seen[-1], "".join(seen)
            seen.append(demo.stdout.readline())
        demo.send_signal(signal.SIGINT)
        out, _ = demo.communicate(timeout=300)
    finally:
        if demo.poll() is None:
            demo.kill()
    out = "".join(seen) + out
    assert demo.returncode == 130, out[-3000:]
    assert "./run.sh: interrupted during setup: nothing started" in out
    assert "[demo] fault" not in out and not (tmp_path / "run").exists()
