"""Message authentication and acceptance (rason.ros.auth), without ROS."""

from __future__ import annotations

import dataclasses
import os

import pytest

from rason.ros.auth import (
    ACTION_KIND,
    AUTH_PARAMETER,
    EVENT_KIND,
    AuthKeyError,
    MessageAuth,
    SignedFields,
    TrustPolicy,
    Verdict,
    load_key,
    sign_parameters,
    split_signed,
    verify_parameters,
)

KEY = b"k" * 32
SECOND = 1_000_000_000


def fields(**changes: object) -> SignedFields:
    base = SignedFields("boss", "robot", "achieve", "go(1)", "id1", "", 100 * SECOND, "n1")
    return dataclasses.replace(base, **changes)


def test_a_signed_message_verifies_once_then_is_a_replay():
    auth = MessageAuth(KEY)
    signature = auth.sign(fields())
    assert signature.startswith("hmac-sha256:")
    assert auth.verify(fields(), signature, 101 * SECOND) is Verdict.OK
    assert auth.verify(fields(), signature, 102 * SECOND) is Verdict.REPLAYED
    other = fields(nonce="n2")
    assert MessageAuth(KEY).verify(other, auth.sign(other), 101 * SECOND) is Verdict.OK


@pytest.mark.parametrize("change", [
    {"sender": "bos"}, {"receiver": "robot2"}, {"performative": "tellHow"},
    {"content": "go(2)"}, {"reply_with": "id2"}, {"in_reply_to": "q"},
    {"stamp_ns": 100 * SECOND + 1}, {"nonce": "n9"},
    # Moving characters between fields must not keep the signature valid.
    {"sender": "bossr", "receiver": "obot"},
])
def test_any_changed_field_makes_a_forgery(change):
    auth = MessageAuth(KEY)
    signature = auth.sign(fields())
    assert auth.verify(fields(**change), signature, 100 * SECOND) is Verdict.FORGED


def test_unsigned_other_key_and_stale_messages_are_refused():
    auth = MessageAuth(KEY, window=10.0)
    assert auth.verify(fields(), "", 100 * SECOND) is Verdict.UNSIGNED
    assert auth.verify(fields(), MessageAuth(b"x" * 32).sign(fields()), 100 * SECOND) \
        is Verdict.FORGED
    assert auth.verify(fields(), auth.sign(fields()), 111 * SECOND) is Verdict.STALE
    assert auth.verify(fields(), auth.sign(fields()), 89 * SECOND) is Verdict.STALE


def test_old_nonces_are_forgotten_past_the_window():
    auth = MessageAuth(KEY, window=10.0)
    for i in range(100):
        f = fields(nonce=f"n{i}", stamp_ns=i * SECOND)
        assert auth.verify(f, auth.sign(f), i * SECOND) is Verdict.OK
    assert len(auth._seen) <= 12


def test_key_files(tmp_path):
    warnings: list[str] = []
    path = tmp_path / "k"
    path.write_text("s" * 20 + "\n")
    os.chmod(path, 0o644)
    assert load_key(path, warn=warnings.append) == b"s" * 20
    assert warnings and "chmod 600" in warnings[0]
    path.write_text("short")
    with pytest.raises(AuthKeyError, match="at least 16"):
        load_key(path)
    with pytest.raises(AuthKeyError, match="cannot read"):
        load_key(tmp_path / "none")


def test_trust_policy_leaves_untrusted_senders_only_tell_untell_and_ask():
    open_policy = TrustPolicy()
    assert open_policy.accepts("robot", "anyone", "tellHow")
    policy = TrustPolicy.of(["boss", " "])
    for performative in ("tellHow", "untellHow", "askHow", "achieve", "unachieve", "signal",
                         "madeUp", ""):
        assert not policy.accepts("robot", "mallory", performative)
        assert policy.accepts("robot", "boss", performative)
    assert policy.accepts("robot", "robot", "achieve")          # an agent may ask itself
    for performative in ("tell", "untell", "askOne", "askAll"):
        assert policy.accepts("robot", "mallory", performative)



def test_signed_action_and_event_parameters():
    """A signed Action/Event carries its signature as a last parameter; it covers the kind,
    the agent, the head and every parameter, and is checked like a message's."""
    now = 100 * SECOND
    auth = MessageAuth(KEY)
    signed = sign_parameters(auth, ACTION_KIND, "mover", "7 move", ["1", "f(a, b)"], now)
    assert signed[:2] == ["1", "f(a, b)"] and signed[2].startswith(AUTH_PARAMETER)
    assert split_signed(signed) == (["1", "f(a, b)"], signed[2])
    assert split_signed(["1"]) == (["1"], "")
    assert verify_parameters(MessageAuth(KEY), ACTION_KIND, "mover", "7 move", signed, now) \
        == (["1", "f(a, b)"], Verdict.OK)
    for kind, agent, head, params in ((EVENT_KIND, "mover", "7 move", signed),
                                      (ACTION_KIND, "other", "7 move", signed),
                                      (ACTION_KIND, "mover", "8 move", signed),
                                      (ACTION_KIND, "mover", "7 move", ["2", *signed[1:]])):
        assert verify_parameters(MessageAuth(KEY), kind, agent, head, params, now)[1] \
            is Verdict.FORGED
    fresh = MessageAuth(KEY)
    assert verify_parameters(fresh, ACTION_KIND, "mover", "7 move", signed, now)[1] is Verdict.OK
    assert verify_parameters(fresh, ACTION_KIND, "mover", "7 move", signed, now)[1] \
        is Verdict.REPLAYED
    assert verify_parameters(MessageAuth(KEY), ACTION_KIND, "mover", "7 move", signed,
                             now + 60 * SECOND)[1] is Verdict.STALE
    assert verify_parameters(auth, ACTION_KIND, "mover", "7 move", ["1"], now)[1] \
        is Verdict.UNSIGNED
    assert verify_parameters(auth, ACTION_KIND, "mover", "7 move", ["1", AUTH_PARAMETER + "x:y:z"],
                             now)[1] is Verdict.FORGED
