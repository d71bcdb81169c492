"""Robots on their own hosts: the case study across network namespaces, and link faults.

Real namespaces, veth links and a bridge (``ip netns``; needs root, as CI runs), real demo
processes (roscore and the simulator on the ``world`` host, each robot's nodes and agent on its
own host). A cut is ``ip link set eth0 down`` on a robot's host for a few simulated seconds.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys

import pytest
from polling import wait_until

from rason.process import netns
from rason.process.harness import processes_left_by
from rason_diagnosis.hosts import LinkCut, PresenceEvent, presence_events

pytestmark = [pytest.mark.ros, pytest.mark.demo, pytest.mark.hosts]


@pytest.fixture(autouse=True)
def _root() -> None:
    if os.geteuid() != 0:
        pytest.fail("network namespaces need root (CI runs as root): run ./run.sh test as root")


def _ours(pid: int) -> list[str]:
    return [n for n in netns.namespaces() if n.startswith(f"{netns.PREFIX}-{pid}-")]


def _demo(out, *args: str) -> tuple[subprocess.CompletedProcess, dict]:
    demo = subprocess.Popen([sys.executable, "-m", "rason_diagnosis", "--quiet", "--out", str(out),
                             *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    stdout, _ = demo.communicate(timeout=600)
    assert not _ours(demo.pid), "the run left its namespaces behind"
    assert not processes_left_by(demo.pid), "the run left processes behind"
    done = subprocess.CompletedProcess(demo.args, demo.returncode, stdout)
    return done, json.loads((out / "result.json").read_text())


def test_link_cut_specs_and_presence_lines() -> None:
    assert LinkCut.parse("faulty@8s+5s") == LinkCut("faulty", 8.0, 5.0)
    assert LinkCut.parse("helper@2.5+1") == LinkCut("helper", 2.5, 1.0)
    assert str(LinkCut("faulty", 8.0, 5.0)) == "faulty@8s+5s"
    for bad in ("faulty@8s", "world@1s+1s", "faulty@1s+0s", "faulty 8 5", ""):
        with pytest.raises(ValueError):
            LinkCut.parse(bad)
    lines = ["[INFO] [1795429976.30, 18.700000]: agent faulty not heard for 3.5 s: forgotten",
             "[helper] Finding faulty", "[INFO] [1795429979.15, 20.670000]: agent faulty present"]
    assert presence_events("helper", lines) == [PresenceEvent(18.7, "helper", "faulty", False),
                                                PresenceEvent(20.67, "helper", "faulty", True)]


def test_lan_links_cut_restore_and_removal() -> None:
    with netns.Lan(["alpha", "beta"]) as lan:
        alpha, beta = lan.host("alpha"), lan.host("beta")
        assert (alpha.address, beta.address) == ("10.211.0.1", "10.211.0.2")
        server = subprocess.Popen(beta.command([sys.executable, "-m", "http.server", "--bind",
                                                beta.address, "8000"]),
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        probe = [sys.executable, "-c", "import socket,sys; s=socket.create_connection("
                 f"('{beta.address}', 8000), timeout=1); print('connected')"]

        def reachable() -> bool:
            done = subprocess.run(alpha.command(probe), capture_output=True, text=True)
            return "connected" in done.stdout

        wait_until(reachable, "beta's server reachable", timeout=10, period=0.1)
        lan.cut("beta")
        assert not lan.link_up("beta") and not reachable()
        lan.restore("beta")
        assert lan.link_up("beta") and reachable()
        assert sorted(_ours(os.getpid())) == sorted([lan.switch, alpha.netns, beta.netns])
    assert not _ours(os.getpid())
    assert server.wait(5) is not None          # removing the host stopped what ran on it


def test_case_study_across_hosts_diagnoses_the_fault(tmp_path) -> None:
    done, result = _demo(tmp_path / "run", "--hosts", "--fault", "left_actuator", "--seed", "13")
    assert result["hosts"] and not result["dead"], done.stdout[-3000:]
    assert result["diagnosis"] == "left_actuator", done.stdout[-3000:]
    assert result["correct"] and done.returncode == 0
    seen = {(e["observer"], e["agent"]) for e in result["presence"] if e["present"]}
    assert seen == {("helper", "faulty"), ("faulty", "helper")}     # across the LAN
    roscore_log = (tmp_path / "run" / "logs" / "roscore.log").read_text()
    assert "http://10.211.0.1:11311/" in roscore_log


def test_link_cut_mid_run_is_noticed_and_never_gives_a_wrong_component(tmp_path) -> None:
    done, result = _demo(tmp_path / "run", "--hosts", "--cut", "faulty@8s+5s",
                         "--fault", "left_actuator", "--seed", "13")
    out = done.stdout[-3000:]
    assert not result["dead"], out                                  # nothing crashed
    links = [(e["host"], e["up"]) for e in result["link_events"]]
    assert links == [("faulty", False), ("faulty", True)], out
    down, up = (e["t"] for e in result["link_events"])
    assert up - down == pytest.approx(5.0, abs=0.2)
    for observer, agent in (("helper", "faulty"), ("faulty", "helper")):   # both sides notice
        saw = [(e["t"], e["present"]) for e in result["presence"]
               if (e["observer"], e["agent"]) == (observer, agent)]
        lapses = [t for t, present in saw if not present and down < t <= up + 1.0]
        assert lapses, f"{observer} never noticed {agent}'s presence lapse: {saw}\n{out}"
        assert any(present and t > lapses[0] for t, present in saw), \
            f"{observer} never noticed {agent}'s return: {saw}\n{out}"
    assert result["diagnosis"] in ("left_actuator", "unknown"), out  # never a wrong component
    if result["diagnosis"] == "unknown":
        assert result["unknown_reason"], out
    else:
        assert result["correct"] and done.returncode == 0, out


# Runs in a child process: entering a namespace is for good, and this test process keeps the
# suite's roscore on loopback.
SUPERVISION = """
import json, sys, time
from pathlib import Path
from rason.process import netns
from rason.process.harness import RosHarness
asl = Path(sys.argv[1])
asl.write_text("!go. +!go <- .wait(1000); move(1).")
with netns.Lan(["master", "brain", "base"], firewall=True) as lan:
    netns.enter(lan.host("master"))
    with RosHarness(master_host=lan.host("master")) as ros:
        base = ros.rosrun("rason", "echo_decomposer", ns="/base", params={"delay": 60},
                          host=lan.host("base"))
        ros.wait_for_subscriber("/base/jason/action", timeout=60)
        ros.rosrun("rason", "agent", "pilot", str(asl), ns="/base", host=lan.host("brain"))
        base.wait_for_line(r"of pilot .action 1.", timeout=60)
        lan.cut("brain")
        cut = time.monotonic()
        line = base.wait_for_line(r"action 1 of pilot -> (\\w+) \\((.*)\\)", timeout=30)
        print(json.dumps({"after_s": time.monotonic() - cut, "result": line.group(1),
                          "why": line.group(2), "log": base.output()[-2000:]}))
"""


def test_decomposer_stops_an_action_when_its_agent_on_another_host_is_cut_off(tmp_path):
    # The agent ("brain": a workstation) and the decomposer ("base": the robot) on two hosts;
    # the brain's link goes down while the decomposer runs its 60 s action: the decomposer
    # notices the agent's presence lapse and ends the action cancelled (the robot stops).
    done = subprocess.run([sys.executable, "-c", SUPERVISION, str(tmp_path / "pilot.asl")],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-3000:]
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["result"] == "cancelled", report["log"]
    assert "pilot not heard" in report["why"], report["log"]
    assert report["after_s"] < 10.0, report          # presence timeout 3.5 s (+ a tick)


def test_interrupted_run_removes_everything_and_a_killed_one_is_cleaned_next_time(tmp_path):
    def start(name: str) -> subprocess.Popen:
        demo = subprocess.Popen([sys.executable, "-m", "rason_diagnosis", "--hosts", "--quiet",
                                 "--fault", "none", "--out", str(tmp_path / name)],
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        def up() -> bool:                                # roscore and some nodes are running
            assert demo.poll() is None, "the demo exited before it started"
            return len(processes_left_by(demo.pid)) >= 3
        wait_until(up, "the demo's first processes", timeout=120, period=0.2)
        assert len(_ours(demo.pid)) == 4                 # lan, world, helper, faulty
        return demo

    demo = start("term")
    demo.send_signal(signal.SIGTERM)
    demo.wait(60)
    assert not _ours(demo.pid) and not processes_left_by(demo.pid)

    demo = start("kill")
    demo.kill()                                          # no chance to clean up
    demo.wait(10)
    assert _ours(demo.pid) and processes_left_by(demo.pid)
    removed = netns.clean_stale()                        # what every run does first
    assert set(_ours(demo.pid)) == set() and set(removed) >= {f"rason-{demo.pid}-faulty"}
    wait_until(lambda: not processes_left_by(demo.pid), "the killed run's processes gone",
               timeout=10, period=0.1)
