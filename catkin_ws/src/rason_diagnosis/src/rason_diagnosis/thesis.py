"""The thesis' measured latencies (Morais 2015, Tables 7.1-7.4), real robots, seconds.

Each run is (fault detection, robot location, diagnosis, total); ``None`` marks the step that
never finished (encoder run 5: the only failed diagnosis, 19 of 20 correct).
"""

from __future__ import annotations

import statistics

Run = tuple[float, float | None, float | None, float | None]

TABLES: dict[str, tuple[str, list[Run]]] = {
    "both_actuators": ("Table 7.1", [
        (4.3, 14.7, 4.4, 23.4), (4.0, 14.2, 4.7, 22.9), (4.5, 13.8, 4.2, 22.5),
        (4.1, 12.4, 4.9, 21.4), (4.5, 13.1, 4.4, 22.0)]),
    "odometry": ("Table 7.2", [
        (7.1, 7.4, 7.0, 21.5), (6.7, 7.0, 6.1, 19.8), (6.6, 8.7, 5.7, 21.0),
        (7.3, 8.5, 5.8, 21.6), (7.3, 62.3, None, None), (7.7, 35.1, 5.1, 47.9),
        (6.7, 8.8, 5.9, 21.5)]),
    "left_actuator": ("Table 7.3", [
        (18.5, 0.9, 10.3, 29.7), (19.2, 1.6, 11.3, 32.1), (18.1, 2.4, 10.5, 31.0),
        (17.8, 1.4, 9.4, 28.6)]),
    "right_actuator": ("Table 7.4", [
        (17.6, 10.6, 11.3, 39.5), (18.9, 9.2, 14.2, 42.3), (16.9, 11.9, 13.1, 41.9),
        (15.6, 10.8, 12.8, 39.2)]),
}
STEPS = ("detection", "location", "diagnosis", "total")


def step_values(fault: str, step: int) -> list[float]:
    """The finished runs' values of one step."""
    return [value for run in TABLES[fault][1] if (value := run[step]) is not None]


def mean(fault: str, step: int) -> float:
    return statistics.fmean(step_values(fault, step))


def stdev(fault: str, step: int) -> float:
    values = step_values(fault, step)
    return statistics.stdev(values) if len(values) > 1 else 0.0


def successes(fault: str) -> tuple[int, int]:
    """(correct diagnoses, runs) in the thesis."""
    runs = TABLES[fault][1]
    return sum(1 for run in runs if run[3] is not None), len(runs)
