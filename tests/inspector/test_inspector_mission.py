"""The inspector's mission view, without ROS: what an agent's beliefs say of its mission
(rason.inspector.mission), and the store putting it in the robots' view only when it changes.
The view on the page, during a real mission: tests/inspector/test_inspector_mission_browser.py."""

from __future__ import annotations

import json
from dataclasses import asdict

from rason.asl import Agent, AgentArch
from rason.asl.inspection import mind_state
from rason.inspector.mission import MAX_WAYPOINTS, mission_of
from rason.inspector.store import MAX_MISSIONS, InspectorStore

WAYPOINTS = [{"text": f"waypoint({i},{x},{y})", "sources": ["percept"]}
             for i, x, y in ((1, 2.0, -1.5), (2, 2.0, -3.0), (3, -2.0, -3.0), (4, -2, -1.5))]


def _belief(text: str, source: str = "self") -> dict:
    return {"text": text, "sources": [source]}


def test_no_waypoint_no_mission():
    assert mission_of("helper", [_belief("contract(faulty)")]) is None


def test_before_the_fault_every_waypoint_left_is_the_agents_own():
    mission = mission_of("faulty", [*WAYPOINTS, _belief("reached(1,faulty)")])
    assert mission is not None
    assert [(p.index, p.reached_by, p.assigned_to, p.current) for p in mission.waypoints] == [
        (1, "faulty", None, False), (2, None, "faulty", True), (3, None, "faulty", False),
        (4, None, "faulty", False)]
    assert (mission.waypoints[3].x, mission.waypoints[3].y) == (-2.0, -1.5)
    assert mission.recovery is None and mission.delegated_to is None and not mission.done


def test_delegated_waypoints_are_helpers_and_its_acceptance_shows():
    beliefs = [*WAYPOINTS, _belief("reached(1,faulty)"), _belief("reached(2,faulty)"),
               _belief("diagnosis(both_actuators)"), _belief("recovery(delegate)"),
               _belief("delegated(helper)")]
    offered = mission_of("faulty", beliefs)
    assert offered is not None and offered.delegated_to == "helper" and not offered.accepted
    assert (offered.diagnosis, offered.recovery) == ("both_actuators", "delegate")
    accepted = mission_of("faulty", [*beliefs, _belief("reached(3, helper)"),
                                     _belief("accept([wp(3,-2,-3),wp(4,-2,-1.5)])", "helper")])
    assert accepted is not None and accepted.accepted
    assert [(p.reached_by, p.assigned_to, p.current) for p in accepted.waypoints] == [
        ("faulty", None, False), ("faulty", None, False), ("helper", None, False),
        (None, "helper", True)]


def test_a_mission_given_up_leaves_its_waypoints_to_nobody():
    mission = mission_of("faulty", [*WAYPOINTS, _belief("reached(1,faulty)"),
                                    _belief("recovery(none)"),
                                    _belief("gaveUp(delegate_failed(bumper))")])
    assert mission is not None and mission.gave_up == "delegate_failed(bumper)"
    assert [p.assigned_to for p in mission.waypoints] == [None] * 4
    assert not any(p.current for p in mission.waypoints)
    done = mission_of("faulty", [*WAYPOINTS, *(_belief(f"reached({i},faulty)") for i in range(1, 5)),
                                 _belief("missionDone")])
    assert done is not None and done.done and not any(p.assigned_to for p in done.waypoints)


class Quiet(AgentArch):
    def console(self, agent_name: str, text: str) -> None:
        pass


def _state(agent: Agent) -> str:
    return json.dumps({"agent": agent.name, "mind": asdict(mind_state(agent))})


def test_the_store_shows_a_real_agents_mission_and_counts_only_changes():
    """An agent's mind state as rason.asl makes it: the beliefs of faulty.asl's Knowledge."""
    agent = Agent("faulty", "waypoint(1, 2.0, -1.5). waypoint(2, 2.0, -3.0). reached(1, faulty).\n"
                            "recovery(delegate). delegated(helper).", Quiet())
    agent.step()
    store = InspectorStore()
    store.agent_heard("faulty")
    store.add_state("faulty", _state(agent), 1.0)
    snapshot = store.robots.snapshot()
    mission = snapshot["missions"]["faulty"]
    assert mission["recovery"] == "delegate" and mission["delegated_to"] == "helper"
    assert [(p["index"], p["reached_by"], p["assigned_to"]) for p in mission["waypoints"]] == [
        (1, "faulty", None), (2, None, "helper")]
    store.add_state("faulty", _state(agent), 2.0)                 # the same mission again
    assert store.robots.snapshot()["version"] == snapshot["version"]
    store.agent_heard("helper")
    store.add_state("helper", json.dumps({"agent": "helper", "mind": {"beliefs": []}}), 3.0)
    assert set(store.robots.snapshot()["missions"]) == {"faulty"}


def test_the_missions_kept_are_bounded():
    store = InspectorStore()
    for k in range(MAX_MISSIONS + 5):
        name = f"a{k}"
        store.agent_heard(name)
        store.add_state(name, json.dumps({"agent": name, "mind": {"beliefs": WAYPOINTS}}), 1.0)
    missions = store.robots.snapshot()["missions"]
    assert len(missions) == MAX_MISSIONS and f"a{MAX_MISSIONS + 4}" in missions


def test_what_an_agent_believes_cannot_make_the_view_unbounded_or_invalid_json():
    odd = [_belief("waypoint(1,1e400,0)"), _belief("waypoint(2,0,-1e999)"),
           *(_belief(f"waypoint({i},1,2)") for i in range(3, 3 + 2 * MAX_WAYPOINTS))]
    mission = mission_of("faulty", odd)
    assert mission is not None and len(mission.waypoints) == MAX_WAYPOINTS
    assert mission.waypoints[0].index == 3
    json.dumps(mission.to_dict(), allow_nan=False)
