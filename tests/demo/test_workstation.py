"""``./run.sh demo --real``: the workstation side alone, against robots already up (#35 item 4).

The test brings "the robots" up itself, as their own bring-up would: the simulator (playing both
Kobuki bases and Helper's Kinect) and each robot's rason nodes (fault injector, motion
decomposer, Helper's synthesizer), started separately on the test's master. Then the
workstation mode runs as a user starts it, as its own process against that master: it must
start only the agents, and its verdict must be the agents' own (Faulty's belief through the
mind service and its printed conclusion), with no simulator, ground truth or /clock of its own.
The diagnosis is the injected fault, or ``unknown`` with the agents' reason when Helper's camera
loses Faulty on a loaded machine (never a wrong component); the demo's tests judge the
diagnosis itself. The robots' decomposers are keyed with a fleet key and the workstation is
given the same file (``--key``): the whole run is signed (docs/real-robot.md, "Signed
traffic").
"""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest
from agent_nodes import key_file

from rason.process.harness import Process, RosHarness
from rason_diagnosis import workstation
from rason_diagnosis.paths import world_file
from rason_diagnosis.scenario import HELPER_MOTION, HELPER_VISION, ROBOTS, keyed

pytestmark = [pytest.mark.ros, pytest.mark.demo]

REPO = Path(__file__).resolve().parents[2]
FAULT = "left_actuator"


def robots_up(ros: RosHarness, key: Path) -> list[Process]:
    """What the two robots run before the workstation starts (docs/real-robot.md), their
    decomposers keyed with the fleet's `key` ("Signed traffic")."""
    ros.set_param("/use_sim_time", True)           # the default profile's simulated time
    sim = ros.rosrun("turtlebot_sim", "sim", params={"world": str(world_file()), "seed": 7,
                                                     "drivers": "sim"})
    ros.wait_for_topic("/clock", timeout=60, watch=[sim])
    nodes = [sim]
    for robot in ROBOTS:
        nodes.append(ros.rosrun("kobuki_fault_injector", "fault_injector", ns=f"/{robot}"))
        nodes.append(ros.rosrun("rason", "motion_decomposer", ns=f"/{robot}",
                                params=keyed(key, HELPER_MOTION if robot == "helper" else None)))
    nodes.append(ros.rosrun("rason_vision", "robot_synthesizer", ns="/helper",
                            params=HELPER_VISION))
    ros.wait_for_topic("/helper/jason/perception", timeout=60, watch=nodes)
    return nodes


def test_the_workstation_mode_runs_the_agents_and_reports_their_verdict(ros: RosHarness,
                                                                       tmp_path: Path):
    key = key_file(tmp_path, "fleet.key")
    robot_side = robots_up(ros, key)
    nodes_before = set(ros.nodes())
    run = ros.run(["./run.sh", "demo", "--real", "--fault", FAULT, "--record", "--no-inspector",
                   "--key", str(key), "--out", str(tmp_path / "run")], label="workstation",
                  cwd=REPO)
    status = run.wait(timeout=500)
    out = run.output()
    assert status in (0, 1), out[-4000:]
    # only the agents were started, nothing robot-side, no simulator of its own
    assert "started on this machine: the agents /helper/jason/helper, /faulty/jason/faulty; " \
           "nothing robot-side" in out
    logs = sorted(p.name for p in (tmp_path / "run" / "logs").glob("*.log"))
    assert logs == ["faulty_agent.log", "helper_agent.log", "rosbag_record.log"], logs
    # signed: the agents got the key (none says it runs open), the robots' decomposers heard
    # them (the run went on), and the workstation did not call the run unsigned
    assert "no ~auth_key_file" not in out and "no --key" not in out, out[-4000:]
    assert all(p.alive() for p in robot_side), "the robots' nodes must run on"
    assert set(ros.nodes()) >= nodes_before
    # the verdict: Faulty's belief, matching what Faulty itself printed. The injected fault,
    # or (Helper's camera losing Faulty on this shared, loaded 2-core machine) unknown with
    # the agents' reason; never a wrong component
    line = re.search(r"\[real\] diagnosis     : (\w+)  \(Faulty's belief; injected "
                     rf"{FAULT}, expected {FAULT}\) -> (\w+)", out)
    assert line, out[-3000:]
    print(line.group(0))
    said = {FAULT: r"left actuator has problems , thanks helper",
            "unknown": r"the fault is unknown"}
    assert line.group(1) in said, line.group(0)
    assert re.search(rf"\[real\] agent said    : \[faulty\] .*{said[line.group(1)]}", out), \
        out[-3000:]
    if line.group(1) == FAULT:
        assert line.group(2) == "CORRECT" and status == 0
    else:
        assert line.group(2) == "UNKNOWN" and status == 1 and "[real] unknown because: " in out
        print("NOTE: the agents ended 'unknown' (Helper lost Faulty): the verdict is theirs")
    info = subprocess.run(["rosbag", "info", str(tmp_path / "run" / "run.bag")],
                          capture_output=True, text=True, timeout=60, env=ros.env)
    assert "/jason/messages" in info.stdout and "/faulty/jason/event" in info.stdout, info.stdout
    assert "/clock" not in info.stdout and "camera" not in info.stdout


def test_without_the_robots_it_names_the_missing_node_and_starts_nothing(ros: RosHarness,
                                                                          tmp_path: Path):
    run = ros.run(["./run.sh", "demo", "--real", "--robots-timeout", "2", "--no-inspector",
                   "--out", str(tmp_path)], label="workstation", cwd=REPO)
    status = run.wait(timeout=120)
    out = run.output()
    assert status == 1, out
    assert "error         : Faulty's motion_decomposer is not up (subscriber " \
           "/faulty/jason/action not seen on the master" in out, out
    assert "started on this machine" not in out
    assert "[real] no --key: the agents and the robots' decomposers talk unsigned" in out


@pytest.mark.parametrize("content", ["", "short\n"])
def test_a_missing_or_short_key_is_refused_before_anything_starts(tmp_path: Path, capsys,
                                                                 content: str):
    key = tmp_path / "fleet.key"
    if content:
        key.write_text(content)
    with pytest.raises(SystemExit) as exit_:
        workstation.main(["--real", "--key", str(key), "--out", str(tmp_path / "run")])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--key: " in err and str(key) in err, err
    assert not (tmp_path / "run").exists()
