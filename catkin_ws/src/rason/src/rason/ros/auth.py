"""Who may talk to an agent: signed messages and trusted senders, without rospy.

Anyone on a ROS graph can publish on ``/jason/messages`` with any ``sender``. Two independent
defences, both off by default (today's open behaviour):

* **Authentication** (:class:`MessageAuth`): agents sharing a secret key sign every message they
  publish with an HMAC-SHA256 over all its fields, its send time and a random nonce. A keyed
  agent drops messages that are unsigned, forged (the signature does not match: wrong key or
  altered fields), stale (sent longer ago than the replay window, or from the future beyond it,
  or before this node started listening) or replayed (a nonce already seen within the window).
  Seen nonces live in memory only, so a restarted node could not tell a replay of a message
  its previous run accepted: it refuses every message stamped more than ``START_GRACE`` before
  the first one it checks (a message is in flight for milliseconds; one sent before the node
  started was never meant for it). Directory registrations (performative ``df``) are the
  exception: a node publishes them latched, so a newcomer gets one sent before it started. They
  are judged by the window and the nonce only, and their publisher signs them again every half
  window (:meth:`rason.ros.node.AgentNode._publish_services`), so the latched copy stays fresh
  for as long as the node lives.
* **Acceptance** (:class:`TrustPolicy`, the model is Jason's message acceptance hook): an agent
  may name the senders it trusts; the others may only tell, untell and ask (``tell``,
  ``untell``, ``askOne``, ``askAll``): every other performative (goals, plans, signals, any
  unknown one) from them is dropped. Whatever the sender, a message never runs an internal
  action outside an allow-list (:mod:`rason.ros.acceptance`). Without authentication a sender
  name is only a claim, so use both on an untrusted network.
"""

from __future__ import annotations

import enum
import hashlib
import hmac
import json
import os
import secrets
import stat
import threading
from collections import OrderedDict
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from rason.ros.presence import DF_PERFORMATIVE

#: The only performatives a sender outside a TrustPolicy may use: they give information or ask
#: for it; every other one (achieve, unachieve, tellHow, untellHow, askHow, signal...) gives the
#: agent goals or plans.
OPEN_PERFORMATIVES = frozenset({"tell", "untell", "askOne", "askAll"})
#: Prefix of a signature: the scheme, so another one can be introduced later.
SCHEME = "hmac-sha256"
#: A key shorter than this (bytes) is refused: it would be guessable.
MIN_KEY_BYTES = 16
#: At most this many nonces are remembered (a flood cannot eat memory; the oldest go first).
MAX_NONCES = 100_000
#: s: messages stamped this long before the first one a node checks are refused as stale (they
#: predate the node: replays of what its previous run accepted); at most the window.
START_GRACE = 1.0
#: Performatives of latched state, exempt from the start rule (see the module's doc).
LATCHED_PERFORMATIVES = frozenset({DF_PERFORMATIVE})


class AuthKeyError(ValueError):
    """The key file is missing, unreadable or too short."""


class Verdict(enum.Enum):
    """What the authentication says about one received message."""

    OK = "ok"
    UNSIGNED = "unsigned"
    FORGED = "forged"
    STALE = "stale"
    REPLAYED = "replayed"


@dataclass(frozen=True)
class SignedFields:
    """The fields of an AgentMessage a signature covers (``stamp_ns``: send time, ROS time)."""

    sender: str
    receiver: str
    performative: str
    content: str
    reply_with: str
    in_reply_to: str
    stamp_ns: int
    nonce: str

    @classmethod
    def of(cls, msg: Any) -> SignedFields:
        """The signed fields of a jason_msgs/AgentMessage."""
        return cls(msg.sender, msg.receiver, msg.performative, msg.content, msg.reply_with,
                   msg.in_reply_to, msg.stamp.to_nsec(), msg.nonce)

    def canonical(self) -> bytes:
        """An unambiguous byte string of the fields (JSON array: no field can bleed into
        another, whatever characters it holds)."""
        return json.dumps([SCHEME, self.sender, self.receiver, self.performative, self.content,
                           self.reply_with, self.in_reply_to, self.stamp_ns, self.nonce],
                          ensure_ascii=False, separators=(",", ":")).encode("utf-8")


def load_key(path: str | Path, warn: Callable[[str], None] = print) -> bytes:
    """The shared key in file `path` (surrounding whitespace ignored); warns if others may
    read the file."""
    path = Path(path)
    try:
        key = path.read_bytes().strip()
        mode = path.stat().st_mode
    except OSError as err:
        raise AuthKeyError(f"cannot read the key file {path}: {err.strerror or err}") from err
    if len(key) < MIN_KEY_BYTES:
        raise AuthKeyError(f"the key in {path} is {len(key)} bytes; at least {MIN_KEY_BYTES} "
                        "are needed (e.g. `head -c 32 /dev/urandom | base64 > FILE`)")
    if mode & (stat.S_IRWXG | stat.S_IRWXO):
        warn(f"the key file {path} can be read by other users (chmod 600 {path})")
    return key


def write_new_key(path: str | Path) -> Path:
    """Write a fresh random key (32 bytes of entropy, URL-safe text) to the new file `path`,
    created readable and writable by its owner only (never wider, not even for a moment);
    FileExistsError if `path` exists."""
    path = Path(path)
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(fd, "w") as out:
        out.write(secrets.token_urlsafe(32) + "\n")
    return path


def message_auth(key_file: str, window: float,
                 warn: Callable[[str], None] = print) -> MessageAuth | None:
    """A node's authentication from its ``~auth_key_file`` and ``~auth_window`` parameters:
    None (open, no authentication) when `key_file` is empty; AuthKeyError for a bad file."""
    if not key_file:
        return None
    try:
        return MessageAuth(load_key(key_file, warn=warn), window)
    except AuthKeyError as err:
        raise AuthKeyError(f"~auth_key_file: {err}") from err


def new_nonce() -> str:
    """A random nonce for one message."""
    return secrets.token_hex(8)


class MessageAuth:
    """Signs and verifies messages with a shared key; remembers nonces for replay protection.

    Args:
        key: the shared secret.
        window: seconds a message stays acceptable after (or before, clocks differ) its stamp.
    """

    def __init__(self, key: bytes, window: float = 10.0) -> None:
        if len(key) < MIN_KEY_BYTES:
            raise AuthKeyError(f"a key needs at least {MIN_KEY_BYTES} bytes")
        self._key = key
        self.window = window
        self._seen: OrderedDict[tuple[str, str], int] = OrderedDict()   # (sender, nonce) -> stamp
        #: ROS time (ns) before which messages are refused: START_GRACE before the first check
        self.started_ns: int | None = None
        self._lock = threading.Lock()

    def sign(self, fields: SignedFields) -> str:
        digest = hmac.new(self._key, fields.canonical(), hashlib.sha256).hexdigest()
        return f"{SCHEME}:{digest}"

    def verify(self, fields: SignedFields, signature: str, now_ns: int) -> Verdict:
        """Check one received message at ROS time `now_ns`; a good one's nonce is remembered."""
        if not signature:
            return Verdict.UNSIGNED
        if not hmac.compare_digest(signature.encode("utf-8", "replace"),
                                   self.sign(fields).encode()):
            return Verdict.FORGED
        window_ns = int(self.window * 1e9)
        if abs(now_ns - fields.stamp_ns) > window_ns:
            return Verdict.STALE
        key = (fields.sender, fields.nonce)
        with self._lock:
            # the first check sets the start; so does a clock that went back (sim restarted)
            if self.started_ns is None or now_ns < self.started_ns:
                self.started_ns = now_ns - int(min(START_GRACE, self.window) * 1e9)
            if fields.stamp_ns < self.started_ns and \
                    fields.performative not in LATCHED_PERFORMATIVES:
                return Verdict.STALE
            self._forget_older_than(now_ns - window_ns)
            if key in self._seen:
                return Verdict.REPLAYED
            self._seen[key] = fields.stamp_ns
            while len(self._seen) > MAX_NONCES:
                self._seen.popitem(last=False)
        return Verdict.OK

    def _forget_older_than(self, oldest_ns: int) -> None:
        # Nonces arrive roughly in stamp order: drop from the old end until a recent one.
        while self._seen:
            key, stamp = next(iter(self._seen.items()))
            if stamp >= oldest_ns:
                break
            del self._seen[key]


@dataclass(frozen=True)
class TrustPolicy:
    """Which senders may use every performative (empty `senders` = everyone); the others
    only the :data:`OPEN_PERFORMATIVES`."""

    senders: frozenset[str] = frozenset()

    @classmethod
    def of(cls, senders: Iterable[str]) -> TrustPolicy:
        return cls(frozenset(s.strip() for s in senders if s.strip()))

    def accepts(self, receiver: str, sender: str, performative: str) -> bool:
        """Jason's acceptance hook: may `sender` send `performative` to `receiver`?"""
        if not self.senders or performative in OPEN_PERFORMATIVES:
            return True
        return sender == receiver or sender in self.senders


# -- actions and their feedback (jason/action, jason/event) -----------------------------------------
#: The last parameter of a signed Action or Event: ``#auth:<stamp ns>:<nonce>:<signature>``.
#: The thesis' messages keep their fields (and md5sums); a parameter never starts this way
#: otherwise (an action's parameters are terms, a decomposer's own come before it).
AUTH_PARAMETER = "#auth:"
#: What a signature of an action or an event covers besides its parameters (the kinds apart, so
#: a signature cannot be moved from one to the other or to an AgentMessage).
ACTION_KIND = "jason/action"
EVENT_KIND = "jason/event"


def split_signed(parameters: list[str]) -> tuple[list[str], str]:
    """An Action's or Event's parameters without their signature parameter, and it ("")."""
    if parameters and parameters[-1].startswith(AUTH_PARAMETER):
        return list(parameters[:-1]), parameters[-1]
    return list(parameters), ""


def _parameter_fields(kind: str, agent: str, head: str, parameters: list[str], stamp_ns: int,
                      nonce: str) -> SignedFields:
    return SignedFields(sender=agent, receiver=kind, performative=head,
                        content=json.dumps(parameters, ensure_ascii=False), reply_with="",
                        in_reply_to="", stamp_ns=stamp_ns, nonce=nonce)


def sign_parameters(auth: MessageAuth, kind: str, agent: str, head: str,
                    parameters: list[str], now_ns: int) -> list[str]:
    """`parameters` with a signature parameter over `kind` (ACTION_KIND, EVENT_KIND), `agent`,
    `head` (the action id and name, or the event type), the parameters, the stamp and a nonce."""
    nonce = new_nonce()
    signature = auth.sign(_parameter_fields(kind, agent, head, parameters, now_ns, nonce))
    return [*parameters, f"{AUTH_PARAMETER}{now_ns}:{nonce}:{signature}"]


def verify_parameters(auth: MessageAuth, kind: str, agent: str, head: str,
                      parameters: list[str], now_ns: int) -> tuple[list[str], Verdict]:
    """The parameters without their signature, and what the signature says (as
    :meth:`MessageAuth.verify`: UNSIGNED, FORGED, STALE, REPLAYED or OK)."""
    bare, auth_parameter = split_signed(parameters)
    if not auth_parameter:
        return bare, Verdict.UNSIGNED
    stamp, _, rest = auth_parameter[len(AUTH_PARAMETER):].partition(":")
    nonce, _, signature = rest.partition(":")
    try:
        stamp_ns = int(stamp)
    except ValueError:
        return bare, Verdict.FORGED
    fields = _parameter_fields(kind, agent, head, bare, stamp_ns, nonce)
    return bare, auth.verify(fields, signature, now_ns)
