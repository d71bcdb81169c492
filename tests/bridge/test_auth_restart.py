"""Replays across a restart and latched directory registrations (rason.ros.auth), without ROS."""

from __future__ import annotations

from rason.ros.auth import START_GRACE, MessageAuth, SignedFields, Verdict
from rason.ros.presence import DF_PERFORMATIVE

KEY = b"k" * 32
SECOND = 1_000_000_000


def signed(auth: MessageAuth, stamp_s: float, nonce: str,
           performative: str = "achieve") -> tuple[SignedFields, str]:
    f = SignedFields("boss", "robot", performative, "go", "id", "", int(stamp_s * SECOND), nonce)
    return f, auth.sign(f)


def test_a_restarted_node_refuses_what_was_signed_before_it_started():
    before = MessageAuth(KEY, window=30.0)              # the node's first run
    captured = signed(before, 100.0, "n1")
    assert before.verify(*captured, 100 * SECOND) is Verdict.OK
    after = MessageAuth(KEY, window=30.0)               # restarted: no nonce remembered
    fresh = signed(after, 105.0, "n2")
    assert after.verify(*fresh, 105 * SECOND) is Verdict.OK         # its first message
    assert after.verify(*captured, 106 * SECOND) is Verdict.STALE   # within the window, yet old
    late = signed(after, 105.0 - START_GRACE / 2, "n3")   # sent just before: in flight
    assert after.verify(*late, 106 * SECOND) is Verdict.OK
    assert after.verify(*fresh, 107 * SECOND) is Verdict.REPLAYED


def test_a_replay_as_the_first_message_after_a_restart_is_refused_too():
    after = MessageAuth(KEY, window=30.0)
    captured = signed(after, 100.0, "n1")
    assert after.verify(*captured, 103 * SECOND) is Verdict.STALE


def test_latched_directory_registrations_are_judged_by_window_and_nonce_only():
    auth = MessageAuth(KEY, window=10.0)
    assert auth.verify(*signed(auth, 200.0, "a"), 200 * SECOND) is Verdict.OK
    registration = signed(auth, 195.0, "d1", DF_PERFORMATIVE)      # latched before we started
    assert auth.verify(*registration, 200 * SECOND) is Verdict.OK
    assert auth.verify(*registration, 201 * SECOND) is Verdict.REPLAYED
    assert auth.verify(*signed(auth, 185.0, "d2", DF_PERFORMATIVE), 200 * SECOND) \
        is Verdict.STALE
    assert auth.verify(*signed(auth, 195.0, "x", "tell"), 200 * SECOND) is Verdict.STALE


def test_a_clock_that_goes_back_starts_again():
    auth = MessageAuth(KEY, window=10.0)
    assert auth.verify(*signed(auth, 500.0, "a"), 500 * SECOND) is Verdict.OK
    assert auth.verify(*signed(auth, 3.0, "b"), 3 * SECOND) is Verdict.OK      # sim restarted
    assert auth.verify(*signed(auth, 1.0, "c"), 3 * SECOND) is Verdict.STALE
