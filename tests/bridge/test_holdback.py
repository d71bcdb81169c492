"""rason.ros.holdback.HoldBack: messages to an agent wait for its node to subscribe (no ROS)."""

from __future__ import annotations

from rason.ros.holdback import HoldBack, Released


def test_an_agent_never_heard_from_or_whose_node_listens_gets_its_message_at_once() -> None:
    hold: HoldBack[str] = HoldBack(max_hold=3.0)
    assert hold.submit("bob", "m1", 0.0, subscribers=set()) == ["m1"]   # node unknown
    hold.heard("bob", "/bob_node")
    assert hold.submit("bob", "m2", 0.0, subscribers={"/bob_node"}) == ["m2"]
    assert hold.held() == 0


def test_messages_wait_for_the_node_to_subscribe_and_leave_in_order() -> None:
    hold: HoldBack[str] = HoldBack(max_hold=3.0)
    hold.heard("bob", "/mas")
    hold.heard("carol", "/mas")
    assert hold.submit("bob", "m1", 0.0, subscribers={"/other"}) == []
    assert hold.submit("carol", "m2", 0.1, subscribers={"/other"}) == []
    assert hold.release(1.0, subscribers={"/other"}) == []            # still not listening
    assert hold.held() == 2
    assert hold.release(1.2, subscribers={"/other", "/mas"}) == [
        Released("m1", "bob", late=False), Released("m2", "carol", late=False)]
    assert hold.held() == 0


def test_a_message_sent_when_the_node_listens_goes_after_the_ones_held_for_it() -> None:
    hold: HoldBack[str] = HoldBack(max_hold=3.0)
    hold.heard("bob", "/bob_node")
    assert hold.submit("bob", "m1", 0.0, subscribers=()) == []
    assert hold.submit("bob", "m2", 0.5, subscribers={"/bob_node"}) == ["m1", "m2"]
    assert hold.held() == 0


def test_after_max_hold_messages_leave_anyway_marked_late() -> None:
    hold: HoldBack[str] = HoldBack(max_hold=3.0)
    hold.heard("bob", "/bob_node")
    hold.submit("bob", "m1", 10.0, subscribers=())
    assert hold.release(12.9, subscribers=()) == []
    assert hold.release(13.0, subscribers=()) == [Released("m1", "bob", late=True)]
    hold.submit("bob", "m2", 20.0, subscribers=())
    # a clock that went back (simulated time restarted) does not keep them forever
    assert hold.release(5.0, subscribers=()) == [Released("m2", "bob", late=True)]


def test_an_agent_that_moved_to_another_node_is_waited_for_there() -> None:
    hold: HoldBack[str] = HoldBack(max_hold=3.0)
    hold.heard("bob", "/old")
    hold.heard("bob", "/new")
    assert hold.submit("bob", "m1", 0.0, subscribers={"/old"}) == []
    assert hold.release(0.1, subscribers={"/old", "/new"}) == [Released("m1", "bob", late=False)]
