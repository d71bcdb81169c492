"""navigate.asl's detour around a stopped robot (docs/mission.md, "Recoveries implemented"),
without ROS: the mission agents' own rules, asked through the AgentSpeak interpreter. A route
takes a via point when its line passes closer than the clearance to the stopped robot, and the
line from that via point is checked again (``+!route(X, Y, K)``)."""

from __future__ import annotations

import math

from rason.asl import Agent, AgentArch, load_agent_source, parse_term
from rason.asl.terms import Var
from rason.asl.unify import resolve
from rason_diagnosis.mission import MISSION_AGENTS
from rason_diagnosis.paths import agents_dir

MISSION = agents_dir() / MISSION_AGENTS
CLEARANCE = 0.8         # m: navigate.asl's clearance(C)
STOPPED = (1.0, -2.0)   # the stopped robot (avoid(OX, OY))


def _helper_at(x: float, y: float) -> Agent:
    path = MISSION / "helper.asl"
    source = load_agent_source(path) + f"\npose({x}, {y}, 0).\n"
    return Agent("helper", source, AgentArch(), filename=str(path), source_path=[str(MISSION)])


def _via(agent: Agent, to: tuple[float, float]) -> tuple[float, float] | None:
    """The via point navigate.asl's viaPoint/6 gives from the agent's pose to `to`, if any."""
    query = f"viaPoint({to[0]}, {to[1]}, {STOPPED[0]}, {STOPPED[1]}, VX, VY)"
    for answer in agent.solve(parse_term(query), {}):
        return float(resolve(Var("VX"), answer)), float(resolve(Var("VY"), answer))
    return None


def _closest(a: tuple[float, float], b: tuple[float, float]) -> float:
    """The closest the segment a-b comes to the stopped robot."""
    (ax, ay), (bx, by), (ox, oy) = a, b, STOPPED
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((ox - ax) * dx + (oy - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(ax + t * dx - ox, ay + t * dy - oy)


def test_a_line_clear_of_the_stopped_robot_takes_no_via_point():
    assert _via(_helper_at(0.0, 0.0), (2.5, 0.0)) is None


def test_the_leg_after_a_via_point_is_checked_again_and_goes_round():
    # to the stand-in point 0.45 m beyond the stopped robot, straight through it
    start, goal = (-1.0, -2.0), (1.45, -2.0)
    via = _via(_helper_at(*start), goal)
    assert via is not None and math.isclose(math.dist(via, STOPPED), CLEARANCE, abs_tol=0.01)
    # from the via point the straight line to the goal still passes too close ...
    assert _closest(via, goal) < CLEARANCE
    second = _via(_helper_at(*via), goal)
    # ... so the route takes a second via point, on the clearance's circle, further round
    assert second is not None and math.isclose(math.dist(second, STOPPED), CLEARANCE, abs_tol=0.01)
    assert second[0] > via[0]
    legs = [(start, via), (via, second), (second, goal)]
    assert min(_closest(a, b) for a, b in legs) >= 0.45 - 1e-3
