"""When an action no decomposer accepted has waited too long (#39), without ROS."""

from __future__ import annotations

import math

from rason.ros.arch import PendingAction, ack_overdue


def test_a_sent_action_gets_the_ack_timeout_from_its_publication():
    held_then_sent = PendingAction(1, "move(1)", sent_at=10.0, published_at=13.0)
    assert not ack_overdue(held_then_sent, now=14.9, ack_timeout=2.0, links_since=12.5)
    assert ack_overdue(held_then_sent, now=15.1, ack_timeout=2.0, links_since=12.5)


def test_a_held_action_waits_while_connections_come():
    held = PendingAction(1, "move(1)", sent_at=10.0)
    # no connection ever changed: ack_timeout from its issue
    assert not ack_overdue(held, now=11.9, ack_timeout=2.0, links_since=-math.inf)
    assert ack_overdue(held, now=12.1, ack_timeout=2.0, links_since=-math.inf)
    # a decomposer's connection came at 11.5: ack_timeout from then
    assert not ack_overdue(held, now=13.4, ack_timeout=2.0, links_since=11.5)
    assert ack_overdue(held, now=13.6, ack_timeout=2.0, links_since=11.5)
