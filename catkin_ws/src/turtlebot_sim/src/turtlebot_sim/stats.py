"""The simulator's running figures: the ``turtlebot_sim stats:`` log line, written and read.

The node logs one line every ``~stats_period`` wall seconds; benchmarks read it back from the
node's output with :func:`read_stats` (one home for the line's format).
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass

#: what starts every stats line
PREFIX = "turtlebot_sim stats:"


class Stats:
    """Running figures, logged every ``period`` wall seconds (what the benchmark reads)."""

    def __init__(self, period: float = 10.0):
        self.period = period
        self.reset(0.0)

    def reset(self, sim_time: float) -> None:
        self.wall0 = time.monotonic()
        self.sim0 = sim_time
        self.frames = 0
        self.render_ms = 0.0
        self.waited = 0.0
        self.dropped = 0          # frames not rendered because the renderer was busy (stock)

    def due(self) -> bool:
        return time.monotonic() - self.wall0 >= self.period

    def line(self, sim_time: float) -> str:
        wall = time.monotonic() - self.wall0
        sim = sim_time - self.sim0
        per_frame = self.render_ms / self.frames if self.frames else 0.0
        return (f"{PREFIX} rtf {sim / wall:.3f} sim {sim:.2f} s wall {wall:.2f} s "
                f"frames {self.frames} ({self.frames / max(sim, 1e-9):.1f}/sim s) "
                f"render {per_frame:.1f} ms/frame, waited {self.waited:.2f} s for the renderer, "
                f"dropped {self.dropped} frames")


@dataclass(frozen=True)
class StatsLine:
    """The figures of one logged stats line."""

    rtf: float            # simulated seconds per wall second
    render_ms: float      # per rendered frame
    dropped: int          # frames not rendered because the renderer was busy (stock profile)


_LINE = re.compile(r"rtf ([\d.]+) .* render ([\d.]+) ms/frame, .* dropped (\d+) frames")


def read_stats(lines: list[str]) -> list[StatsLine]:
    """The stats lines among a node's output lines, oldest first."""
    found = []
    for line in lines:
        match = _LINE.search(line) if PREFIX in line else None
        if match:
            found.append(StatsLine(float(match.group(1)), float(match.group(2)),
                                   int(match.group(3))))
    return found
