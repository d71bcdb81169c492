"""Write a decomposer in a few lines: the action protocol, timeouts, cancel and feedback done once.

A decomposer turns an agent's action (``beep(2)``) into commands for the robot. Subclass
:class:`Decomposer`, name the actions it handles and fill in what is yours::

    class Beeper(Decomposer):
        actions = ("beep",)

        def setup(self) -> None:                       # publishers, own parameters
            self.buzzer = rospy.Publisher("buzzer", Bool, queue_size=1)

        def parse(self, action: str, parameters: list[str]) -> float:
            return float(parameters[0])                # ValueError -> bad_parameters

        def start(self, goal: Goal) -> None:
            self.buzzer.publish(True)

        def step(self, goal: Goal, now: float) -> Verdict | None:
            return Verdict(OK, "beeped") if now - goal.started >= goal.target else None

        def halt(self, goal: Goal) -> None:            # every ending goes through here
            self.buzzer.publish(False)

    if __name__ == "__main__":
        run(Beeper, "beeper")

What the base does (names relative, so ``__ns:=/robot`` puts it under the robot):

* ``jason/action`` (jason_msgs/Action, in): actions named in ``actions`` (and from the agents
  in ``~agents``, if given) are parsed, acknowledged with ``action_accepted [id]`` and started;
  a ValueError/TypeError from :meth:`Decomposer.parse` answers ``bad_parameters`` instead.
  With ``exclusive`` (default) a new action preempts the running one (``preempted``).
* ``jason/event`` (jason_msgs/Event, out): ``action_feedback [RESULT, id, message]`` once per
  action, RESULT ``OK`` or a reason (:mod:`rason.execution.results`); ``action_accepted [id,
  beat period]`` and, every ``~beat_period`` while actions run, ``action_running [id...]``
  (the agent's supervision of its decomposer, see :mod:`rason.ros.feedback`).
* ``jason/cancel`` (jason_msgs/ActionCancel, in): the agent gave the action up; it is halted at
  once and ends ``cancelled``.
* ``jason/presence`` (jason_msgs/AgentMessage, in): the presence beats and goodbyes the agent
  nodes of this namespace repeat there every period (:data:`rason.ros.presence.PRESENCE_TOPIC`;
  a decomposer does not hear the fleet's messages on ``/jason/messages``, so its cost does not
  grow with the fleet; remap it with ``jason/action`` if the agent lives in another namespace).
  An agent that said
  ``goodbye``, or was heard before and then not for ``~presence_timeout`` s, has its actions
  halted and ended ``cancelled``: nothing runs for an agent that is gone. (An issuer never heard,
  such as ``rosrun rason act``, is not supervised this way.) With ``~auth_key_file`` (the
  agents' shared key, :mod:`rason.ros.auth`) only messages with a valid signature count as
  hearing an agent: a forged, unsigned, stale or replayed presence beat cannot keep a robot
  driving after its agent died. A ``goodbye`` stops the agent's actions signed or not (stopping
  is always safe, as a cancel on ``jason/cancel`` is).
* While an action runs, a timer at ``~watchdog_rate`` Hz (ROS time) calls
  :meth:`Decomposer.step` for every running action and ends the ones older than ``~timeout`` s
  (``timeout``) or whose agent went silent; with no action running it sleeps
  (:class:`rason.ros.ticker.Ticker`: nothing moves, so there is nothing to watch).

Every callback is exception-safe (:mod:`rosnode_kit.guard`); one re-entrant lock,
:attr:`Decomposer.lock`, is held around all of them, including the ones registered with
:meth:`Decomposer.subscribe`. Private parameters: :class:`DecomposerParams` (``--help`` prints
them); a decomposer with parameters of its own declares a subclass of it as ``Params`` and
reads them as ``self.params``.
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import rospy
from jason_msgs.msg import Action, ActionCancel, AgentMessage, Event

from rason.execution.results import (
    ACTION_FAILED,
    BAD_PARAMETERS,
    CANCELLED,
    OK,
    PREEMPTED,
    TIMEOUT,
    Verdict,
)
from rason.ros import fastpath
from rason.ros.auth import (
    ACTION_KIND,
    EVENT_KIND,
    SignedFields,
    message_auth,
    sign_parameters,
    split_signed,
    verify_parameters,
)
from rason.ros.auth import Verdict as Authenticity
from rason.ros.feedback import ACTION_ACCEPTED, ACTION_FEEDBACK, ACTION_RUNNING
from rason.ros.presence import GOODBYE, PRESENCE, PRESENCE_TOPIC
from rason.ros.ticker import Ticker
from rosnode_kit.badinput import shorten
from rosnode_kit.guard import RateLimitedWarnings, guarded
from rosnode_kit.master_watch import watch_master
from rosnode_kit.params import load_or_exit, param, start_node

__all__ = ["OK", "Decomposer", "DecomposerParams", "Goal", "Verdict", "run"]

#: Every action of an agent (ActionCancel.action_id).
ALL_ACTIONS = -1


@dataclass(frozen=True)
class DecomposerParams:
    """The private parameters every decomposer has."""

    agents: list[str] = param([], "handle only these agents' actions ([] = every agent)")
    timeout: float = param(0.0, "seconds an action may run before it ends 'timeout' (0 = no "
                           "limit)", minimum=0.0)
    presence_timeout: float = param(3.5, "an agent heard before and then silent this long (s) "
                                    "has its actions stopped, 'cancelled' (0 = never)",
                                    minimum=0.0)
    watchdog_rate: float = param(20.0, "Hz (ROS time) of step() and of the checks above",
                                 minimum=0.1, maximum=1000.0)
    beat_period: float = param(
        1.0, "s (ROS time) between two action_running beats on jason/event while actions run "
        "(announced in each action_accepted): an agent fails an action whose decomposer falls "
        "silent with decomposer_lost (its ~decomposer_timeout); 0 = no beats", minimum=0.0)
    auth_key_file: str = param(
        "", "the agents' shared key file (their ~auth_key_file): only messages signed with it "
        "count as an agent's presence, only actions signed with it run (the others are "
        "ignored with a warning), and every event this decomposer publishes is signed; empty "
        "= no authentication (every message counts, every action runs)")
    auth_window: float = param(
        10.0, "s (ROS time) a signed message stays acceptable after its stamp (the agents' "
        "~auth_window)", minimum=0.0)


@dataclass
class Goal:
    """One running action: who asked, what, and the decomposer's own state for it."""

    agent: str
    action_id: int
    action: str
    parameters: list[str]
    target: Any            # what parse() returned
    started: float         # ROS time (s) it was accepted
    state: Any = None      # free for the subclass

    @property
    def key(self) -> tuple[str, int]:
        return (self.agent, self.action_id)

    def __str__(self) -> str:
        """The goal for a log line, its parameters and agent name shortened (they come from
        the network)."""
        return (f"{self.action}({shorten(', '.join(self.parameters))}) of {shorten(self.agent)} "
                f"(action {self.action_id})")


class Decomposer:
    """Base class of decomposers; override :meth:`parse`, :meth:`start`, :meth:`step`,
    :meth:`halt` (and :meth:`setup` for publishers and parameters of your own)."""

    #: The actions handled (``Action.action``).
    actions: tuple[str, ...] = ()
    #: Actions answered at once by :meth:`answer` (e.g. a setting): no goal, no preemption of
    #: the running ones, only an ``action_feedback``.
    instant: tuple[str, ...] = ()
    #: One action at a time: a new one preempts the running one (False: run side by side).
    exclusive: ClassVar[bool] = True
    #: Acknowledge with ``action_accepted`` (False: a thesis-only decomposer).
    acknowledge: bool = True
    #: The private parameters (a subclass of :class:`DecomposerParams`), read as ``params``.
    Params: ClassVar[type[DecomposerParams]] = DecomposerParams

    def __init__(self) -> None:
        self.name = rospy.get_name().rsplit("/", 1)[-1]
        self.params: Any = load_or_exit(self.Params, self.name)
        self.agents: set[str] = set(self.params.agents)
        self.action_timeout: float = self.params.timeout
        self.presence_timeout: float = self.params.presence_timeout
        self.lock = threading.RLock()
        self.warnings = RateLimitedWarnings()
        self.goals: dict[tuple[str, int], Goal] = {}
        self.heard: dict[str, float] = {}          # agent -> ROS time it was last heard
        self.beat_period: float = self.params.beat_period
        self._last_beat = -1.0                     # ROS time of the last action_running beats
        self.auth = message_auth(self.params.auth_key_file, self.params.auth_window,
                                 warn=rospy.logwarn)
        if self.auth is None:
            rospy.logwarn(f"{self.name}: no ~auth_key_file: this decomposer accepts actions "
                          "from any sender on the ROS graph, and any process may keep them "
                          "running with presence beats in the agent's name")
        self.events = fastpath.publisher("jason/event", Event, queue_size=100)
        # the watchdog ticks only while an action runs: an idle decomposer's thread sleeps
        self.watchdog = Ticker(self.params.watchdog_rate, self._locked("watchdog", self._on_tick),
                               lambda: bool(self.goals), name=f"{self.name}-watchdog")
        self.setup()
        self.subscribe("jason/action", Action, self._on_action, queue_size=100)
        self.subscribe("jason/cancel", ActionCancel, self._on_cancel, queue_size=100)
        self.subscribe(PRESENCE_TOPIC, AgentMessage, self._on_message, queue_size=50)
        rospy.on_shutdown(self._on_shutdown)

    # -- to override ----------------------------------------------------------------------
    def setup(self) -> None:
        """Create publishers, subscribers (:meth:`subscribe`) and read parameters."""

    def parse(self, action: str, parameters: list[str]) -> Any:
        """The goal's target from the action's parameters; ValueError -> ``bad_parameters``."""
        return parameters

    def start(self, goal: Goal) -> Verdict | None:
        """Begin `goal`; return a Verdict to end it at once."""
        return None

    def step(self, goal: Goal, now: float) -> Verdict | None:
        """Called at ``~watchdog_rate`` (ROS time `now`); return a Verdict to end the goal."""
        return None

    def halt(self, goal: Goal) -> None:
        """Leave the actuators safe: called whenever `goal` ends, however it ends."""

    def answer(self, action: str, parameters: list[str]) -> Verdict:
        """The verdict of an :attr:`instant` action; ValueError -> ``bad_parameters``."""
        raise ValueError(f"{action} is not answered by this decomposer")

    def preempted(self, goal: Goal, by: Action) -> Verdict:
        """How `goal` ends when action `by` takes over (``exclusive`` decomposers)."""
        return Verdict(PREEMPTED, f"preempted by {by.action}({', '.join(by.parameters)}) "
                                  f"(action {by.action_id})")

    # -- for subclasses -------------------------------------------------------------------
    def subscribe(self, topic: str, msg_type: type, callback: Callable[[Any], None],
                  **kwargs: Any) -> rospy.Subscriber:
        """A subscriber whose callback runs exception-safe with :attr:`lock` held."""
        kwargs.setdefault("tcp_nodelay", True)
        return rospy.Subscriber(topic, msg_type, self._locked(topic, callback), **kwargs)

    def finish(self, goal: Goal, verdict: Verdict) -> None:
        """End `goal` (if it still runs): halt, then report ``verdict``."""
        with self.lock:
            if self.goals.get(goal.key) is not goal:
                return
            del self.goals[goal.key]
            try:
                self.halt(goal)
            except Exception as err:  # the feedback must still go out
                rospy.logerr(f"{self.name}: halt of {goal} raised {type(err).__name__}: "
                             f"{shorten(str(err))}")
            self.feedback(goal.agent, goal.action_id, verdict)

    def running(self, agent: str | None = None) -> list[Goal]:
        """The running goals (of `agent`), oldest first."""
        with self.lock:
            return [g for g in self.goals.values() if agent is None or g.agent == agent]

    def feedback(self, agent: str, action_id: int, verdict: Verdict) -> None:
        log = rospy.loginfo if verdict.ok or verdict.result == PREEMPTED else rospy.logwarn
        log(f"{self.name}: action {action_id} of {shorten(agent)} -> {verdict.result} "
            f"({shorten(verdict.message)})")
        self.publish_event(agent, ACTION_FEEDBACK,
                           [verdict.result, str(action_id), verdict.message])

    def publish_event(self, agent: str, event_type: str, parameters: list[str]) -> None:
        """An Event on jason/event, signed when this decomposer has a key."""
        if self.auth is not None:
            parameters = sign_parameters(self.auth, EVENT_KIND, agent, event_type, parameters,
                                         rospy.get_rostime().to_nsec())
        self.events.publish(Event(agent=agent, event_type=event_type, parameters=parameters))

    # -- callbacks ------------------------------------------------------------------------
    def _locked(self, what: str, callback: Callable[..., None]) -> Callable[..., None]:
        @guarded(f"{self.name} {what}", self.warnings)
        def run_locked(*args: Any) -> None:
            with self.lock:
                callback(*args)
        return run_locked

    def _on_action(self, msg: Action) -> None:
        if msg.action not in self.actions + self.instant or \
                (self.agents and msg.agent not in self.agents):
            return
        parameters = self._signed_parameters(msg)
        if parameters is None:
            return
        if msg.action in self.instant:
            try:
                verdict = self.answer(msg.action, parameters)
            except (ValueError, TypeError, IndexError) as err:
                verdict = Verdict(BAD_PARAMETERS, shorten(str(err)))
            self.feedback(msg.agent, msg.action_id, verdict)
            return
        try:
            target = self.parse(msg.action, parameters)
        except (ValueError, TypeError, IndexError) as err:
            self.feedback(msg.agent, msg.action_id, Verdict(BAD_PARAMETERS, shorten(str(err))))
            return
        if self.exclusive:
            for old in self.running():
                self.finish(old, self.preempted(old, msg))
        previous = self.goals.get((msg.agent, msg.action_id))
        if previous is not None:
            self.finish(previous, Verdict(PREEMPTED, "the same action id again"))
        goal = Goal(msg.agent, msg.action_id, msg.action, parameters, target,
                    rospy.get_time())
        self.goals[goal.key] = goal
        self.watchdog.kick()
        if self.acknowledge:
            accepted = [str(msg.action_id)]
            if self.beat_period > 0:
                accepted.append(f"{self.beat_period:g}")
            self.publish_event(msg.agent, ACTION_ACCEPTED, accepted)
        rospy.loginfo(f"{self.name}: {goal}")
        self._settle(goal, self.start, goal)

    def _signed_parameters(self, msg: Action) -> list[str] | None:
        """The action's parameters without their signature; None (and a rate-limited warning)
        when this decomposer has a key and the signature is missing or wrong: the action is
        ignored, never answered (its agent's ~ack_timeout fails it)."""
        if self.auth is None:
            return split_signed(list(msg.parameters))[0]
        parameters, verdict = verify_parameters(
            self.auth, ACTION_KIND, msg.agent, f"{msg.action_id} {msg.action}",
            list(msg.parameters), rospy.get_rostime().to_nsec())
        if verdict is Authenticity.OK:
            return parameters
        self.warnings.warn(f"{verdict.value} action {shorten(msg.agent, 64)}",
                           f"{self.name}: ignored a {verdict.value} action "
                           f"{shorten(msg.action, 32)} claiming to be from "
                           f"'{shorten(msg.agent, 64)}' (not signed with ~auth_key_file)")
        return None

    def _on_cancel(self, msg: ActionCancel) -> None:
        reason = shorten(msg.reason or "no reason given", 100)
        for goal in self.running(msg.agent):
            if msg.action_id in (goal.action_id, ALL_ACTIONS):
                self.finish(goal, Verdict(CANCELLED, f"cancelled by {msg.agent}: {reason}"))

    def _on_message(self, msg: AgentMessage) -> None:
        if msg.performative == PRESENCE and msg.content == GOODBYE:
            self.heard.pop(msg.sender, None)
            for goal in self.running(msg.sender):
                self.finish(goal, Verdict(CANCELLED, f"agent {msg.sender} said goodbye"))
            return
        if msg.sender and self._authentic(msg):
            now = rospy.get_time()
            self.heard[msg.sender] = now
            self._forget_long_gone(now)

    def _authentic(self, msg: AgentMessage) -> bool:
        """True without a key; with one, True only for a message with a valid signature."""
        if self.auth is None:
            return True
        verdict = self.auth.verify(SignedFields.of(msg), msg.signature,
                                   rospy.get_rostime().to_nsec())
        if verdict is Authenticity.OK:
            return True
        self.warnings.warn(f"{verdict.value} {shorten(msg.sender, 64)}",
                           f"{self.name}: ignored a {verdict.value} "
                           f"{shorten(msg.performative, 32) or '?'} message claiming to be "
                           f"from '{shorten(msg.sender, 64)}' (it does not count as its "
                           "presence)")
        return False

    def _on_tick(self) -> None:
        now = rospy.get_time()
        for goal in self.running():
            verdict = self._supervision(goal, now)
            if verdict is not None:
                self.finish(goal, verdict)
            else:
                self._settle(goal, self.step, goal, now)
        self._beat(now)

    def _beat(self, now: float) -> None:
        """Every ``~beat_period``, tell each agent which of its actions still run here."""
        if not self.acknowledge or self.beat_period <= 0 or \
                0 <= now - self._last_beat < self.beat_period:
            return
        self._last_beat = now
        by_agent: dict[str, list[str]] = {}
        for goal in self.running():
            by_agent.setdefault(goal.agent, []).append(str(goal.action_id))
        for agent, ids in by_agent.items():
            self.publish_event(agent, ACTION_RUNNING, ids)

    def _forget_long_gone(self, now: float) -> None:
        """Forget the agents not heard for four presence timeouts that run nothing here
        (bounded memory)."""
        if self.presence_timeout > 0 and len(self.heard) > 1:
            busy = {g.agent for g in self.goals.values()}
            for agent, last in list(self.heard.items()):
                if agent not in busy and now - last > 4 * self.presence_timeout:
                    del self.heard[agent]

    def _supervision(self, goal: Goal, now: float) -> Verdict | None:
        """A verdict when nobody supervises `goal` any more or it ran out of time."""
        if self.action_timeout > 0 and now - goal.started > self.action_timeout:
            return Verdict(TIMEOUT, f"{goal.action} did not finish within "
                                    f"{self.action_timeout:g} s")
        last = self.heard.get(goal.agent)
        if self.presence_timeout > 0 and last is not None \
                and now - last > self.presence_timeout:
            return Verdict(CANCELLED, f"agent {goal.agent} not heard for {now - last:.2f} s")
        return None

    def _settle(self, goal: Goal, hook: Callable[..., Verdict | None], *args: Any) -> None:
        """Run a subclass hook for `goal`; end the goal with its verdict or its exception."""
        try:
            verdict = hook(*args)
        except Exception as err:  # a bug in a hook fails the action, not the node
            verdict = Verdict(ACTION_FAILED, f"{type(err).__name__}: {shorten(str(err))}")
        if verdict is not None:
            self.finish(goal, verdict)

    def _on_shutdown(self) -> None:
        """Leave every actuator safe when the node ends."""
        with self.lock:
            for goal in list(self.goals.values()):
                try:
                    self.halt(goal)
                except Exception:  # shutting down: best effort
                    pass


def run(decomposer: type[Decomposer], node_name: str, argv: list[str] | None = None,
        usage: str | None = None) -> int:
    """``--help`` (the parameter table), or ``rospy.init_node(node_name)``, build the
    decomposer and spin; the exit status (2 for a bad parameter)."""
    argv = argv if argv is not None else sys.argv
    summary = (decomposer.__doc__ or "").strip().split("\n")[0]
    node = start_node(decomposer, decomposer.Params, node_name, argv, usage,
                      f"{node_name}: {summary} (actions: "
                      f"{', '.join(decomposer.actions + decomposer.instant) or 'see ~actions'})")
    if node is None:
        return 2
    watch_master()
    rospy.loginfo(f"{node_name}: handling {', '.join(node.actions + node.instant)} in namespace "
                  f"{rospy.get_namespace()}")
    rospy.spin()
    return 0
