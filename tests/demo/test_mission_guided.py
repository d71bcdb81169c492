"""Guided mode's arithmetic (docs/mission.md, "Guided mode"), without ROS: the mission agents'
own rules, asked through the AgentSpeak interpreter. Helper turns a sighting into Faulty's world
pose (``worldFix``); Faulty takes a fix's centre and heading (``fixOf``) and navigates by it
(``here``, ``legLength``)."""

from __future__ import annotations

import math

import pytest

from rason.asl import Agent, AgentArch, load_agent_source, parse_term
from rason.asl.terms import Literal, Var
from rason.asl.unify import resolve
from rason_diagnosis.mission import MISSION_AGENTS
from rason_diagnosis.paths import agents_dir
from turtlebot_model.geometry import wrap_deg

MISSION = agents_dir() / MISSION_AGENTS
CAMERA_AHEAD = 0.135    # m: Helper's Kinect ahead of its centre (turtlebot_sim's KINECT_OPTICAL)


def _agent(robot: str, beliefs: list[str]) -> Agent:
    path = MISSION / f"{robot}.asl"
    source = load_agent_source(path) + "\n" + "\n".join(f"{b}." for b in beliefs)
    return Agent(robot, source, AgentArch(), filename=str(path), source_path=[str(MISSION)])


def _ask(agent: Agent, query: str, *names: str) -> list[float | str]:
    """The first answer to `query`: the values of the variables `names`."""
    for answer in agent.solve(parse_term(query), {}):
        values = [resolve(Var(name), answer) for name in names]
        return [v.functor if isinstance(v, Literal) else float(v) for v in values]
    raise AssertionError(f"no answer to {query}")


def _sighting(helper: tuple[float, float, float],
              faulty: tuple[float, float, float]) -> tuple[float, float, float]:
    """What Helper's synthesizer reports (rason_vision README): bearing (deg, clockwise), depth
    along the optical axis, yaw = Faulty's heading in the camera frame (clockwise) + bearing."""
    hx, hy, ha = helper
    fx, fy, fa = faulty
    r = math.radians(ha)
    dx, dy = fx - hx - CAMERA_AHEAD * math.cos(r), fy - hy - CAMERA_AHEAD * math.sin(r)
    depth = dx * math.cos(r) + dy * math.sin(r)
    right = dx * math.sin(r) - dy * math.cos(r)
    bearing = math.degrees(math.atan2(right, depth))
    return bearing, depth, wrap_deg(ha - fa + bearing)


@pytest.mark.parametrize("helper, faulty", [
    ((0.0, 0.0, -90.0), (0.0, -1.5, 0.0)),          # the case study's start
    ((1.0, 0.5, -60.0), (2.0, -3.0, 179.0)),
    ((-0.3, 0.2, -150.0), (-2.0, -1.5, 95.0)),
])
def test_helper_places_faulty_from_its_own_pose_and_a_sighting(helper, faulty):
    bearing, depth, yaw = _sighting(helper, faulty)
    agent = _agent("helper", [f"pose({helper[0]}, {helper[1]}, {helper[2]})"])
    x, y, a = _ask(agent, f"worldFix(pos({bearing}, {depth}, {yaw}), X, Y, A)", "X", "Y", "A")
    assert (x, y) == pytest.approx(faulty[:2], abs=1e-3)
    assert wrap_deg(a - faulty[2]) == pytest.approx(0.0, abs=1e-6)


def test_a_lone_cylinder_is_answered_with_its_colour():
    agent = _agent("helper", ["pose(0, 0, -90)"])
    _, _, colour = _ask(agent, "worldFix(part(0, 1.5, orange), X, Y, A)", "X", "Y", "A")
    assert colour == "orange"


def test_faulty_takes_the_heading_travelled_over_a_long_leg():
    # from (0.2, -2) to (1.2, -2.1): the base went a little right of +x, whatever yaw was seen
    agent = _agent("faulty", ["course(0)", "legFrom(0.2, -2.0, 1.0)"])
    x, y, a = _ask(agent, "fixOf(1.2, -2.1, 10, X, Y, A)", "X", "Y", "A")
    assert (x, y) == (1.2, -2.1)
    assert a == pytest.approx(math.degrees(math.atan2(-0.1, 1.0)), abs=0.05)


def test_faulty_takes_the_seen_yaw_after_a_short_leg():
    agent = _agent("faulty", ["course(0)", "legFrom(1.0, -2.0, 0.3)"])
    assert _ask(agent, "fixOf(1.2, -2.0, 12.5, X, Y, A)", "A") == [12.5]


@pytest.mark.parametrize("colour, centre", [("green", (1.314, -2.0)), ("orange", (1.087, -2.0))])
def test_a_lone_cylinders_centre_is_put_across_the_course(colour, centre):
    # facing +y (course 90): the left (green) cylinder is on -x of the centre, the orange on +x
    agent = _agent("faulty", ["course(90)"])
    x, y, a = _ask(agent, f"fixOf(1.2, -2.0, {colour}, X, Y, A)", "X", "Y", "A")
    assert (x, y) == pytest.approx(centre, abs=1e-3) and a == 90


def test_guided_faulty_navigates_by_its_fix_in_legs_of_at_most_guided_leg():
    agent = _agent("faulty", ["pose(0, -1.5, 0)", "fix(2.0, -3.0, 180)", "guidedBy(helper)"])
    assert _ask(agent, "here(X, Y, A)", "X", "Y", "A") == [2.0, -3.0, 180.0]
    assert _ask(agent, "legLength(4, L)", "L") == [1.5]
    assert _ask(agent, "legBudget(-2, -3, N)", "N") == [3 + math.ceil(4 / 1.5)]
