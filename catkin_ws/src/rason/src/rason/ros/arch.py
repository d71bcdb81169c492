"""RosAgArch: the agent architecture that plugs a rason.asl agent into ROS (thesis 5.2).

The agent's environment is ROS: actions go out as ``jason_msgs/Action`` and come back as
``action_feedback`` Events; an action the agent gives up (its timeout, its intention dropped or
failed, the node stopping) is cancelled with ``jason_msgs/ActionCancel`` on ``jason/cancel``;
percepts come from the node's perception table; messages to other agents travel on the global
``/jason/messages`` topic. Time is ROS time, so ``/clock`` works.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import rospy

from rason.asl import AgentArch, Clock, Message, UnknownReceiver
from rason.ros.auth import TrustPolicy
from rason.ros.feedback import CancelReason, Feedback
from rason.ros.perceptions import PerceptionFilter, PerceptionTable, parse_percept
from rosnode_kit.badinput import shorten

if TYPE_CHECKING:
    from rason.asl import Agent
    from rason.asl.df import ServiceDirectory
    from rason.ros.node import RasonNode


def ros_now() -> float:
    """ROS time in seconds, as ``rospy.get_time()`` returns it, without building its objects
    under wall time (it is read for every message a node hears)."""
    if rospy.rostime.is_wallclock():
        return time.time()
    return rospy.get_time()


class RosClock(Clock):
    """ROS time (``rospy.get_time``): wall time, or the simulator's ``/clock`` with use_sim_time.

    ``waiting_until``: the deadline (ROS time) the agent's thread sleeps until under simulated
    time, else None (read by the node's frozen-clock watch).
    """

    waiting_until: float | None = None

    def now(self) -> float:
        return ros_now()

    def now_ns(self) -> int:
        if rospy.rostime.is_wallclock():
            return time.time_ns()
        return rospy.get_rostime().to_nsec()

    def wait(self, event: threading.Event, deadline: float | None) -> None:
        if deadline is None:
            event.wait()
            return
        if rospy.rostime.is_wallclock():   # ROS time is wall time: one wait, no polling
            remaining = deadline - self.now()
            if remaining > 0:
                event.wait(remaining)
            return
        # Simulated time may run faster or slower than real time: re-check it often.
        self.waiting_until = deadline
        try:
            while not event.is_set():
                remaining = deadline - self.now()
                if remaining <= 0:
                    return
                event.wait(min(remaining, 0.02))
        finally:
            self.waiting_until = None


@dataclass
class PendingAction:
    """An action issued and not yet answered (published, or held back until it can be)."""

    action_id: int
    text: str
    #: when the agent issued it (ROS time)
    sent_at: float
    accepted_at: float | None = None
    #: when it was published on jason/action (None while held back): ``~ack_timeout`` runs from
    #: here, so time spent waiting for the connections is not counted against the decomposer
    published_at: float | None = None
    #: the action term while it is held back, not yet published: no decomposer could answer it
    #: yet (an agent acting as soon as it starts acts before the connections are made)
    unheard: Any = None
    #: the beat period its decomposer announced when it accepted it (None: it does not beat)
    beat_period: float | None = None
    #: when its decomposer last said anything about it (accepted, a beat)
    heard_at: float | None = None


def ack_overdue(pending: PendingAction, now: float, ack_timeout: float,
                links_since: float) -> bool:
    """Has `pending` (not yet accepted) waited too long for a decomposer's acknowledgement?

    Published: `ack_timeout` after its publication. Held back: `ack_timeout` after both its
    issue and `links_since`, the last change in the decomposers' connections to its node.
    """
    if pending.published_at is not None:
        return now - pending.published_at > ack_timeout
    return now - max(pending.sent_at, links_since) > ack_timeout


class RosAgArch(AgentArch):
    """Architecture of one agent hosted by a :class:`RasonNode`."""

    def __init__(self, node: RasonNode, name: str,
                 perception_filter: PerceptionFilter | None = None,
                 trust: TrustPolicy | None = None):
        self.ros_clock = RosClock()
        super().__init__(self.ros_clock)
        self.node = node
        self.name = name
        self.trust = trust or TrustPolicy()
        # a function the agent's thread calls once, at the start of its next reasoning cycle
        # (see rason.ros.mind_state); None costs the cycle one attribute test
        self.at_next_cycle: Callable[[], None] | None = None
        self.perceptions: PerceptionTable = PerceptionTable(
            parse=parse_percept, warn=lambda text: rospy.logwarn("[%s] %s", name, text),
            mode=node.perception_mode, filter=perception_filter or PerceptionFilter(),
            ttl=node.perception_ttl, now=rospy.get_time)
        self.pending: dict[int, PendingAction] = {}
        self._lock = threading.Lock()
        # the decomposers' connections to this node last seen, and since when (ROS time): a
        # held-back action waits ~ack_timeout after the last change, a connection under way
        self._links: frozenset[str] = frozenset()
        self._links_since = -math.inf

    def run_at_next_cycle(self, hook: Callable[[], None]) -> None:
        """Have the agent's thread call `hook` once, at the start of its next reasoning cycle."""
        self.at_next_cycle = hook

    # -- AgentArch --------------------------------------------------------------------------------
    def perceive(self):
        if self.at_next_cycle is not None:
            hook, self.at_next_cycle = self.at_next_cycle, None
            hook()
        return self.perceptions.percepts()

    def act(self, agent: Agent, action, action_id: int) -> None:
        with self._lock:
            pending = PendingAction(action_id, str(action), self.clock.now())
            self.pending[action_id] = pending
        self.node.kick_checks()      # its timeouts are watched
        if self.node.publish_action(self.name, action_id, action):
            pending.published_at = pending.sent_at
        else:
            pending.unheard = action

    def action_abandoned(self, agent: Agent, action_id: int) -> None:
        with self._lock:
            pending = self.pending.pop(action_id, None)
        if pending is not None:
            self.node.publish_cancel(self.name, action_id, CancelReason.DROPPED)

    def send(self, agent: Agent, message: Message) -> None:
        self.node.note_message(self.name, message, outgoing=True)
        if self.node.deliver_local(message):
            return
        if not self.node.directory.knows(message.receiver, self.clock.now()):
            raise UnknownReceiver(f"no agent named '{message.receiver}' is known on the network "
                               f"(known: {', '.join(self.agent_names())})")
        self.node.publish_message(message)

    def broadcast(self, agent: Agent, message: Message) -> None:
        message.receiver = ""
        self.node.note_message(self.name, message, outgoing=True)
        self.node.deliver_local(message)
        self.node.publish_message(message)

    def agent_names(self) -> list[str]:
        return self.node.directory.names(self.clock.now())

    def service_directory(self) -> ServiceDirectory:
        return self.node.services

    def service_alive(self, agent: str) -> bool:
        return self.node.directory.knows(agent, self.clock.now())

    def create_agent(self, creator: Agent, name: str | None, source: str | None) -> str:
        """``.create_agent``: a new agent in this node."""
        return self.node.create_agent(creator, name, source)

    def kill_agent(self, name: str) -> bool:
        return self.node.kill_agent(name)

    def console(self, agent_name: str, text: str) -> None:
        self.node.console(agent_name, text)

    def output(self, text: str) -> None:
        self.node.output(text)

    def accepts(self, message: Message) -> bool:
        """Jason's message acceptance hook: may `message` reach this agent at all?"""
        return self.refusal(message) is None

    def refusal(self, message: Message) -> str | None:
        """Why `message` may not reach this agent (None: it may).

        By default senders outside the trust policy may only tell, untell and ask, and no
        message's content may call an internal action outside the node's
        ``~remote_internal_actions`` (:mod:`rason.ros.acceptance`); override in a subclass to
        decide otherwise.
        """
        if not self.trust.accepts(self.name, message.sender, message.performative):
            return "not a trusted sender"
        return self.node.remote_actions.refusal(message.performative, message.content)

    # -- from the node -------------------------------------------------------------------------------
    def on_perception(self, source: str, perceptions: list[str]) -> None:
        changed = self.perceptions.update(source, perceptions, self.clock.now())
        if changed and self.agent is not None:
            self.agent.wake()
        if changed and self.perceptions.watches_silence():
            self.node.kick_checks()  # its TTL is watched

    def needs_checks(self) -> bool:
        """Is there anything the node's periodic checks must watch for this agent: an action
        waiting for feedback, or a perception list that expires when its source goes silent?"""
        return bool(self.pending) or self.perceptions.watches_silence()

    def expire_perceptions(self, now: float) -> None:
        """Clear the sources silent for longer than their TTL (the agent gets ``-`` events)."""
        expired = self.perceptions.expire(now)
        for source in expired:   # at most one warning per source and 10 s (a CPU-starved
            # synthesizer may miss its TTL again and again)
            self.node.warnings.warn(f"ttl {shorten(source, 64)}",
                                 f"[{self.name}] perception source '{source}' silent for longer "
                                 f"than its time to live ({self.node.perception_ttl(source):g} s):"
                                 " its percepts are cleared")
        if expired and self.agent is not None:
            self.agent.wake()

    def on_accepted(self, action_id: int, beat_period: float | None = None) -> None:
        with self._lock:
            pending = self.pending.get(action_id)
            if pending is not None and pending.accepted_at is None:
                pending.accepted_at = pending.heard_at = self.clock.now()
                pending.beat_period = beat_period

    def on_running(self, action_ids: list[int]) -> None:
        """A decomposer's beat: these actions still run."""
        now = self.clock.now()
        with self._lock:
            for action_id in action_ids:
                pending = self.pending.get(action_id)
                if pending is not None:
                    pending.heard_at = now

    def on_feedback(self, feedback: Feedback) -> None:
        with self._lock:
            pending = self.pending.pop(feedback.action_id, None)
        if pending is None or self.agent is None:
            return  # not ours, or already failed by a timeout
        # called by the event subscription's receiving thread: it may reason for the agent
        if feedback.ok:
            self.agent.action_feedback(feedback.action_id, True, run_here=True)
        else:
            self.agent.action_feedback(feedback.action_id, False, feedback.result,
                                       feedback.message or f"{pending.text} failed: {feedback.result}",
                                       run_here=True)

    def check_timeouts(self, now: float, ack_timeout: float, action_timeout: float,
                       decomposer_timeout: float = 0.0) -> None:
        """Fail actions no decomposer acknowledged, accepted ones that never finished, and
        those whose decomposer's beats stopped for `decomposer_timeout` (and three beats).

        A held-back action (no decomposer connected both ways yet) is sent as soon as one is;
        it fails ``no_decomposer`` only once `ack_timeout` passed both since it was issued and
        since the decomposers' connections to this node last changed (a connection under way
        on a loaded machine is waited for, a graph with no decomposer is not). A sent action's
        `ack_timeout` runs from its publication."""
        failed: list[tuple[PendingAction, str, str]] = []
        with self._lock:
            unheard = [p for p in self.pending.values() if p.unheard is not None]
        if unheard:
            links = self.node.decomposer_links()
            if links != self._links:
                self._links, self._links_since = links, now
        for pending in unheard:      # held back: sent once a decomposer can answer them
            if self.node.publish_action(self.name, pending.action_id, pending.unheard):
                pending.unheard = None
                pending.published_at = now
        with self._lock:
            for pending in list(self.pending.values()):
                if pending.accepted_at is None and ack_timeout > 0 \
                        and ack_overdue(pending, now, ack_timeout, self._links_since):
                    failed.append((pending, CancelReason.NO_DECOMPOSER,
                                   f"no decomposer acknowledged {pending.text} within "
                                   f"{ack_timeout:g} s" + ("" if pending.published_at is not None
                                                          else " (none could hear it yet: "
                                                          "not published)")))
                elif action_timeout > 0 and now - (pending.accepted_at or pending.sent_at) \
                        > action_timeout:
                    failed.append((pending, CancelReason.ACTION_TIMEOUT,
                                   f"{pending.text} did not finish within {action_timeout:g} s"))
                elif self._decomposer_lost(pending, now, decomposer_timeout):
                    failed.append((pending, CancelReason.DECOMPOSER_LOST,
                                   f"the decomposer running {pending.text} fell silent "
                                   f"{now - (pending.heard_at or now):.1f} s ago (it announced "
                                   f"a beat every {pending.beat_period:g} s): it is gone"))
            for pending, _, _ in failed:
                del self.pending[pending.action_id]
        for pending, reason, text in failed:
            rospy.logwarn("[%s] %s", self.name, text)
            self.node.publish_cancel(self.name, pending.action_id, reason)
            if self.agent is not None:
                self.agent.action_feedback(pending.action_id, False, reason, text)

    @staticmethod
    def _decomposer_lost(pending: PendingAction, now: float, timeout: float) -> bool:
        if timeout <= 0 or pending.beat_period is None or pending.heard_at is None:
            return False
        return now - pending.heard_at > max(timeout, 3 * pending.beat_period)

    def waits_on_time(self) -> list[str]:
        """What this agent waits for that only ROS time ends: its pending actions (their
        timeouts) and its reasoning's sleep until a deadline (``.wait``...)."""
        with self._lock:
            waits = [f"action {p.text}" for p in self.pending.values()]
        deadline = self.ros_clock.waiting_until
        if deadline is not None:
            waits.append(f"a wait until {deadline:.3f} s (.wait or a timed event)")
        return waits

    def cancel_all(self, reason: str) -> int:
        """Cancel every pending action (the agent stops); how many there were."""
        with self._lock:
            ids = list(self.pending)
            self.pending.clear()
        for action_id in ids:
            self.node.publish_cancel(self.name, action_id, reason)
        return len(ids)

    def pending_actions(self) -> list[PendingAction]:
        """A copy of the actions waiting for feedback (for the published mind)."""
        with self._lock:
            return [replace(p) for p in self.pending.values()]

    def pending_texts(self) -> list[str]:
        with self._lock:
            return [f"{p.action_id}: {p.text}" + ("" if p.accepted_at is not None
                                                   else " (not yet accepted)")
                    for p in self.pending.values()]
