"""``rosrun rason_vision_tools record_bags --seed N --out DIR [--frames K]``: Kinect bags from the sim.

Renders scenarios (:mod:`rason_vision_tools.scenarios`) with ``turtlebot_sim``'s World and writes
ROS 1 bags (see :mod:`rason_vision_tools.bagio` for topics and the ground-truth JSON):

* ``--committed``: the compact set kept in the repository, ``bags/vision_sweep.bag`` (24
  frames) and ``bags/vision_cases.bag`` (7 frames); ``--seed``/``--frames`` are ignored. With
  ``--form kinect`` or ``compressed`` only the cases, as ``bags/vision_cases_<form>.bag``.
* otherwise ``K`` seeded random frames (default 200) into ``DIR/vision_seed<N>[_part<k>].bag``,
  split over ``--jobs`` processes (one bag each).

Frames are ``--period`` seconds apart in bag time (default 0.25 s, so ``rosbag play`` feeds a
node at 4 Hz). ``--compression``: bz2 (default, smallest), lz4 (fast, ROS-1-readable frames).
``--form``: raw (default: rgb8 + cloud, the simulator's), kinect (bayer_grbg8 + 16UC1 depth +
camera_info, depth stamped 0.055 s early) or compressed (JPEG + compressedDepth + camera_info);
see :mod:`rason_vision_tools.bagio`.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from rason_vision_tools.bagio import Form, Frame, write_bag
from rason_vision_tools.scenarios import Scenario, committed_cases, committed_sweep, random_scenarios, render
from turtlebot_sim.config import load as load_world

#: Bag time of the first frame (s): a fixed, plausible epoch so bags are reproducible.
START_S = 1_700_000_000


def frames_of(scenarios: Sequence[Scenario], period: float, first_index: int = 0,
              verbose: bool = False, world: dict[str, Any] | None = None) -> Iterator[Frame]:
    """Render scenarios (in `world`'s light and camera, see scenarios.world_config) into
    frames stamped ``period`` apart."""
    for i, scenario in enumerate(scenarios):
        index = first_index + i
        rgb, xyz, truth = render(scenario, world)
        truth["index"] = index
        if verbose:
            print(f"  frame {index}: {truth['case']} expect={truth['expect']}", flush=True)
        yield Frame(START_S * 10**9 + round(index * period * 1e9), rgb, xyz, truth)


Job = tuple[str, list[Scenario], float, int, str, bool, Form, "dict[str, Any] | None"]


def _record(job: Job) -> tuple[str, int]:
    path, scenarios, period, first, compression, verbose, form, world = job
    return path, write_bag(path, frames_of(scenarios, period, first, verbose, world),
                           compression, form)


def record(out: Path, seed: int, frames: int, jobs: int = 1, period: float = 0.25,
           compression: str = "bz2", committed: bool = False,
           verbose: bool = False, form: Form = Form.RAW,
           world: dict[str, Any] | None = None) -> list[Path]:
    """Record bags (in `world`'s light and camera when given); returns their paths."""
    out.mkdir(parents=True, exist_ok=True)
    if committed:
        sets = ((("vision_sweep.bag", committed_sweep()), ("vision_cases.bag", committed_cases()))
                if form is Form.RAW else ((f"vision_cases_{form.value}.bag", committed_cases()),))
        return [Path(_record((str(out / name), scenarios, period, 0, compression, verbose,
                              form, world))[0]) for name, scenarios in sets]
    scenarios = list(random_scenarios(seed, frames))
    jobs = max(1, min(jobs, len(scenarios)))
    size = -(-len(scenarios) // jobs)
    work = []
    for k in range(jobs):
        part = scenarios[k * size:(k + 1) * size]
        if part:
            name = f"vision_seed{seed}.bag" if jobs == 1 else f"vision_seed{seed}_part{k}.bag"
            work.append((str(out / name), part, period, k * size, compression, verbose, form,
                         world))
    if len(work) == 1:
        return [Path(_record(work[0])[0])]
    with multiprocessing.get_context("spawn").Pool(len(work)) as pool:
        return [Path(p) for p, _ in pool.map(_record, work)]


def main(argv: list[str] | None = None) -> int:
    """Command-line entry point."""
    parser = argparse.ArgumentParser(prog="record_bags", description=__doc__.split("\n")[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--jobs", type=int, default=1)
    parser.add_argument("--period", type=float, default=0.25)
    parser.add_argument("--compression", choices=("bz2", "lz4", "none"), default="bz2")
    parser.add_argument("--form", choices=[f.value for f in Form], default=Form.RAW.value,
                        help="the frames' form: raw (rgb8 + cloud), kinect (Bayer + 16UC1 "
                        "depth + camera_info) or compressed (JPEG + compressedDepth)")
    parser.add_argument("--world", type=Path,
                        help="render in this world file's lighting, camera, floor and room")
    parser.add_argument("--committed", action="store_true",
                        help="record the compact committed set (bags/vision_*.bag)")
    parser.add_argument("-v", "--verbose", action="store_true")
    args = parser.parse_args(argv if argv is not None else _strip_ros_args(sys.argv[1:]))
    start = time.monotonic()
    paths = record(args.out, args.seed, args.frames, args.jobs, args.period, args.compression,
                   args.committed, args.verbose, Form(args.form),
                   load_world(args.world) if args.world else None)
    for path in paths:
        print(f"wrote {path} ({path.stat().st_size / 1e6:.1f} MB)")
    print(f"done in {time.monotonic() - start:.1f} s")
    return 0


def _strip_ros_args(args: list[str]) -> list[str]:
    """Drop ROS remapping arguments (``name:=value``) rosrun may pass."""
    return [a for a in args if ":=" not in a]
