"""The agent architecture interface (Jason's ``AgArch``), messages and clocks."""

from __future__ import annotations

import itertools
import random
import sys
import threading
import time
from typing import TYPE_CHECKING, Any

from .terms import Literal, term_str

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent
    from .df import ServiceDirectory


class Clock:
    """Injectable time source (seconds as float)."""

    def now(self) -> float:
        raise NotImplementedError

    def now_ns(self) -> int:
        """The same clock in integer nanoseconds (``.nano_time``)."""
        return int(self.now() * 1e9)

    def wait(self, event: threading.Event, deadline: float | None) -> None:
        """Block until ``event`` is set or ``now() >= deadline`` (None: only the event)."""
        raise NotImplementedError


class WallClock(Clock):
    """``time.monotonic`` based clock."""

    def now(self) -> float:
        return time.monotonic()

    def now_ns(self) -> int:
        return time.monotonic_ns()

    def wait(self, event: threading.Event, deadline: float | None) -> None:
        if deadline is None:
            event.wait()
            return
        remaining = deadline - time.monotonic()
        if remaining > 0:
            event.wait(remaining)


class VirtualClock(Clock):
    """Simulated time for tests: waiting with a deadline jumps the clock to it at once."""

    def __init__(self, start: float = 0.0) -> None:
        self._t = start
        self._lock = threading.Lock()

    def now(self) -> float:
        with self._lock:
            return self._t

    def advance(self, dt: float) -> None:
        with self._lock:
            self._t += dt

    def wait(self, event: threading.Event, deadline: float | None) -> None:
        if event.is_set():
            return
        if deadline is None:
            event.wait()
            return
        with self._lock:
            if deadline > self._t:
                self._t = deadline


_msg_ids = itertools.count(1)


def new_msg_id() -> str:
    return f"mid{next(_msg_ids)}"


class Message:
    """A message between agents (Jason's ``Message``); ``content`` is a term.

    A plain class with the methods ``@dataclass`` would make: every agent imports this module
    at start-up and ``dataclasses`` costs ~3.5 ms there (it imports ``inspect``)."""

    def __init__(self, sender: str, receiver: str, performative: str, content: Any,
                 msg_id: str | None = None, in_reply_to: str | None = None) -> None:
        self.sender = sender
        self.receiver = receiver
        self.performative = performative
        self.content = content
        self.msg_id: str = msg_id if msg_id is not None else new_msg_id()
        self.in_reply_to = in_reply_to

    def _fields(self) -> tuple:
        return (self.sender, self.receiver, self.performative, self.content, self.msg_id,
                self.in_reply_to)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self._fields() == other._fields()

    __hash__ = None  # type: ignore[assignment]  # mutable and compared by value

    def __repr__(self) -> str:
        return (f"Message(sender={self.sender!r}, receiver={self.receiver!r}, "
                f"performative={self.performative!r}, content={self.content!r}, "
                f"msg_id={self.msg_id!r}, in_reply_to={self.in_reply_to!r})")

    def __str__(self) -> str:
        r = f",{self.in_reply_to}" if self.in_reply_to else ""
        return (f"<{self.msg_id},{self.sender},{self.performative},{self.receiver},"
                f"{term_str(self.content)}{r}>")


class UnknownReceiver(Exception):
    """Raised by :meth:`AgentArch.send` when the receiver does not exist."""


class AgentArch:
    """Base architecture: the seam between an agent and its environment / infrastructure.

    Subclasses override :meth:`perceive`, :meth:`act`, :meth:`action_abandoned`, :meth:`send`,
    :meth:`broadcast`, :meth:`agent_names`, :meth:`console`, :meth:`output`.
    """

    #: Jason's ``verbose`` (the ``.mas2j`` option ``[verbose=N]``, :func:`verbosity`, and
    #: ``.verbose(N)``): 0 shows warnings only (``.print`` and ``.printf`` then write their bare
    #: text, as Jason's do when its logger shows no info), 1 the agent's messages too (the
    #: default); 2 is taken as 1 (Jason's debugging logs are not reproduced)
    verbose: int = 1

    def __init__(self, clock: Clock | None = None) -> None:
        self.clock: Clock = clock if clock is not None else WallClock()
        #: the agent this architecture serves, once its constructor has finished
        self.agent: Agent | None = None

    def attach(self, agent: Agent) -> None:
        """Serve ``agent``: called by the agent's constructor once it is built (Jason's
        ``AgArch.setTS``). An architecture serves one agent."""
        if self.agent is not None and self.agent is not agent:
            raise ValueError(f"architecture already serves agent {self.agent.name}")
        self.agent = agent

    def perceive(self) -> list[Literal] | None:
        """Current percepts; None means unchanged since the last call."""
        return None

    def act(self, agent: Agent, action: Literal, action_id: int) -> None:
        """Start an environment action; report its end with ``agent.action_feedback``."""
        # jason.infra.local.LocalAgArch.act without an environment
        agent.action_feedback(action_id, False, "action_failed", "no environment configured!",
                              annots=[Literal("noenv")])

    def action_abandoned(self, agent: Agent, action_id: int) -> None:
        """The agent no longer waits for action ``action_id``: the intention that issued it was
        dropped, or failed or finished above it. An environment stops the action here."""

    def send(self, agent: Agent, message: Message) -> None:
        raise UnknownReceiver(f"unknown receiver {message.receiver}")

    def broadcast(self, agent: Agent, message: Message) -> None:
        for name in self.agent_names():
            if name != agent.name:
                m = Message(message.sender, name, message.performative, message.content)
                self.send(agent, m)

    def agent_names(self) -> list[str]:
        return []

    def service_directory(self) -> ServiceDirectory | None:
        """The directory facilitator of this agent's host (``.df_*``), or None."""
        return None

    def service_alive(self, agent: str) -> bool:
        """Whether a provider ``.df_search`` found is still around (a host that loses agents
        from sight, as a ROS node does, says no for those)."""
        return True

    def console(self, agent_name: str, text: str) -> None:
        print(f"[{agent_name}] {text}", flush=True)

    def output(self, text: str) -> None:
        """Bare text on the console: no agent name, no new line added (``verbose=0``)."""
        sys.stdout.write(text)
        sys.stdout.flush()


def verbosity(options: dict, default: int = 1) -> int:
    """The ``verbose`` level of an agent's ``.mas2j`` options (Jason's ``Settings.setVerbose``),
    ``default`` without one; anything but a whole number is an error."""
    value = options.get("verbose")
    if value is None:
        return default
    text = str(value).strip().strip('"')
    try:
        return int(text)
    except ValueError:
        raise ValueError(f"verbose={value}: a whole number (0, 1 or 2) is expected") from None


class JavaRandom(random.Random):
    """``java.util.Random``'s generator (a 48-bit linear congruential one), so that a seeded
    agent (``.set_random_seed``, ``--seed``) draws the numbers Jason draws with that seed."""

    _MULT = 0x5DEECE66D
    _MASK = (1 << 48) - 1

    def seed(self, a: Any = None, version: int = 2) -> None:
        if a is None:
            a = random.SystemRandom().getrandbits(64)
        if not isinstance(a, int):
            a = hash(a)
        self._state = (a ^ self._MULT) & self._MASK

    def _next(self, bits: int) -> int:
        self._state = (self._state * self._MULT + 0xB) & self._MASK
        return self._state >> (48 - bits)

    def random(self) -> float:
        return ((self._next(26) << 27) + self._next(27)) * (1.0 / (1 << 53))

    def getrandbits(self, k: int) -> int:
        out, got = 0, 0
        while got < k:
            out = (out << 32) | self._next(32)
            got += 32
        return out >> (got - k)

    def getstate(self) -> Any:
        return self._state

    def setstate(self, state: Any) -> None:
        self._state = state
