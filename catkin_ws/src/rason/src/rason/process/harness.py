"""Start a private ROS master and real `rosrun` nodes, and tear them all down.

One way to run ROS processes, shared by the tests, the benchmarks and the demo::

    with RosHarness() as ros:                 # roscore on a free port, private ROS_HOME
        sim = ros.rosrun("turtlebot_sim", "sim", "_world:=my_lab.yaml")
        ros.wait_for_topic("/clock")
        agent = ros.rosrun("rason", "agent", "faulty", "my_agent.asl", ns="/faulty")
        ros.wait_for_output(agent, "Moving to Destination")
    # every node and roscore have been stopped here, even if the block raised

Every process runs in its own process group (``setsid``) and is stopped as a group, so
``rosmaster`` and ``rosout`` end with ``roscore`` and nothing is orphaned. Each process's
stdout and stderr go to a log file under ``ros.log_dir`` and are kept in memory for
:meth:`RosHarness.wait_for_output`; ``echo=True`` also streams them to this process's stdout.
"""

from __future__ import annotations

import codecs
import contextlib
import itertools
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
import urllib.parse
import xmlrpc.client
from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import rospy  # for init_rospy: the observing process's own node

from rason.process.interrupts import raise_if_interrupted
from rason.process.netns import Host
from rason.process.reaper import HARNESS_ID, HARNESS_PARENT, STOP_SIGNALS, processes_carrying
from rosnode_kit.polling import Deadline, poll, watching

#: The master this process's rospy node was initialised against (rospy allows only one).
_ROSPY_MASTER: str | None = None
#: the caller id of the harness' own master calls
HARNESS_CALLER = "/rason_harness"
#: numbers this process's harnesses (their ids)
_HARNESS_COUNT = itertools.count(1)


@dataclass(frozen=True)
class Checkpoint:
    """The processes started and the parameters set at one moment (see ``rollback``)."""

    processes: int
    params: frozenset[str]


def _refuses_connections(uri: str, timeout: float = 0.5) -> bool:
    """Whether nothing listens at ``uri``'s host and port (connection refused): a node's slave
    API that is gone for sure, unlike one that is slow or on a host out of reach."""
    address = urllib.parse.urlsplit(uri)
    if not address.hostname or not address.port:
        return False
    try:
        with socket.create_connection((address.hostname, address.port), timeout=timeout):
            return False
    except ConnectionRefusedError:
        return True
    except OSError:
        return False


def _node_names(state: tuple[list, list, list]) -> set[str]:
    """The nodes named in the master's system state (publishers, subscribers, services)."""
    return {node for group in state for _, nodes in group for node in nodes}


def processes_left_by(parent_pid: int) -> list[str]:
    """Processes still running that a harness in process ``parent_pid`` started ("pid: argv").

    Every harness process carries ``RASON_HARNESS_PARENT=<pid>`` in its environment (and so do
    their children), so this finds orphans even after the parent itself is gone.
    """
    found = processes_carrying(HARNESS_PARENT, str(parent_pid), skip=(parent_pid, os.getpid()))
    return [f"{pid}: {cmd[:120]}" for pid, cmd in found.items()]


#: the signals :func:`interrupts_deferred` holds back
DEFERRED_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@contextlib.contextmanager
def interrupts_deferred() -> Iterator[None]:
    """Ctrl-C and SIGTERM that come during the block take effect when it ends.

    Around a spawn and its bookkeeping: interrupted in between (Python's subprocess can raise
    after the fork, before the child's exec), the child would run on with nobody to stop it.
    Signal handlers belong to the main thread; elsewhere the block runs as it is.

    Every handler swapped is put back, even when another signal's handler raises in the middle
    of the swap (``signal.signal`` first runs the handlers of signals already pending): a
    handler left swapped would swallow that signal for the rest of the process.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    caught: list[signal.Signals] = []

    def defer(signum: int, _frame: object) -> None:
        caught.append(signal.Signals(signum))

    previous: dict[signal.Signals, Any] = {}
    try:
        for sig in DEFERRED_SIGNALS:
            previous[sig] = signal.getsignal(sig)   # before the swap: known even if it raises
            signal.signal(sig, defer)
        yield
    finally:
        _restore_handlers(previous)
        if caught:
            handler = previous[caught[0]]
            if callable(handler):
                handler(caught[0], None)
            elif handler == signal.SIG_DFL:
                signal.raise_signal(caught[0])


def _restore_handlers(handlers: dict[signal.Signals, Any]) -> None:
    """Put every handler of ``handlers`` back (None: one not set from Python, left as it is);
    the first exception a handler raised on the way (a signal that came meanwhile, run by
    ``signal.signal`` before or after the swap) is raised once all are back."""
    raised: BaseException | None = None
    for sig, handler in handlers.items():
        while handler is not None:
            try:
                signal.signal(sig, handler)
                break
            except BaseException as exc:   # raised below, once every handler is back
                raised = raised or exc
    if raised is not None:
        raise raised


class HarnessError(RuntimeError):
    """A ROS process did not start, or something waited for did not appear in time."""

def free_port() -> int:
    """A TCP port on the loopback interface that was free a moment ago."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


#: held while one whole line goes to stdout (see :func:`echo_line`)
_STDOUT_LOCK = threading.Lock()


def echo_line(text: str) -> None:
    """Write ``text`` and its newline to stdout in one locked write, then flush. The harness's
    reader threads relay each process's lines this way, so lines of processes relayed at the
    same time (and of the caller, if it prints through here too) never splice: ``print`` writes
    the text and the newline separately, and another thread could write in between."""
    with _STDOUT_LOCK:
        sys.stdout.write(text + "\n")
        sys.stdout.flush()


#: how often a followed log file (``Process(piped=False)``) is read for new lines, in seconds
FOLLOW_PERIOD = 0.2


class Process:
    """A process started by the harness, in its own process group, its output captured.

    Its stdout and stderr go to ``log_path`` and are kept as lines. ``piped`` (default): through a
    pipe whose reader thread writes the file, woken for every line; ``piped=False``: the process
    writes the file itself and the harness follows it (every :data:`FOLLOW_PERIOD`), for
    processes that print a line per message, whose pipe reader would otherwise be woken as often
    as they are and compete with them for the CPU (the fleet benchmark's agents).
    """
    def __init__(self, name: str, argv: Sequence[str], env: dict[str, str], log_path: Path,
                 echo: bool | str = False, cwd: str | Path | None = None, piped: bool = True):
        self.name = name
        self.argv = list(argv)
        self.log_path = log_path
        self._lines: list[str] = []
        self._cond = threading.Condition()
        self._echo_prefix = echo if isinstance(echo, str) else (f"[{name}] " if echo else None)
        self._log = open(log_path, "w", encoding="utf-8")  # noqa: SIM115 - closed by the reader
        self.popen = subprocess.Popen(
            self.argv, env=env, cwd=cwd, stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE if piped else self._log, stderr=subprocess.STDOUT,
            start_new_session=True, text=True, bufsize=1, errors="replace")
        if not piped:
            self._log.close()             # the process has its own descriptor of the file
        self._reader = threading.Thread(target=self._read if piped else self._follow,
                                        name=f"log-{name}", daemon=True)
        self._reader.start()

    def _read(self) -> None:
        assert self.popen.stdout is not None
        for line in self.popen.stdout:
            line = line.rstrip("\n")
            self._log.write(line + "\n")
            self._log.flush()
            self._add([line])
        self._log.close()
        with self._cond:
            self._cond.notify_all()

    def _follow(self) -> None:
        """Read the lines the process writes to its log file, until it exits."""
        partial = ""
        # bytes through an incremental decoder: a character the process wrote in two pieces is
        # kept whole across reads (a text file's read() decodes what it has as final)
        decoder = codecs.getincrementaldecoder("utf-8")(errors="replace")
        with open(self.log_path, "rb") as log:
            while True:
                exited = self.popen.poll() is not None   # before the read: nothing is missed
                *lines, partial = (partial + decoder.decode(log.read())).split("\n")
                self._add(lines)
                if exited:
                    break
                time.sleep(FOLLOW_PERIOD)
        partial += decoder.decode(b"", final=True)
        if partial:
            self._add([partial])
        with self._cond:
            self._cond.notify_all()

    def _add(self, lines: list[str]) -> None:
        if not lines:
            return
        if self._echo_prefix is not None:
            for line in lines:
                echo_line(self._echo_prefix + line)
        with self._cond:
            self._lines.extend(lines)
            self._cond.notify_all()

    @property
    def pid(self) -> int:
        return self.popen.pid

    def alive(self) -> bool:
        """True while the process runs."""
        return self.popen.poll() is None

    def output(self) -> str:
        """Everything the process printed so far (stdout and stderr)."""
        with self._cond:
            return "\n".join(self._lines)

    def lines(self) -> list[str]:
        """A copy of the lines printed so far."""
        with self._cond:
            return list(self._lines)

    def wait_for_line(self, pattern: str | re.Pattern[str], timeout: float = 30.0,
                      start: int = 0) -> re.Match[str]:
        """Wait until a line from index `start` on matches `pattern` (re.search); return the match."""
        regex = re.compile(pattern) if isinstance(pattern, str) else pattern
        deadline = Deadline(timeout)
        index = start
        with self._cond:
            while True:
                while index < len(self._lines):
                    match = regex.search(self._lines[index])
                    index += 1
                    if match:
                        return match
                if not self.alive() and not self._reader.is_alive():
                    raise HarnessError(f"{self.name} exited ({self.popen.returncode}) before "
                                       f"printing /{regex.pattern}/; output:\n{self._tail()}")
                remaining = deadline.remaining()
                if remaining <= 0:
                    raise HarnessError(f"{self.name} did not print /{regex.pattern}/ within "
                                       f"{timeout} s; output:\n{self._tail()}")
                self._cond.wait(min(remaining, 0.5))

    def _tail(self, n: int = 30) -> str:
        return "\n".join(self._lines[-n:])

    def wait(self, timeout: float | None = None) -> int:
        """Wait for the process to exit; return its exit status."""
        status = self.popen.wait(timeout)
        self._reader.join(5)
        return status

    def signal_group(self, sig: int) -> None:
        """Send `sig` to the process's whole group, if it still exists."""
        try:
            os.killpg(self.popen.pid, sig)
        except ProcessLookupError:
            pass

    def group_alive(self) -> bool:
        """True while any process of the group exists (the leader or children it left)."""
        try:
            os.killpg(self.popen.pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:
            return True
        return True

    def stop(self, grace: float = 5.0, interrupted: bool = False) -> None:
        """Stop the whole process group: SIGINT (how ROS nodes like to stop), then SIGTERM, then
        SIGKILL. ``interrupted``: the SIGINT was sent already (:func:`stop_together`); the
        process still gets its whole ``grace`` from now."""
        for sig, wait in ((signal.SIGINT, grace), (signal.SIGTERM, 2.0), (signal.SIGKILL, 2.0)):
            if not self.group_alive():
                break
            if not (interrupted and sig == signal.SIGINT):
                self.signal_group(sig)
            poll(lambda: self.popen.poll() is not None and not self.group_alive(), wait, 0.02)
        try:
            self.popen.wait(2)
        except subprocess.TimeoutExpired:
            pass
        self._reader.join(2)


def stop_together(processes: Sequence[Process]) -> None:
    """Stop ``processes``: SIGINT to every group at once, then each :meth:`Process.stop` in turn
    (which waits its whole grace, then escalates), so that their shutdowns (a ROS node's takes
    about 0.6 s, mostly waiting) overlap instead of adding up."""
    for proc in processes:
        if proc.group_alive():
            proc.signal_group(signal.SIGINT)
    for proc in processes:
        proc.stop(interrupted=True)


class RosHarness:
    """A private roscore on a free port plus the nodes started against it.

    Args:
        sim_time: set ``/use_sim_time`` before any node starts (the simulator publishes /clock).
        echo: stream every process's output to stdout, each line prefixed with its name.
        log_dir: where process logs go (default: a fresh temporary folder, kept for reading).
        master_host: run roscore on this host of a :class:`rason.process.netns.Lan`, on port
            11311 as on a real robot network (this process must be on the LAN too:
            ``netns.enter``); nodes given ``host=`` then run on their own hosts, the others
            on the master's host.
        placement: ROS namespace -> host: ``rosrun(..., ns="/faulty")`` runs on the robot's
            own host, as a robot's nodes run on its own computer; a key ``NS/EXECUTABLE``
            (``/faulty/fault_injector``, ``/sim`` without a namespace) places one node.
    """

    def __init__(self, sim_time: bool = False, echo: bool = False,
                 log_dir: str | Path | None = None, master_host: Host | None = None,
                 placement: dict[str, Host] | None = None):
        self.sim_time = sim_time
        self.master_host = master_host
        self.placement = dict(placement or {})
        self.echo = echo
        self._own_tmp = log_dir is None
        # absolute: ROS_HOME and ROS_LOG_DIR below are read by processes in other folders
        # (rosmaster works in ROS_HOME; a node may get a cwd of its own), and a relative path
        # there gave logs under ros_home/out/... and a broken `latest` link
        self.log_dir = (Path(log_dir) if log_dir
                        else Path(tempfile.mkdtemp(prefix="rason-ros-"))).resolve()
        self.log_dir.mkdir(parents=True, exist_ok=True)
        self.port = 0
        self.master_uri = ""
        self.env: dict[str, str] = {}
        self.roscore: Process | None = None
        self.processes: list[Process] = []
        self._names: dict[str, int] = {}
        #: names this harness's processes (``RASON_HARNESS_ID``) for its reaper
        self.id = f"{os.getpid()}-{next(_HARNESS_COUNT)}"
        self._reaper: subprocess.Popen[bytes] | None = None

    # -- life cycle -------------------------------------------------------------------------
    def start(self, timeout: float = 20.0) -> RosHarness:
        """Start roscore on a free port and wait until the master answers."""
        address = self.master_host.address if self.master_host else "127.0.0.1"
        self.port = 11311 if self.master_host else free_port()
        self.master_uri = f"http://{address}:{self.port}"
        ros_home = self.log_dir / "ros_home"
        ros_home.mkdir(exist_ok=True)
        self.env = dict(os.environ)
        self.env.update(ROS_MASTER_URI=self.master_uri, ROS_IP=address,
                        ROS_HOME=str(ros_home), ROS_LOG_DIR=str(ros_home / "log"),
                        PYTHONUNBUFFERED="1", **self._tokens())
        self.env.pop("ROS_HOSTNAME", None)
        # `with RosHarness()` calls stop() only once start() has returned: whatever ends the
        # start (a timeout, Ctrl-C, SIGTERM turned into KeyboardInterrupt) stops roscore here
        try:
            self._start_reaper()
            self._launch_roscore("roscore.log", "roscore", timeout)
        except BaseException:
            self.stop()
            raise
        return self

    def attach(self, master_uri: str, timeout: float = 10.0) -> RosHarness:
        """Use a master that already runs (real robots' ``ROS_MASTER_URI``) instead of starting
        one: nodes started here join it, :meth:`stop` stops them and leaves the master and
        every other node alone. This machine's ``ROS_IP`` is kept from the environment (its
        address on the robot network; a loopback master needs none)."""
        url = urllib.parse.urlparse(master_uri)
        self.master_uri, self.port = master_uri, url.port or 11311
        ros_home = self.log_dir / "ros_home"
        ros_home.mkdir(exist_ok=True)
        self.env = dict(os.environ)
        if not self.env.get("ROS_IP"):
            if not (url.hostname or "").startswith(("127.", "localhost")):
                raise HarnessError(f"master {master_uri} is on another machine: set ROS_IP to "
                                   "this machine's address on the robot network")
            self.env["ROS_IP"] = "127.0.0.1"
        self.env.update(ROS_MASTER_URI=master_uri, ROS_HOME=str(ros_home),
                        ROS_LOG_DIR=str(ros_home / "log"), PYTHONUNBUFFERED="1",
                        **self._tokens())
        self._wait(f"the master at {master_uri}", self._master_up, timeout)
        self._start_reaper()
        return self

    def _tokens(self) -> dict[str, str]:
        """The environment that marks this harness's processes (and their children): this
        process's pid (:func:`processes_left_by`) and the harness's id (its reaper)."""
        return {HARNESS_PARENT: str(os.getpid()), HARNESS_ID: self.id}

    def _start_reaper(self) -> None:
        """Start the watcher that stops this harness's processes if this process dies without
        stopping them (:mod:`rason.process.reaper`): SIGKILL cannot be caught, and an xdist
        worker is killed so when its teardown outlasts the controller's patience."""
        if self._reaper is not None:
            return
        env = {k: v for k, v in os.environ.items() if k not in (HARNESS_PARENT, HARNESS_ID)}
        with interrupts_deferred():
            self._reaper = subprocess.Popen(
                [sys.executable, "-m", "rason.process.reaper", self.id], stdin=subprocess.PIPE,
                stdout=subprocess.DEVNULL, env=env, start_new_session=True)

    def _stop_reaper(self) -> None:
        """Close the reaper's pipe: it finds nothing left after a clean teardown and exits."""
        if self._reaper is None:
            return
        assert self._reaper.stdin is not None
        self._reaper.stdin.close()
        try:
            self._reaper.wait(sum(grace for _, grace in STOP_SIGNALS) + 5)
        except subprocess.TimeoutExpired:
            self._reaper.kill()
            self._reaper.wait()
        self._reaper = None

    def _launch_roscore(self, log_name: str, what: str, timeout: float) -> float:
        """Start roscore on ``self.port`` (on the master's host) and wait until the master
        and rosout answer; the ``time.monotonic()`` at which the master first answered."""
        argv = ["roscore", "-p", str(self.port)]
        if self.master_host:
            argv = self.master_host.command(argv)
        with interrupts_deferred():
            self.roscore = Process("roscore", argv, self.env, self.log_dir / log_name,
                                   echo=False)
        roscore = self.roscore

        def running() -> None:
            raise_if_interrupted()
            if not roscore.alive():
                raise HarnessError(f"{what} exited:\n{roscore.output()}")
        if not poll(self._master_up, timeout, 0.05, check=running):
            raise HarnessError(f"{what} did not answer within {timeout} s")
        answered = time.monotonic()
        # rosout must be up too, or the first node's log calls race it.
        self.wait_for_node("/rosout", timeout)
        if self.sim_time:
            self.set_param("/use_sim_time", True)
        return answered

    def restart_master(self, down: float = 0.0, timeout: float = 20.0) -> float:
        """Stop roscore (master and rosout), wait `down` seconds, start it again on the same
        port; the nodes keep running. Returns when the new master and rosout answer, with the
        ``time.monotonic()`` at which the new master first answered."""
        if self.roscore is None:
            raise HarnessError("no roscore to restart: call start() first")
        self.roscore.stop()
        if self.roscore.group_alive():
            raise HarnessError("roscore survived its stop")
        time.sleep(down)
        count = self._names.get("roscore", 1)
        self._names["roscore"] = count + 1
        return self._launch_roscore(f"roscore.{count}.log", "the restarted roscore", timeout)

    def stop(self) -> None:
        """Stop every node (together, see :func:`stop_together`), then roscore; leaves no
        process behind."""
        stop_together(self.processes[::-1])
        if self.roscore is not None:
            self.roscore.stop()
        self._stop_reaper()
        leftovers = [p.name for p in [*self.processes, *([self.roscore] if self.roscore else [])]
                     if p.group_alive()]
        if leftovers:
            raise HarnessError(f"processes survived teardown: {leftovers}")

    def checkpoint(self) -> Checkpoint:
        """What runs and which parameters are set now, for :meth:`rollback`."""
        return Checkpoint(processes=len(self.processes), params=frozenset(self.param_names()))

    def rollback(self, checkpoint: Checkpoint) -> None:
        """Stop the processes started since `checkpoint`, delete the parameters set since, and
        unregister the nodes that died without unregistering (:meth:`forget_dead_nodes`).

        On a master shared by many tests, a node's private parameters (``_name:=value``) stay
        after it exits and would change the next node of that name, and a killed node's topics
        stay listed, with subscribers and publishers that never connect; the rollback clears both.
        """
        try:
            self.stop_started_since(checkpoint.processes)
        finally:
            for name in sorted(set(self.param_names()) - checkpoint.params):
                self._master().deleteParam(HARNESS_CALLER, name)
            self.forget_dead_nodes()

    def stop_started_since(self, mark: int) -> None:
        """Stop the processes started after ``mark = len(ros.processes)`` (together, see
        :func:`stop_together`)."""
        started, self.processes = self.processes[mark:], self.processes[:mark]
        stop_together(started[::-1])
        leftovers = [p.name for p in started if p.group_alive()]
        if leftovers:
            raise HarnessError(f"processes survived teardown: {leftovers}")

    def __enter__(self) -> RosHarness:
        return self.start()

    def __exit__(self, *exc: object) -> None:
        self.stop()

    # -- processes ----------------------------------------------------------------------------
    def rosrun(self, package: str, executable: str, *args: str, ns: str | None = None,
               name: str | None = None, params: dict[str, object] | None = None,
               echo: bool | str | None = None, cwd: str | Path | None = None,
               host: Host | None = None, piped: bool = True,
               env: dict[str, str] | None = None) -> Process:
        """Start ``rosrun package executable args...`` (``__ns:=ns``, ``__name:=name``, ``_k:=v``)
        on ``host`` (a namespace of a Lan) or on this machine (``piped``: see :class:`Process`),
        with ``env`` added to the harness' environment."""
        argv = ["rosrun", package, executable, *args]
        if ns:
            argv.append(f"__ns:={ns}")
        if name:
            argv.append(f"__name:={name}")
        for key, value in (params or {}).items():
            argv.append(f"_{key}:={_param_text(value)}")
        label = f"{(ns or '').strip('/')}/{name or executable}".strip("/")
        if host is None:
            node_key = "/" + "/".join(p.strip("/") for p in (ns or "", executable) if p.strip("/"))
            host = self.placement.get(node_key) or (
                self.placement.get("/" + ns.strip("/")) if ns else None)
        return self.run(argv, label=label, echo=echo, cwd=cwd, env=env, host=host, piped=piped)

    def run(self, argv: Sequence[str], label: str | None = None, echo: bool | str | None = None,
            cwd: str | Path | None = None, env: dict[str, str] | None = None,
            host: Host | None = None, piped: bool = True) -> Process:
        """Start any command against this master (e.g. ``rosbag play``), managed like a node;
        on ``host`` it runs in that host's namespace with the host's ``ROS_IP`` (``piped``: see
        :class:`Process`)."""
        raise_if_interrupted()         # nothing more starts once the run was interrupted
        label = label or Path(argv[0]).name
        host = host or self.master_host
        if host is not None:
            argv = host.command(argv)
            env = {**(env or {}), **host.env(self.master_uri)}
        count = self._names.get(label, 0)
        self._names[label] = count + 1
        log_name = re.sub(r"[^\w.-]+", "_", label) + (f".{count}" if count else "") + ".log"
        with interrupts_deferred():       # a process is never running unrecorded
            proc = Process(label, argv, {**self.env, **(env or {})}, self.log_dir / log_name,
                           echo=self.echo if echo is None else echo, cwd=cwd, piped=piped)
            self.processes.append(proc)
        return proc

    def check_output(self, argv: Sequence[str], timeout: float = 30.0,
                     host: Host | None = None) -> str:
        """Run a ROS command-line tool (rostopic, rosservice...) to completion; return stdout."""
        env, host = self.env, host or self.master_host
        if host is not None:
            argv, env = host.command(argv), {**env, **host.env(self.master_uri)}
        done = subprocess.run(list(argv), env=env, capture_output=True, text=True,
                              timeout=timeout, start_new_session=True)
        if done.returncode != 0:
            raise HarnessError(f"{' '.join(argv)} failed ({done.returncode}):\n"
                               f"{done.stdout}\n{done.stderr}")
        return done.stdout

    # -- the master ---------------------------------------------------------------------------
    def _master(self) -> Any:
        """The master's XML-RPC API (its answers are untyped ``[code, message, value]`` lists)."""
        return xmlrpc.client.ServerProxy(self.master_uri)

    def _master_up(self) -> bool:
        try:
            code, _, _ = self._master().getPid(HARNESS_CALLER)
        except OSError:
            return False
        return code == 1

    def _system_state(self) -> tuple[list, list, list]:
        code, msg, state = self._master().getSystemState(HARNESS_CALLER)
        if code != 1:
            raise HarnessError(f"master: {msg}")
        return state

    def topics(self) -> dict[str, list[str]]:
        """Published topics and their publisher node names."""
        return {topic: nodes for topic, nodes in self._system_state()[0]}

    def subscribers(self, topic: str) -> list[str]:
        """The names of the nodes the master lists as subscribers of `topic` (absolute name;
        a node killed by SIGKILL stays listed until the master notices)."""
        return next((nodes for name, nodes in self._system_state()[1] if name == topic), [])

    def services(self) -> dict[str, list[str]]:
        """Advertised services and their provider node names."""
        return {srv: nodes for srv, nodes in self._system_state()[2]}

    def nodes(self) -> set[str]:
        """Names of the nodes the master knows."""
        return _node_names(self._system_state())

    def forget_dead_nodes(self) -> list[str]:
        """Unregister from the master every node whose slave API refuses connections: one that
        was killed (SIGKILL) or died before it could unregister, which the master would
        otherwise list for good (``rosnode cleanup``, without its question, and only for nodes
        known to be gone: an unreachable or slow node is kept). The names forgotten."""
        try:
            return self._forget_dead_nodes()
        except (OSError, HarnessError):
            return []                     # no master (stopped, or restarted by a test)

    def _forget_dead_nodes(self) -> list[str]:
        publishers, subscribers, services = self._system_state()
        master = self._master()
        dead: dict[str, str] = {}
        for name in sorted(_node_names((publishers, subscribers, services))):
            code, _, uri = master.lookupNode(HARNESS_CALLER, name)
            if code == 1 and _refuses_connections(uri):
                dead[name] = uri
        for topic, nodes in publishers:
            for name in set(nodes) & dead.keys():
                master.unregisterPublisher(name, topic, dead[name])
        for topic, nodes in subscribers:
            for name in set(nodes) & dead.keys():
                master.unregisterSubscriber(name, topic, dead[name])
        for service, nodes in services:
            for name in set(nodes) & dead.keys():
                code, _, service_uri = master.lookupService(HARNESS_CALLER, service)
                if code == 1:
                    master.unregisterService(name, service, service_uri)
        return sorted(dead)

    def registrations(self, node: str) -> set[str]:
        """The topics ``node`` publishes or subscribes and the services it provides."""
        return {name for group in self._system_state() for name, nodes in group if node in nodes}

    def param_names(self) -> list[str]:
        """Every parameter set on the master (leaf names)."""
        return list(self._master().getParamNames(HARNESS_CALLER)[2])

    def set_param(self, key: str, value: object) -> None:
        self._master().setParam(HARNESS_CALLER, key, value)

    def get_param(self, key: str) -> object:
        code, msg, value = self._master().getParam(HARNESS_CALLER, key)
        if code != 1:
            raise KeyError(f"{key}: {msg}")
        return value

    def _wait(self, what: str, ready: Callable[[], bool], timeout: float,
              watch: Iterable[Process] = ()) -> None:
        watcher = watching(watch, what, HarnessError)

        def check() -> None:
            raise_if_interrupted()     # a start step: an interrupt swallowed meanwhile ends it
            watcher()
        if not poll(ready, timeout, 0.05, check=check):
            raise HarnessError(f"{what} did not appear within {timeout} s")

    def wait_for_topic(self, topic: str, timeout: float = 20.0,
                       watch: Iterable[Process] = ()) -> None:
        """Wait until some node publishes `topic` (absolute name)."""
        self._wait(f"topic {topic}", lambda: topic in self.topics(), timeout, watch)

    def wait_for_subscriber(self, topic: str, timeout: float = 20.0,
                            watch: Iterable[Process] = ()) -> None:
        """Wait until some node subscribes `topic` (absolute name)."""
        self._wait(f"subscriber of {topic}", lambda: bool(self.subscribers(topic)), timeout,
                   watch)

    def wait_for_service(self, service: str, timeout: float = 20.0,
                         watch: Iterable[Process] = ()) -> None:
        """Wait until `service` (absolute name) is advertised."""
        self._wait(f"service {service}", lambda: service in self.services(), timeout, watch)

    def wait_for_node(self, node: str, timeout: float = 20.0,
                      watch: Iterable[Process] = ()) -> None:
        """Wait until the master knows a node named `node`."""
        self._wait(f"node {node}", lambda: node in self.nodes(), timeout, watch)

    # -- rospy in this process ---------------------------------------------------------------------
    def init_rospy(self, name: str = "rason_test") -> None:
        """Make this process a rospy node of this master (rospy allows one per process)."""
        os.environ.update({k: self.env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_HOME",
                                                    "ROS_LOG_DIR")})
        global _ROSPY_MASTER
        if _ROSPY_MASTER is not None:
            if self.master_uri != _ROSPY_MASTER:
                raise HarnessError("rospy is already initialised against another master "
                                   f"({_ROSPY_MASTER}); use one harness per test session")
            return
        _ROSPY_MASTER = self.master_uri
        rospy.init_node(name, anonymous=True, disable_signals=True)

    def cleanup_logs(self) -> None:
        """Remove the log folder if the harness created it."""
        if self._own_tmp:
            shutil.rmtree(self.log_dir, ignore_errors=True)


def _param_text(value: object) -> str:
    """A private parameter value as rosrun's ``_name:=value`` takes it (YAML)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (list, tuple)):
        return "[" + ",".join(_param_text(v) for v in value) + "]"
    return str(value)


def python() -> str:
    """The interpreter running this process (the project's venv one under run.sh)."""
    return sys.executable
