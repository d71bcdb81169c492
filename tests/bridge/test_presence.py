"""Presence: which agents are around, forgotten after a timeout (no ROS)."""

from rason.ros.presence import Directory


def test_local_agents_are_always_known_remote_ones_expire():
    directory = Directory(timeout=3.0, local=["faulty"])
    assert directory.heard("helper", now=10.0)
    assert not directory.heard("helper", now=11.0)
    assert directory.names(now=12.0) == ["faulty", "helper"]
    assert directory.knows("helper", now=14.0)
    assert not directory.knows("helper", now=14.5)
    assert directory.expire(now=14.5) == ["helper"]
    assert directory.names(now=100.0) == ["faulty"]


def test_a_returning_agent_is_new_again_and_goodbye_forgets_at_once():
    directory = Directory(timeout=1.0)
    directory.heard("a", 0.0)
    assert directory.heard("a", 5.0)
    directory.forget("a")
    assert not directory.knows("a", 5.0)
