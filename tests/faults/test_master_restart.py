"""The graph can restart: a rason node registers again with a restarted roscore (same port),
keeping the agent's mind, and messages, perceptions and actions flow again; so do the simulator
and the fault injector (the functional layer)."""

from __future__ import annotations

import time

import pytest
import yaml
from agent_nodes import mind, start_agent
from polling import wait_until

from rason.process.harness import HarnessError, RosHarness
from rason.process.procstat import tcp_connections

pytestmark = pytest.mark.ros

KEEPER = """
    +note(X)[source(S)] <- +kept(X); .print("kept ", X, " from ", S).
    +seen(X)[source(percept)] <- .print("seen ", X).
    +kept(2) <- move(1); .print("moved after the restart").
    """
TELLER = """
    !tell.
    +!tell : .all_names(L) & .member(keeper, L) & .member(mate, L)
       <- .send(keeper, tell, note({n})); .send(mate, tell, note({n})).
    +!tell <- .wait(200); !tell.
    """


def test_nodes_register_again_with_a_restarted_master_and_keep_the_mind(fresh_ros, tmp_path):
    ros = fresh_ros
    ns = "/restart"
    keeper = start_agent(ros, tmp_path, "keeper", KEEPER, ns=ns, ack_timeout=5.0)
    decomposer = ros.rosrun("rason", "echo_decomposer", ns=ns)
    ros.wait_for_subscriber(f"{ns}/jason/action", watch=[decomposer])
    # A mas node too: the same registration, several agents in one node.
    (tmp_path / "mate.asl").write_text(KEEPER)
    (tmp_path / "crew.mas2j").write_text("MAS crew {\n  agents: mate;\n}\n")
    crew = ros.rosrun("rason", "mas", str(tmp_path / "crew.mas2j"), ns="/restart_crew")
    ros.wait_for_service("/restart_crew/jason/mate/mind", watch=[crew])
    start_agent(ros, tmp_path, "teller1", TELLER.format(n=1), ns="/restart_teller1")
    keeper.wait_for_line(r"\[keeper\] kept 1 from teller1", timeout=30)
    assert "kept(1)[source(self)]" in mind(ros, ns, "keeper")["beliefs"]
    before = ros.nodes()

    back = ros.restart_master(down=1.0)
    minds = {f"{ns}/jason/keeper/mind", "/restart_crew/jason/mate/mind"}
    wait_until(lambda: minds <= set(ros.services()), "the minds on the restarted master", timeout=15)
    took = time.monotonic() - back
    wait_until(lambda: before <= ros.nodes(), "every node registered again", timeout=15)
    every = time.monotonic() - back
    print(f"mind services back {took:.2f} s after the new master answered; every node "
          f"({len(before)}) back after {every:.2f} s")

    # The mind survived: the belief added before the restart is still there.
    assert "kept(1)[source(self)]" in mind(ros, ns, "keeper")["beliefs"]
    # Nodes started after the restart find the old ones through the new master: a message
    # from a new agent, a perception from a new publisher, and an action to the old decomposer.
    start_agent(ros, tmp_path, "teller2", TELLER.format(n=2), ns="/restart_teller2")
    keeper.wait_for_line(r"\[keeper\] kept 2 from teller2", timeout=30)
    keeper.wait_for_line(r"\[keeper\] moved after the restart", timeout=15)
    ros.run(["rostopic", "pub", "-r", "5", f"{ns}/jason/perception", "jason_msgs/Perception",
             "{source: probe, perception: ['seen(3)']}"], label="rostopic_pub")
    keeper.wait_for_line(r"\[keeper\] seen 3", timeout=30)
    beliefs = mind(ros, ns, "keeper")["beliefs"]
    assert {"kept(1)[source(self)]", "kept(2)[source(self)]"} <= set(beliefs), beliefs
    # teller2 tells keeper and mate: mate's note may come after keeper's (mate prints nothing
    # then: its +kept(2) plan's move fails, no decomposer in its namespace)
    wait_until(lambda: "kept(2)[source(self)]" in mind(ros, "/restart_crew", "mate")["beliefs"],
               "kept(2) in mate's mind", timeout=30, period=0.5)
    assert keeper.alive() and decomposer.alive() and crew.alive()


def _kept_master_connections(ros: RosHarness, pid: int, looks: int = 8) -> set[int]:
    """The local ports of the connections to the master that process `pid` has open at every
    one of `looks` looks 0.4 s apart (the watch asks the master every second)."""
    seen = []
    for _ in range(looks):
        seen.append({c.local_port for c in tcp_connections(pid)
                     if c.remote_port == ros.port and c.established})
        time.sleep(0.4)                 # looks spread over the watch's 1 s period (its pace)
    return set.intersection(*seen)


def test_master_watch_keeps_its_connection_to_the_master(fresh_ros):
    """The watch asks over one kept-alive connection, not a new one each second (rospy may keep
    one of its own); after a restart it asks the new master over a new one, kept again."""
    ros = fresh_ros
    decomposer = ros.rosrun("rason", "echo_decomposer", ns="/watched")
    ros.wait_for_subscriber("/watched/jason/action", watch=[decomposer])
    before = ros.nodes()
    kept = _kept_master_connections(ros, decomposer.pid)
    assert kept, "no connection to the master stayed open"

    ros.restart_master(down=0.5)
    wait_until(lambda: before <= ros.nodes(), "the decomposer registered again", timeout=15)
    again = _kept_master_connections(ros, decomposer.pid)
    assert again and again.isdisjoint(kept), (kept, again)
    assert decomposer.alive()


SIM_WORLD = """\
robots:
  - {name: rebot, kind: faulty, x: 0.0, y: 0.0, yaw: 0.0}
"""


def _odom_speed(ros: RosHarness, topic: str) -> float:
    """The forward speed in the next message on `topic`, heard by a new process (it finds
    the publisher through the master)."""
    out = ros.check_output(["rostopic", "echo", "-n", "1", f"{topic}/twist/twist/linear/x"],
                           timeout=15)
    return float(yaml.safe_load(out.split("---")[0]))


def test_simulator_and_fault_injector_register_again(fresh_ros, tmp_path):
    ros = fresh_ros
    world = tmp_path / "world.yaml"
    world.write_text(SIM_WORLD)
    sim = ros.rosrun("turtlebot_sim", "sim", f"_world:={world}", "_camera_rate:=0")
    injector = ros.rosrun("kobuki_fault_injector", "fault_injector", ns="/rebot")
    ros.wait_for_service("/rebot/fault_injector", watch=[sim, injector])
    ros.wait_for_topic("/rebot/mobile_base/odom", watch=[sim, injector])
    ros.wait_for_topic("/rebot/odom", watch=[sim, injector])
    before = ros.nodes()
    assert {"/turtlebot_sim", "/rebot/fault_injector"} <= before, before

    back = ros.restart_master(down=1.0)
    wait_until(lambda: "/rebot/fault_injector" in ros.services(),
               "the injector's service on the restarted master", timeout=15)
    wait_until(lambda: before <= ros.nodes(), "the simulator and the injector back", timeout=15)
    print(f"simulator and injector back {time.monotonic() - back:.2f} s after the new master "
          "answered")

    def odometry_published() -> bool:
        topics = ros.topics()
        return ("/turtlebot_sim" in topics.get("/rebot/mobile_base/odom", [])
                and "/rebot/fault_injector" in topics.get("/rebot/odom", []))
    # a node counts as back at its first registration; its publishers follow one by one
    wait_until(odometry_published, "the odometry publishers registered again", timeout=15)

    # The service answers; a velocity command from a publisher started after the restart goes
    # through the injector (its subscription is known again) to the simulator, whose odometry
    # a new subscriber hears, directly and through the injector.
    answer = ros.check_output(["rosservice", "call", "/rebot/fault_injector", "odometry"])
    assert "odometry" in answer.lower(), answer
    answer = ros.check_output(["rosservice", "call", "/rebot/fault_injector", "cancel"])
    assert "cancel" in answer.lower(), answer
    ros.run(["rostopic", "pub", "-r", "10", "/rebot/cmd_vel", "geometry_msgs/Twist",
             "{linear: {x: 0.1}}"], label="rostopic_pub")

    def driving(topic: str) -> bool:
        try:
            return _odom_speed(ros, topic) > 0.05
        except HarnessError:
            return False
    wait_until(lambda: driving("/rebot/mobile_base/odom"), "odometry of a driving robot", timeout=30)
    wait_until(lambda: driving("/rebot/odom"), "that odometry through the injector", timeout=15)
    assert sim.alive() and injector.alive()
