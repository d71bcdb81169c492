"""Fixtures shared by the whole suite.

ROS tests use real processes started by :class:`rason.process.harness.RosHarness`:

* ``ros``: the session's roscore (one per pytest run, so this process's rospy node can join it:
  rospy allows one master per process). Processes a test starts with ``ros.rosrun``/``ros.run``
  are stopped when the test ends, even when it fails; ``/use_sim_time`` is reset to false.
  Call ``ros.init_rospy()`` before using rospy in the test itself. Use a namespace of your own
  per test so topics of different tests never meet.
* ``fresh_ros``: a brand-new roscore for this test alone (no rospy in the test process).

``./run.sh test`` runs the suite on two pytest-xdist workers (``RASON_TEST_WORKERS=0``: in one
process) (``--dist loadgroup``), each with a roscore of its own. The end-to-end
runs (a simulator and agents each, see :func:`is_end_to_end`) are then one group, so one
worker runs them in turn while the other runs the rest: two of them at once would share two cores with two
robots' simulators, agents and vision each.
"""

from __future__ import annotations

import functools
import os
import re
import shutil
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from xdist.scheduler import LoadGroupScheduling

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


#: the xdist group of the CPU-heavy end-to-end tests, which one worker runs one after another
E2E_GROUP = "e2e"
#: their modules' markers (``pytestmark``): whole runs of the demo and mission (simulator,
#: agents, often a browser) and of hosts
E2E_MARKERS = frozenset({"demo", "hosts"})
#: other tests of that weight, by node id prefix: a catkin build then a demo; the agent language
#: suite again as plain Python
E2E_NODEIDS = (
    "tests/workspace/test_install_space.py",
    "tests/asl/test_asl_native.py::test_the_agent_language_suite_passes_as_plain_python_too",
)


def is_end_to_end(nodeid: str, root: Path) -> bool:
    """Whether the test ``nodeid`` (relative to ``root``) is one of the end-to-end tests; by
    node id, as xdist's controller sees only node ids."""
    return (nodeid.startswith(E2E_NODEIDS)
            or bool(E2E_MARKERS & module_marks(root / nodeid.split("::")[0])))


@functools.cache
def module_marks(path: Path) -> frozenset[str]:
    """The markers a test module's ``pytestmark = ...`` line names (none for other paths)."""
    if path.suffix != ".py" or not path.is_file():
        return frozenset()
    line = next((line for line in path.read_text(encoding="utf-8").splitlines()
                 if line.startswith("pytestmark")), "")
    return frozenset(re.findall(r"pytest\.mark\.(\w+)", line))


class E2EScheduling(LoadGroupScheduling):
    """xdist's ``loadgroup``, with the end-to-end tests as one more group.

    (``xdist_group`` marks cannot make that group with pytest 9.2: xdist 3.8 puts the group in
    the node id, which pytest 9.2 no longer lets it change; pytest-xdist issue 1386.)"""

    def _split_scope(self, nodeid: str) -> str:
        if is_end_to_end(nodeid, self.config.rootpath):
            return E2E_GROUP
        return super()._split_scope(nodeid)


@pytest.hookimpl(optionalhook=True)   # an xdist hook: absent with -p no:xdist
def pytest_xdist_make_scheduler(config: pytest.Config, log: Any) -> E2EScheduling | None:
    """``--dist loadgroup`` (as ``./run.sh test`` passes) schedules with
    :class:`E2EScheduling`."""
    return E2EScheduling(config, log) if config.getvalue("dist") == "loadgroup" else None


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


#: orphans the xdist workers reported (see ``pytest_testnodedown``), on the controller's config
_WORKER_ORPHANS = pytest.StashKey[list]()


@pytest.hookimpl(optionalhook=True)   # an xdist hook: absent with -p no:xdist
def pytest_testnodedown(node: Any, error: object) -> None:
    """On the controller: a worker is done; keep the orphans it reported (a worker that crashed
    reports none, but xdist fails the run for the crash itself)."""
    found = getattr(node, "workeroutput", {}).get("orphans", [])
    node.config.stash.setdefault(_WORKER_ORPHANS, []).extend(found)


def pytest_sessionfinish(session: pytest.Session, exitstatus: int) -> None:
    """After the suite, no roscore, rosout or node started by the harness may be left running.

    An xdist worker hands its orphans to the controller (a worker's exit status is not the
    run's), which reports them with its own and fails the run."""
    leftovers = processes_left_by(os.getpid())
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is not None:
        workeroutput["orphans"] = leftovers
        return
    leftovers += session.config.stash.get(_WORKER_ORPHANS, [])
    if leftovers:
        print("\nORPHAN ROS PROCESSES LEFT BY THE SUITE:\n  " + "\n  ".join(leftovers))
        session.exitstatus = 1
