"""Fixtures shared by the whole suite.

ROS tests use real processes started by :class:`rason.process.harness.RosHarness`:

* ``ros``: the session's roscore (one per pytest run, so this process's rospy node can join it:
  rospy allows one master per process). Processes a test starts with ``ros.rosrun``/``ros.run``
  are stopped when the test ends, even when it fails; ``/use_sim_time`` is reset to false.
  Call ``ros.init_rospy()`` before using rospy in the test itself. Use a namespace of your own
  per test so topics of different tests never meet.
* ``fresh_ros``: a brand-new roscore for this test alone (no rospy in the test process).
"""

from __future__ import annotations

import os
import shutil
from collections.abc import Iterator

import pytest

from rason.process.harness import Process, RosHarness, processes_left_by


def _ros_available() -> bool:
    return shutil.which("roscore") is not None and "ROS_PACKAGE_PATH" in os.environ


def _harness() -> Iterator[RosHarness]:
    if not _ros_available():
        pytest.fail("ROS is not set up: run the suite with ./run.sh test")
    harness = RosHarness()
    with harness:
        yield harness
    harness.cleanup_logs()


#: fixtures that start a roscore: a test using one (directly or through another fixture) gets
#: the ``ros`` marker, which ``./run.sh test --fast`` (``-m "not ros"``) leaves out
ROS_FIXTURES = frozenset({"ros", "ros_session", "fresh_ros"})


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Mark ``ros`` every test that uses a roscore fixture (files that start ROS processes
    themselves say ``pytestmark = pytest.mark.ros``)."""
    for item in items:
        if ROS_FIXTURES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.ros)


@pytest.fixture(scope="session")
def ros_session() -> Iterator[RosHarness]:
    yield from _harness()


#: the phases of a test that failed so far ("setup", "call"), for fixtures acting on a failure
_FAILED = pytest.StashKey[set]()
#: lines of each process's output printed when a test that started it fails
FAILURE_TAIL = 40


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo) -> Iterator[None]:
    """Note on the item each phase that failed (see ``_FAILED``)."""
    report = yield
    if report.failed:
        item.stash.setdefault(_FAILED, set()).add(report.when)
    return report


@pytest.fixture
def ros(ros_session: RosHarness, request: pytest.FixtureRequest) -> Iterator[RosHarness]:
    checkpoint = ros_session.checkpoint()
    ros_session.set_param("/use_sim_time", False)
    try:
        yield ros_session
    finally:
        if request.node.stash.get(_FAILED, set()):
            print_process_tails(ros_session.processes[checkpoint.processes:])
        ros_session.rollback(checkpoint)
        ros_session.set_param("/use_sim_time", False)


def print_process_tails(processes: list[Process]) -> None:
    """The last lines of each process a failed test started: they show up under "Captured
    stdout teardown" in the failure report, so a failure in CI can be read without a rerun."""
    for proc in processes:
        lines = proc.lines()
        state = "running" if proc.alive() else f"exited {proc.popen.returncode}"
        print(f"----- {proc.name} ({state}, {len(lines)} lines; last {FAILURE_TAIL}) -----")
        print("\n".join(lines[-FAILURE_TAIL:]))


@pytest.fixture
def fresh_ros() -> Iterator[RosHarness]:
    yield from _harness()


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """After the suite, no roscore, rosout or node started by the harness may be left running."""
    leftovers = processes_left_by(os.getpid())
    if leftovers:
        print("\nORPHAN ROS PROCESSES LEFT BY THE SUITE:\n  " + "\n  ".join(leftovers))
        session.exitstatus = 1
