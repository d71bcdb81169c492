"""The workspace and the shared harness, with a real roscore and real rosrun processes."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading

import pytest
from polling import wait_until

from rason.process.harness import HarnessError, Process, RosHarness, processes_left_by, stop_together

pytestmark = pytest.mark.ros


def test_rosmsg_shows_the_thesis_action_fields(ros):
    out = ros.check_output(["rosmsg", "show", "jason_msgs/Action"])
    assert [line.split() for line in out.strip().splitlines()] == [
        ["string", "agent"], ["int32", "action_id"], ["string", "action"],
        ["string[]", "parameters"]]
    assert ros.check_output(["rosmsg", "show", "jason_msgs/Perception"]).split() == [
        "string", "source", "string[]", "perception"]
    assert ros.check_output(["rosmsg", "show", "jason_msgs/Event"]).split() == [
        "string", "agent", "string", "event_type", "string[]", "parameters"]


def test_rosrun_node_publishes_an_action_the_test_receives(ros):
    import rospy
    from jason_msgs.msg import Action, Event

    ros.init_rospy()
    received: list[Action] = []
    got = threading.Event()

    def on_action(msg: Action) -> None:
        received.append(msg)
        got.set()

    sub = rospy.Subscriber("/ws/jason/action", Action, on_action)
    events = rospy.Publisher("/ws/jason/event", Event, queue_size=10, latch=True)
    try:
        # the test answers as a decomposer written to the thesis alone would (no action_accepted)
        act = ros.rosrun("rason", "act", "tester", "move(1, fast)", "--id", "41",
                         "--ack-timeout", "0", ns="/ws")
        ros.wait_for_topic("/ws/jason/action", watch=[act])
        assert got.wait(15), act.output()
        msg = received[0]
        assert (msg.agent, msg.action_id, msg.action, list(msg.parameters)) == \
            ("tester", 41, "move", ["1", "fast"])

        # The real ROS command-line tools work against the node.
        echoed = ros.check_output(["rostopic", "echo", "-n", "1", "/ws/jason/action"])
        assert "agent: \"tester\"" in echoed and "action_id: 41" in echoed
        services = ros.check_output(["rosservice", "list"]).split()
        assert any(s.startswith("/ws/act") and s.endswith("/get_loggers") for s in services)

        # The node waits for the decomposer's feedback and reports it.
        events.publish(Event(agent="tester", event_type="action_feedback",
                             parameters=["OK", "41", "done"]))
        assert act.wait(15) == 0, act.output()
        assert "feedback: OK (done)" in act.output()
    finally:
        sub.unregister()
        events.unregister()


def test_subscribers_lists_the_nodes_the_master_has_for_a_topic(ros):
    import rospy
    from std_msgs.msg import Empty

    ros.init_rospy()
    topic = "/subs_probe/topic"
    assert ros.subscribers(topic) == []
    sub = rospy.Subscriber(topic, Empty, lambda _: None)
    try:
        ros.wait_for_subscriber(topic)
        assert ros.subscribers(topic) == [rospy.get_name()]
        assert ros.subscribers("/subs_probe/other") == []
    finally:
        sub.unregister()
    wait_until(lambda: ros.subscribers(topic) == [], f"{topic} left without subscribers")


def test_teardown_leaves_no_process_even_after_an_error():
    harness = RosHarness()
    pids: list[int] = []
    with pytest.raises(RuntimeError, match="boom"), harness:
        node = harness.rosrun("rason", "act", "x", "noop", "--timeout", "60")
        harness.wait_for_topic("/jason/action", watch=[node])
        pids = [harness.roscore.pid, node.pid]
        raise RuntimeError("boom")
    harness.cleanup_logs()
    for pid in pids:
        with pytest.raises(ProcessLookupError):
            os.killpg(pid, 0)


def test_a_harness_killed_before_its_teardown_leaves_no_process(tmp_path):
    """SIGKILL of the process whose harness started roscore (an xdist worker its controller
    kills after Ctrl-C while the worker's teardown still runs): its reaper stops roscore."""
    starter = subprocess.Popen(
        [sys.executable, "-c", "import sys, time; from rason.process.harness import RosHarness; "
         "RosHarness(log_dir=sys.argv[1]).start(); print('up', flush=True); time.sleep(600)",
         str(tmp_path)], stdout=subprocess.PIPE, text=True)
    try:
        assert starter.stdout is not None and starter.stdout.readline() == "up\n"
        assert len(processes_left_by(starter.pid)) >= 3, "roscore, rosmaster and rosout run"
        starter.kill()
        starter.wait(10)
        wait_until(lambda: not processes_left_by(starter.pid),
                   "end of the killed harness's roscore", timeout=30)
    finally:
        starter.kill()
        for line in processes_left_by(starter.pid):    # what a failure left, for the suite's sake
            os.kill(int(line.split(":")[0]), signal.SIGKILL)


def test_rollback_clears_the_private_parameters_a_node_left(fresh_ros):
    fresh_ros.set_param("/kept", 1)
    checkpoint = fresh_ros.checkpoint()
    node = fresh_ros.rosrun("rason", "act", "x", "noop", "--timeout", "60", "_leaked:=7",
                            ns="/leak")
    fresh_ros.wait_for_topic("/leak/jason/action", watch=[node])
    assert any(name.endswith("/leaked") for name in fresh_ros.param_names())
    fresh_ros.rollback(checkpoint)
    assert not node.alive()
    names = fresh_ros.param_names()
    assert "/kept" in names
    assert not any(name.endswith("/leaked") for name in names), names


def test_rollback_forgets_the_registrations_of_a_killed_node_only(fresh_ros):
    """The master keeps a SIGKILLed node's topics; a later test waiting for every subscriber
    of such a topic to connect would wait for a dead one. The rollback unregisters nodes whose
    slave API refuses connections, and keeps the live ones."""
    # publishers that run until stopped (`rason act` with no decomposer leaves after 2 s, which
    # a loaded machine once reached before the last assertion: the live node gone by itself)
    live = fresh_ros.rosrun("rostopic", "rostopic", "pub", "chatter", "std_msgs/String",
                            "data: alive", ns="/alive")
    fresh_ros.wait_for_topic("/alive/chatter", watch=[live])
    checkpoint = fresh_ros.checkpoint()
    killed = fresh_ros.rosrun("rostopic", "rostopic", "pub", "chatter", "std_msgs/String",
                              "data: killed", ns="/killed")
    fresh_ros.wait_for_topic("/killed/chatter", watch=[killed])
    name = next(n for n in fresh_ros.nodes() if n.startswith("/killed/"))
    assert fresh_ros.registrations(name)
    killed.signal_group(signal.SIGKILL)
    killed.wait(20)
    assert fresh_ros.registrations(name), "the master still lists the killed node"
    fresh_ros.rollback(checkpoint)
    assert not fresh_ros.registrations(name)
    assert name not in fresh_ros.nodes()
    assert "/alive/chatter" in fresh_ros.topics() and live.alive()
    assert "/rosout" in fresh_ros.nodes()


def test_waiting_for_a_topic_that_never_comes_fails_clearly(fresh_ros):
    with pytest.raises(HarnessError, match="did not appear"):
        fresh_ros.wait_for_topic("/nobody/publishes/this", timeout=0.5)


def test_a_node_that_dies_is_reported_while_waiting(fresh_ros):
    bad = fresh_ros.rosrun("rason", "act", "x", "Not An Action")
    with pytest.raises(HarnessError, match="exited"):
        fresh_ros.wait_for_topic("/jason/action", watch=[bad], timeout=20)


@pytest.mark.parametrize("piped", [True, False])
def test_a_process_output_is_kept_as_lines_and_in_its_log_file(tmp_path, piped):
    # piped=False: the process writes its log itself (no pipe), the harness follows the file;
    # "café" is written in two pieces, split inside the "é", more than a follow period apart
    script = ("import sys, time\n"
              "for k in range(5):\n"
              "    print('line', k, flush=True); time.sleep(0.05)\n"
              "print('to stderr', file=sys.stderr, flush=True)\n"
              "sys.stdout.buffer.write(b'caf\\xc3'); sys.stdout.flush(); time.sleep(0.5)\n"
              "sys.stdout.buffer.write(b'\\xa9\\n'); sys.stdout.flush()\n"
              "time.sleep(0.3)\n"
              "sys.stdout.write('no newline at the end')\n")
    proc = Process("printer", [sys.executable, "-c", script], dict(os.environ),
                   tmp_path / "printer.log", piped=piped)
    assert (proc.popen.stdout is not None) == piped
    assert proc.wait_for_line(r"line 2", timeout=10).group(0) == "line 2"
    assert proc.wait_for_line(r"to stderr", timeout=10)
    assert proc.wait(10) == 0
    expected = [f"line {k}" for k in range(5)] + ["to stderr", "café", "no newline at the end"]
    assert proc.lines() == expected
    assert (tmp_path / "printer.log").read_text(encoding="utf-8").splitlines() == expected
    with pytest.raises(HarnessError, match="exited"):
        proc.wait_for_line("never printed", timeout=5)


def test_a_relative_log_dir_keeps_every_log_under_it(tmp_path, monkeypatch):
    # the demo gives out/demo-FAULT-SEED/logs: rosmaster works in ROS_HOME and a node may run in
    # another folder, so a relative ROS_HOME once doubled the path and broke the `latest` link
    monkeypatch.chdir(tmp_path)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    with RosHarness(log_dir="out/run/logs") as harness:
        node = harness.rosrun("rason", "echo_decomposer", ns="/logs", cwd=elsewhere)
        harness.wait_for_node("/logs/echo_decomposer", timeout=60, watch=[node])
    ros_home = tmp_path / "out" / "run" / "logs" / "ros_home"
    assert harness.log_dir == ros_home.parent
    assert not (ros_home / "out").exists()
    latest = ros_home / "log" / "latest"
    assert latest.resolve().is_dir() and (latest / "master.log").is_file()
    assert list(ros_home.glob("log/**/*echo_decomposer*.log"))
    assert not list(elsewhere.iterdir())


def test_processes_stopped_together_all_get_their_sigint_before_any_exits(tmp_path):
    # on SIGINT each marks it, then waits for the marks of all three before it exits; stopped
    # one after another, the first would wait in vain and end by the SIGTERM after its grace
    marks = tmp_path / "marks"
    marks.mkdir()
    script = ("import pathlib, signal, sys, time\n"
              "marks = pathlib.Path(sys.argv[1])\n"
              "def on_sigint(sig, frame):\n"
              "    (marks / sys.argv[2]).touch()\n"
              "    deadline = time.monotonic() + 30\n"
              "    while len(list(marks.iterdir())) < 3 and time.monotonic() < deadline:\n"
              "        time.sleep(0.02)\n"
              "    print('interrupted; marks:', len(list(marks.iterdir())), flush=True)\n"
              "    sys.exit(0)\n"
              "signal.signal(signal.SIGINT, on_sigint)\n"
              "print('ready', flush=True)\n"
              "while True:\n"
              "    time.sleep(1)\n")
    procs = [Process(f"p{k}", [sys.executable, "-c", script, str(marks), f"p{k}"],
                     dict(os.environ), tmp_path / f"p{k}.log") for k in range(3)]
    for proc in procs:
        proc.wait_for_line("ready", timeout=30)
    stop_together(procs)
    assert [(proc.popen.returncode, proc.lines()[-1]) for proc in procs] == \
        [(0, "interrupted; marks: 3")] * 3
