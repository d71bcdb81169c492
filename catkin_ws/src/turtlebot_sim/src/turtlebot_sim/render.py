"""Kinect rendering in worker processes, so physics and ROS never wait on TinyRenderer.

Each worker owns a render-only copy of the scene (built from the same resolved config, so
colours and lighting match), receives the robots' base poses of one instant, renders one
robot's Kinect and sends back the RGB image and the packed XYZRGB cloud. Results come back in
submission order. With ``workers`` > 1 frames render in parallel (pipelined). The world's
camera effects (:mod:`turtlebot_sim.camera_effects`: motion blur over the exposure, auto
exposure; off by default) are applied to the colour, the blur from the camera's turn rate
between the robot's successive submitted frames.

Workers are plain subprocesses (``python -m turtlebot_sim.render FD``) talking pickled messages
over a socket pair, not ``multiprocessing`` children: nothing re-imports the caller's main
module and no resource-tracker process is left behind. They ignore SIGINT (they stay in the
caller's process group) and end when told to or when the caller's end of the socket closes.

    pool = RenderPool(world.config, workers=2)
    pool.submit(world.time, "helper", world.base_states())
    for frame in pool.collect(block=True):
        ...  # frame.stamp, frame.robot, frame.rgb (HxWx3 uint8), frame.cloud (HxWx4 float32)
    pool.close()
"""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import time
from collections import deque
from dataclasses import dataclass
from multiprocessing.connection import Connection
from pathlib import Path
from typing import Any

import numpy as np

from turtlebot_model.cloud import pack_cloud
from turtlebot_model.geometry import angle_diff_deg, yaw_from_quaternion
from turtlebot_sim.camera_effects import CameraEffects
from turtlebot_sim.world import World


@dataclass
class Frame:
    """One rendered Kinect frame, for the instant ``stamp`` (sim seconds)."""
    stamp: float
    robot: str
    rgb: np.ndarray        # HxWx3 uint8, RGB order
    cloud: np.ndarray      # HxWx4 float32: x, y, z (optical frame, NaN = no depth), packed rgb
    render_ms: float       # time the worker spent (render + noise + packing)


def _worker(conn: Connection) -> None:
    """Worker process body: get the scene, build it, then render on request until told to stop."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)   # the parent stops us (None or a closed pipe)
    cfg, index = conn.recv()
    world = World(cfg, render_only=True)
    seed = cfg["seed"] if cfg["seed"] is not None else 0
    rng = np.random.default_rng([int(seed), 2, index])
    effects = CameraEffects.from_config(cfg["camera"])
    conn.send("ready")
    while True:
        try:
            job = conn.recv()
        except (EOFError, OSError):
            break                                   # the parent went away
        if job is None:
            break
        robot, states, yaw_rate = job
        start = time.perf_counter()
        world.apply_base_states(states)
        rgb, xyz = world.render_kinect(robot, rng)
        if effects.active:
            rgb = effects.apply(rgb, yaw_rate, world.intrinsics.fx)
        cloud = pack_cloud(xyz, rgb)
        try:
            conn.send((rgb, cloud, (time.perf_counter() - start) * 1000.0))
        except OSError:
            break                                   # the parent closed the pipe
    world.close()


class RenderPool:
    """``workers`` rendering processes, at most one frame in flight per worker."""
    def __init__(self, cfg: dict[str, Any], workers: int = 2, timeout: float = 60.0):
        self._conns: list[Connection] = []
        self._procs: list[subprocess.Popen] = []
        env = dict(os.environ)
        package_root = str(Path(__file__).resolve().parents[1])
        env["PYTHONPATH"] = os.pathsep.join(
            [package_root, *filter(None, env.get("PYTHONPATH", "").split(os.pathsep))])
        self._cfg, self._env, self._timeout = cfg, env, timeout
        for index in range(max(1, workers)):
            conn, proc = self._spawn(index)
            self._conns.append(conn)
            self._procs.append(proc)
        self._pending: deque[tuple[int, float, str]] = deque()   # (worker, stamp, robot)
        self._next = 0
        self._last_yaw: dict[str, tuple[float, float]] = {}     # robot -> (stamp, yaw deg)
        for conn in self._conns:
            if not conn.poll(timeout) or conn.recv() != "ready":
                self.close()
                raise RuntimeError("a render worker did not start")

    def _spawn(self, index: int) -> tuple[Connection, subprocess.Popen]:
        """Start render worker `index`; returns its connection (not yet known to be ready)."""
        ours, theirs = socket.socketpair()
        # Blocking on both ends, whatever socket.setdefaulttimeout() says: rospy sets a default
        # timeout of 60 s once its node runs, which makes new sockets non-blocking, and the
        # worker's first read then fails with EAGAIN and the worker quits (seen as a dead worker).
        ours.setblocking(True)
        theirs.setblocking(True)
        proc = subprocess.Popen(
            [sys.executable, "-m", "turtlebot_sim.render", str(theirs.fileno())],
            pass_fds=[theirs.fileno()], stdin=subprocess.DEVNULL, env=self._env)
        theirs.close()
        conn = Connection(ours.detach())
        conn.send((self._cfg, index))
        return conn, proc

    def _respawn(self, worker: int) -> None:
        """Replace a worker that died (seen as a broken pipe) and wait until it is ready."""
        with contextlib.suppress(OSError):
            self._conns[worker].close()
        if self._procs[worker].poll() is None:
            self._procs[worker].kill()
        self._procs[worker].wait(2)
        conn, proc = self._spawn(worker)
        self._conns[worker], self._procs[worker] = conn, proc
        if not conn.poll(self._timeout) or conn.recv() != "ready":
            raise RuntimeError(f"render worker {worker} died and could not be restarted")

    @property
    def workers(self) -> int:
        return len(self._conns)

    def busy(self) -> bool:
        """True when every worker has a frame in flight (submit would have to wait)."""
        return len(self._pending) >= len(self._conns)

    def submit(self, stamp: float, robot: str, states: dict[str, Any]) -> None:
        """Queue a frame of ``robot``'s Kinect for the instant ``stamp`` with the given poses.

        Call only when not :meth:`busy` (collect first).
        """
        if self.busy():
            raise RuntimeError("all render workers busy: collect() first")
        in_use = {w for w, _, _ in self._pending}
        while self._next in in_use:
            self._next = (self._next + 1) % len(self._conns)
        worker = self._next
        self._next = (self._next + 1) % len(self._conns)
        job = (robot, states, self._yaw_rate(stamp, robot, states))
        try:
            self._conns[worker].send(job)
        except OSError:
            # A worker that crashed (it should not: see _spawn) is replaced, and the frame resent.
            print(f"turtlebot_sim: render worker {worker} died; restarting it", file=sys.stderr)
            self._respawn(worker)
            self._conns[worker].send(job)
        self._pending.append((worker, stamp, robot))

    def _yaw_rate(self, stamp: float, robot: str, states: dict[str, Any]) -> float:
        """The camera's turn rate (rad/s) since the robot's previous submitted frame (0 for the
        first, or when time did not advance)."""
        if robot not in states:
            return 0.0
        quat = states[robot][1]
        yaw = float(np.degrees(yaw_from_quaternion(*quat)))
        last = self._last_yaw.get(robot)
        self._last_yaw[robot] = (stamp, yaw)
        if last is None or stamp <= last[0]:
            return 0.0
        return float(np.radians(angle_diff_deg(yaw, last[1])) / (stamp - last[0]))

    def collect(self, block: bool = False) -> list[Frame]:
        """Finished frames in submission order; with ``block``, wait for at least one."""
        frames: list[Frame] = []
        while self._pending:
            worker, stamp, robot = self._pending[0]
            conn = self._conns[worker]
            if not (block and not frames) and not conn.poll():
                break
            rgb, cloud, ms = conn.recv()
            self._pending.popleft()
            frames.append(Frame(stamp, robot, rgb, cloud, ms))
        return frames

    def close(self) -> None:
        """Stop the workers (a worker blocked sending a frame gets a broken pipe and ends)."""
        for conn in self._conns:
            try:
                conn.send(None)
            except (OSError, ValueError):
                pass
            conn.close()
        for proc in self._procs:
            try:
                proc.wait(2)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(2)
        self._conns.clear()
        self._procs.clear()
        self._pending.clear()

    def __enter__(self) -> RenderPool:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


if __name__ == "__main__":
    os.set_blocking(int(sys.argv[1]), True)
    _worker(Connection(int(sys.argv[1])))
