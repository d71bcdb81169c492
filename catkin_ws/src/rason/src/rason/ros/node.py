"""RasonNode: one ROS node hosting one or more Jason agents (thesis 5.2).

``rosrun rason agent NAME FILE.asl [__ns:=/robot]`` runs the node ``jason/NAME``;
``rosrun rason mas FILE.mas2j`` hosts every agent of a project file in one node.

Topics (relative names, so one robot per namespace works; un-namespaced it is the thesis):
  jason/action        publish   jason_msgs/Action      actions for the decomposers
  jason/cancel        publish   jason_msgs/ActionCancel  actions the agent gave up (stop them)
  jason/event         subscribe jason_msgs/Event       action_accepted / action_feedback
  jason/perception    subscribe jason_msgs/Perception  per-source perception lists
  jason/presence      publish   jason_msgs/AgentMessage  the agents' presence beats and goodbyes,
                                every period, for this robot's decomposers (their supervision)
  /jason/messages     both      jason_msgs/AgentMessage  agent communication and presence (global)
  /jason/directory    both      jason_msgs/AgentMessage  (latched) each node's directory-facilitator
                                registrations: performative "df", content [provider(Ag,"service"),...]
Services:
  jason/NAME/mind     jason_msgs/Mind   the agent's beliefs, desires, intentions, pending actions
Topic jason/NAME/mind_state (std_msgs/String, latched): the mind as JSON for the mind inspector
  (rason.ros.mind_state), published on change at most ~mind_state_rate times a second while
  someone subscribes.

Private parameters: :class:`AgentNodeParams` (``rosrun rason agent --help`` prints them).

Stopping is stopping: however an agent ends, its pending actions are cancelled on jason/cancel
(with the reason: ``stop_mas``, ``shutdown``, ``dropped``, ``agent_ended``), it says goodbye
and no presence beat follows, so its decomposers stop the robot. ``.stopMAS`` stops the whole
node, every agent it hosts, and the node exits with status 0 (Jason's platform ends the MAS);
``.kill_agent`` ends one agent and the node goes on; SIGINT/SIGTERM and node shutdown end all;
an agent whose reasoning ends on an error is ended as ``.kill_agent`` would.
"""

from __future__ import annotations

import math
import os
import sys
import threading
import time
import uuid
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TextIO

import rosgraph.names
import rospy
from jason_msgs.msg import Action, ActionCancel, AgentMessage, Event, Perception
from jason_msgs.srv import Mind, MindResponse

from rason.asl import Agent, AgentOptions, Message, load_agent_source, parse_term_text, term_str, term_text
from rason.asl.arch import verbosity
from rason.asl.df import DF_NAME, ProviderNotice, Registration, ServiceDirectory
from rason.asl.inspection import mind_text
from rason.asl.terms import ListTerm, Literal, list_to_python, non_finite_part
from rason.ros import fastpath
from rason.ros.acceptance import RemoteActions
from rason.ros.arch import RosAgArch, ros_now
from rason.ros.auth import (
    ACTION_KIND,
    EVENT_KIND,
    AuthKeyError,
    MessageAuth,
    SignedFields,
    TrustPolicy,
    Verdict,
    message_auth,
    new_nonce,
    sign_parameters,
    split_signed,
    verify_parameters,
)
from rason.ros.feedback import (
    CancelReason,
    accepted_beat_period,
    parse_accepted,
    parse_feedback,
    parse_running,
)
from rason.ros.holdback import HoldBack
from rason.ros.mind_state import LatchedTopic, MindStatePublisher, mind_state_topic
from rason.ros.perceptions import PerceptionFilter
from rason.ros.presence import (
    DF_PERFORMATIVE,
    DIRECTORY_TOPIC,
    GOODBYE,
    HELLO,
    MESSAGES_TOPIC,
    PRESENCE,
    PRESENCE_TOPIC,
    Directory,
)
from rason.ros.ticker import Ticker
from rosnode_kit.badinput import BadInputLog, shorten
from rosnode_kit.guard import RateLimitedWarnings, guarded
from rosnode_kit.params import ParamError, param

#: s (ROS time) between two checks of action timeouts and perception TTLs
CHECK_PERIOD = 0.05
#: s of wall time ROS time may stand still while an agent waits on it before a warning
FROZEN_CLOCK_S = 3.0


@dataclass(frozen=True)
class AgentNodeParams:
    """The agent node's private parameters (``rosrun rason agent|mas ... _name:=value``)."""

    ack_timeout: float = param(
        2.0, "s (ROS time) a decomposer has to acknowledge an action with action_accepted once "
        "it is sent, else the action fails with no_decomposer (an action held until a "
        "decomposer is connected both ways fails when no connection came for as long); 0 "
        "disables the check (thesis-only decomposers)",
        minimum=0.0)
    action_timeout: float = param(
        120.0, "s an accepted action may run before it fails with action_timeout (and is "
        "cancelled on jason/cancel); 0 disables", minimum=0.0)
    decomposer_timeout: float = param(
        3.0, "s (ROS time, and three of its beat periods at least) an accepted action's "
        "decomposer may stay silent, when it announced action_running beats, before the action "
        "fails with decomposer_lost (and is cancelled); 0 disables", minimum=0.0)
    perception_mode: str = param(
        "replace", "replace: per-source replacement (thesis 5.2); queue: every message is "
        "applied (the thesis' unfiltered baseline)")
    perception_functors: list = param(
        [], "only these percepts reach the agent, e.g. \"[robot/4, battery]\"; [] = all")
    perception_sources: list = param(
        [], "only these perception sources reach the agent; [] = all")
    perception_ttl: float = param(
        0.0, "s (ROS time) a perception source may stay silent before its list is cleared (the "
        "usual - events); 0 = a list stands until replaced. For sources that declare no TTL of "
        "their own as the parameter jason/perception_ttl/<source> (every synthesizer built on "
        "rason.execution.synthesizer declares its ~perception_ttl)", minimum=0.0)
    perception_ttls: dict = param(
        {}, "per-source TTLs, e.g. \"{robot_synthesizer_robot: 0.3, sonar: 2}\"; they win over "
        "a source's own declaration and over ~perception_ttl")
    presence_period: float = param(
        1.0, "s between presence announcements on /jason/messages; every message counts as "
        "presence, so an agent that published one within the last half period skips its "
        "announcement (it is never silent for more than 1.5 periods)", minimum=0.01)
    presence_timeout: float = param(
        3.5, "s after which a silent agent is forgotten by .all_names and .broadcast; a .send to "
        "it then fails with a clear reason", minimum=0.0)
    internal_actions: list = param(
        [], "Python modules (importable, or in the current directory) whose "
        "@internal_action(\"lib.name\") functions every hosted agent gets")
    auth_key_file: str = param(
        "", "file holding a shared secret (16 bytes or more) that signs every message this node "
        "publishes on /jason/messages (HMAC-SHA256 over all fields, stamp and nonce); unsigned, "
        "forged, stale or replayed ones are dropped (make one: head -c 32 /dev/urandom | base64 > "
        "fleet.key; chmod 600 fleet.key). Its actions on jason/action are signed too (a last "
        "parameter #auth:...) and only signed jason/event feedback is heard: give the robot's "
        "decomposers the same key. Empty = NO authentication: anyone on the ROS graph "
        "can send anything with any sender, as in the thesis")
    auth_window: float = param(
        10.0, "s (ROS time) a signed message stays acceptable after its stamp (hosts' clocks "
        "must agree within it: chrony/NTP); a nonce seen within it is a replay", minimum=0.0)
    trusted_senders: list = param(
        [], "the only senders whose every message may reach the agents of this node (Jason's "
        "message acceptance hook); the others' are dropped but for tell, untell, askOne and "
        "askAll; [] = everyone. In a .mas2j, per agent: trusted_senders=\"[boss]\"")
    remote_internal_actions: list = param(
        [], "the internal actions a message from another agent may make the receiver run when "
        "its content is evaluated (an askOne .my_name(N), a told rule calling .count...), for "
        "every sender, trusted or not, e.g. \"[.my_name, .count]\"; a message whose content "
        "calls any other (or holds a plan term) is dropped with a warning. [] = none")
    tro: bool = param(AgentOptions().tro, "tail-recursion optimisation as Jason's tro agent option: "
                      "+!loop <- ...; !loop. runs in constant memory")
    max_intention_depth: int = param(
        AgentOptions().max_intention_depth,
        "an intention deeper than this fails with error(intention_too_deep) (a -!g plan can "
        "handle it) and a warning", minimum=1)
    receive_nice: int = param(
        5, "added to the nice value of the threads that read /jason/messages (Linux keeps one "
        "per thread; such a thread also runs the reasoning a message starts in an idle agent, "
        "until the agent's own input wakes its thread): when the CPU is short, this node's own "
        "work, and the broadcasts it sends, go before the fleet's incoming messages, so a "
        "broadcast reaches its receivers before they take the CPU from its sender; 0 = the "
        "node's own priority", minimum=0, maximum=fastpath.MAX_NICE)
    receive_slice: float = param(
        0.0002, "seconds: the scheduling slice the threads that read /jason/messages ask Linux "
        "for (EEVDF, kernel 6.12 and later; older kernels ignore it): a thread with a shorter "
        "slice gets the CPU sooner when it wakes, for less time at a time, so a message's "
        "handling (a fraction of a millisecond) does not wait behind the default slices of "
        "the other processes woken with it; 0 = the kernel's default slice",
        minimum=0.0, maximum=fastpath.MAX_SLICE_S)
    mind_state_rate: float = param(
        10.0, "at most this many jason/NAME/mind_state publications a second (only when the mind "
        "changed; for the mind inspector); 0 = not published", minimum=0.0)


@dataclass
class HostedAgent:
    """An agent, its architecture and the thread running its reasoning cycle."""

    agent: Agent
    arch: RosAgArch
    thread: threading.Thread
    mind_state: MindStatePublisher | None = None
    mind_service: Any = None


def _presence(sender: str, content: str = "") -> AgentMessage:
    return AgentMessage(sender=sender, receiver="", performative=PRESENCE, content=content,
                        reply_with="", in_reply_to="")


class _GreetNewSubscribers(rospy.SubscribeListener):
    """Calls ``greet(publish_to_newcomer)`` whenever a node subscribes to our publisher."""

    def __init__(self, greet: Callable[[Callable[[AgentMessage], None]], None]):
        super().__init__()
        self._greet = guarded("greeting a new subscriber")(greet)

    def peer_subscribe(self, topic_name: str, topic_publish: Callable[[AgentMessage], None],
                       peer_publish: Callable[[AgentMessage], None]) -> None:
        self._greet(peer_publish)


class RasonNode:
    """The ROS side of a process hosting agents: topics, services, timers, presence."""

    def __init__(self, params: AgentNodeParams, base_ns: str = "/") -> None:
        self.base_ns = base_ns if base_ns.endswith("/") else base_ns + "/"
        # first: a node may subscribe to message_pub (and be greeted) before __init__ ends
        self._started = False
        # -- parameters ---------------------------------------------------------------------------
        self.params = params
        self.ack_timeout = params.ack_timeout
        self.action_timeout = params.action_timeout
        self.decomposer_timeout = params.decomposer_timeout
        self.perception_mode = params.perception_mode
        self.default_filter = PerceptionFilter.from_lists(params.perception_functors,
                                                          params.perception_sources)
        presence_period = params.presence_period
        self.directory = Directory(params.presence_timeout)
        self.agent_options = AgentOptions(tro=params.tro,
                                          max_intention_depth=params.max_intention_depth)
        self.mind_state_rate = params.mind_state_rate
        self.default_perception_ttl = params.perception_ttl
        self.perception_ttls = {source: _seconds(f"~perception_ttls/{source}", ttl)
                                for source, ttl in params.perception_ttls.items()}
        self._declared_ttls: dict[str, float | None] = {}
        self.auth = _message_auth(params.auth_key_file, params.auth_window)
        self.trust = TrustPolicy.of(params.trusted_senders)
        self.remote_actions = RemoteActions.of(params.remote_internal_actions)
        if self.auth is None:
            rospy.logwarn("no ~auth_key_file: this node accepts any sender on the ROS graph (any "
                          "process may send its agents messages in any agent's name; messages "
                          "run no internal action outside ~remote_internal_actions)")
        # Rejected messages, expired perception sources: one warning per kind and 10 s at most.
        self.warnings = RateLimitedWarnings(period=10.0)
        self.agents: dict[str, HostedAgent] = {}
        self.stop = threading.Event()
        self._console_lock = threading.Lock()
        self._stop_lock = threading.Lock()       # shutdown runs once
        self.bad_input = BadInputLog(rospy.logwarn, rospy.get_time)

        # -- topics (subscriptions start with the agents: see start) -------------------------------
        # The agents' traffic is written from the publishing thread, each subscriber at once,
        # never waiting for one that does not read (rason.ros.fastpath.fanout).
        self.action_pub = fastpath.publisher(self.topic("jason/action"), Action, queue_size=100)
        self.cancel_pub = fastpath.publisher(self.topic("jason/cancel"), ActionCancel, queue_size=100)
        # a node that subscribes hears our agents' presence at once, not a period later
        self.message_pub = fastpath.publisher(MESSAGES_TOPIC, AgentMessage, queue_size=100,
                                            subscriber_listener=_GreetNewSubscribers(self.greet))
        # the same beats for this robot's decomposers, every period (they do not hear the fleet)
        self.presence_pub = fastpath.publisher(self.topic(PRESENCE_TOPIC), AgentMessage,
                                             queue_size=10, tcp_nodelay=True)
        self._presence_period = presence_period
        # ROS time each hosted agent last published on /jason/messages (presence or message)
        self._last_said: dict[str, float] = {}
        # messages to an agent whose node does not listen to us yet (heard one way only)
        self.hold_back: HoldBack[AgentMessage] = HoldBack(max_hold=params.presence_timeout)
        # -- directory facilitator: our agents' services, published latched; the others' heard
        self.services = ServiceDirectory(self._tell_provider, self._publish_services)
        self.directory_pub = rospy.Publisher(DIRECTORY_TOPIC, AgentMessage, queue_size=10, latch=True)
        self.checks: Ticker | None = None    # made by start()
        self.event_sub: rospy.Subscriber | None = None

    def topic(self, name: str) -> str:
        """`name` relative to the robot's namespace (the node itself lives in <ns>/jason)."""
        return self.base_ns + name

    # -- hosting ----------------------------------------------------------------------------------------
    def host(self, name: str, source: str, filename: str,
             perception_filter: PerceptionFilter | None = None,
             options: dict | None = None) -> HostedAgent:
        """Create agent `name` from AgentSpeak `source`, serve its mind, start its cycle
        (`options`: the agent's own `.mas2j` options, over the node's `~tro`...)."""
        arch = RosAgArch(self, name, perception_filter or self.default_filter,
                         _agent_trust(options or {}, self.trust))
        arch.verbose = verbosity(options or {})
        agent = Agent(name, source, arch, filename=filename,
                      options=AgentOptions.from_options(options or {}, self.agent_options))
        self.directory.add_local(name)
        service = rospy.Service(self.topic(f"jason/{name}/mind"), Mind,
                                lambda _req, a=agent, r=arch: self.mind(a, r))
        thread = threading.Thread(target=self._run_agent, args=(agent,), name=f"agent-{name}",
                                  daemon=True)
        hosted = HostedAgent(agent, arch, thread, mind_service=service)
        if self.mind_state_rate > 0:
            topic = LatchedTopic(mind_state_topic(self.base_ns, name), on_subscribe=self.kick_checks)
            hosted.mind_state = MindStatePublisher(
                agent, arch.pending_actions, topic.publish, rospy.get_name(), self.base_ns,
                schedule=arch.run_at_next_cycle, listened=topic.listened)
        self.agents[name] = hosted
        return hosted

    def start(self) -> None:
        """Subscribe (latched messages may arrive at once), announce the agents, start them."""
        # Every callback is guarded: a bad message costs a warning, never a timer or the node.
        # The frequent topics are read by rason.ros.fastpath's frame readers (less work per
        # message than rospy's), unless RASON_STOCK_ROSPY=1.
        self.event_sub = fastpath.subscriber(self.topic("jason/event"), Event,
                                             guarded("jason/event")(self.on_event), queue_size=100)
        fastpath.subscriber(self.topic("jason/perception"), Perception,
                            guarded("jason/perception")(self.on_perception),
                            queue_size=100, tcp_nodelay=True)
        fastpath.subscriber(MESSAGES_TOPIC, AgentMessage, guarded(MESSAGES_TOPIC)(self.on_message),
                            queue_size=200, nice=self.params.receive_nice,
                            slice_s=self.params.receive_slice, tcp_nodelay=True)
        rospy.Subscriber(DIRECTORY_TOPIC, AgentMessage, guarded(DIRECTORY_TOPIC)(self.on_directory),
                         queue_size=50)
        self._started = True
        # One thread for the frequent checks (each guarded on its own), ticking only while there
        # is something to check: an action waiting for feedback, a perception list with a time
        # to live, a mind-state subscriber (each kicks it, see kick_checks). An idle agent in a
        # fleet pays for no wake-ups.
        checks = [guarded("action timeouts")(self.on_check_actions),
                  guarded("perception TTLs")(self.on_check_perceptions)]
        mind_state = guarded("mind_state")(self.on_mind_state)
        mind_state_period = 1.0 / self.mind_state_rate if self.mind_state_rate > 0 else None
        period = min(CHECK_PERIOD, mind_state_period or CHECK_PERIOD)
        last_mind_state = [-math.inf]

        def on_checks() -> None:
            for check in checks:
                check(None)
            now = rospy.get_time()
            if mind_state_period is not None and (
                    now - last_mind_state[0] >= mind_state_period - period / 2
                    or now < last_mind_state[0]):      # < : simulated time restarted
                last_mind_state[0] = now
                mind_state(None)

        self.checks = Ticker(1.0 / period, on_checks, self._checks_needed, name="node-checks")
        if not rospy.rostime.is_wallclock():     # simulated time can stand still
            threading.Thread(target=guarded("clock watch")(self._watch_clock),
                             name="clock-watch", daemon=True).start()
        rospy.Timer(rospy.Duration(self._presence_period), guarded("presence")(self.on_presence))
        self._wait_for_first_clock()
        for name in list(self.agents):
            self._announce(name, HELLO)
        for hosted in list(self.agents.values()):
            hosted.thread.start()

    def _wait_for_first_clock(self) -> None:
        """Under simulated time ROS time reads 0 until the first /clock arrives: the agents start
        after it, so that no .wait or timeout is measured from 0 (it would end at once)."""
        if rospy.rostime.is_wallclock():
            return
        started, warned = time.monotonic(), False
        while rospy.get_time() == 0.0 and not self.stop.wait(0.02) and not rospy.is_shutdown():
            if not warned and time.monotonic() - started >= FROZEN_CLOCK_S:
                rospy.logwarn("use_sim_time is set and no /clock has come yet: the agents start "
                              "once it does (is the simulator running?)")
                warned = True

    def _watch_clock(self) -> None:
        """Warn (once per stop) when ROS time stands still for FROZEN_CLOCK_S of wall time
        while an agent waits on it: the one place where wall time is the right measure."""
        last, since, warned = rospy.get_time(), time.monotonic(), False
        while not self.stop.wait(FROZEN_CLOCK_S / 4):
            now = rospy.get_time()
            if now != last:
                last, since, warned = now, time.monotonic(), False
                continue
            stood = time.monotonic() - since
            if warned or stood < FROZEN_CLOCK_S:
                continue
            waits = [f"[{name}] {what}" for name, hosted in list(self.agents.items())
                     for what in hosted.arch.waits_on_time()]
            if waits:
                warned = True
                rospy.logwarn("ROS time has stood still at %.3f s for %.0f s of wall time (is "
                              "/clock published? the simulator stopped?) while waiting on it: %s",
                              now, stood, shorten("; ".join(waits), 400))

    def kick_checks(self) -> None:
        """Something may need the periodic checks now (see :meth:`_checks_needed`)."""
        if self.checks is not None:
            self.checks.kick()

    def _checks_needed(self) -> bool:
        return any(hosted.arch.needs_checks()
                   or (hosted.mind_state is not None and hosted.mind_state.listened())
                   for hosted in list(self.agents.values()))

    def on_master_restarted(self) -> None:
        """Registered again with a restarted master: ask everyone to announce themselves."""
        for name in list(self.agents):
            self._announce(name, "hello")

    def _run_agent(self, agent: Agent) -> None:
        """An agent's thread: its reasoning cycle, then, however it ended, its actions
        cancelled and its goodbye (``.stopMAS`` stops the whole node, as Jason's platform)."""
        error: Exception | None = None
        try:
            agent.run(self.stop)
        except Exception as err:
            error = err
            rospy.logerr("agent %s stopped: %s", agent.name, err)
        hosted = self.agents.get(agent.name)
        if self.stop.is_set() or hosted is None or hosted.agent is not agent:
            return        # the node stops (it says goodbye for all) or .kill_agent did it
        if error is None and agent.stop_requested:
            rospy.loginfo("agent %s called .stopMAS: the node stops", agent.name)
            self.shutdown(CancelReason.STOP_MAS)
            rospy.signal_shutdown(f"{agent.name} called .stopMAS")
        else:
            self.kill_agent(agent.name, CancelReason.AGENT_ENDED)

    def shutdown(self, reason: str = CancelReason.SHUTDOWN) -> None:
        """Stop every reasoning cycle, cancel the pending actions (``reason``), say goodbye on
        the network; presence ends (done once: later calls do nothing)."""
        with self._stop_lock:
            if self.stop.is_set():
                return
            self.stop.set()
        cancelled = 0
        for name, hosted in list(self.agents.items()):
            hosted.agent.wake()
            cancelled += hosted.arch.cancel_all(reason)
            try:
                self._announce(name, GOODBYE)
            except rospy.ROSException:
                pass
        if cancelled:
            time.sleep(0.1)       # let the cancels leave before the connections close
        for hosted in list(self.agents.values()):
            if hosted.thread is not threading.current_thread() and hosted.thread.is_alive():
                hosted.thread.join(2.0)

    # -- output -----------------------------------------------------------------------------------------
    def publish_action(self, agent: str, action_id: int, action) -> bool:
        """Publish an action on jason/action; False, without publishing, while no decomposer
        could answer it (see :meth:`action_listeners`): the caller tries again later."""
        if self.action_listeners() == 0:
            return False
        name, args = action.functor, [term_str(arg) for arg in action.args]
        if self.auth is not None:
            args = sign_parameters(self.auth, ACTION_KIND, agent, f"{action_id} {name}", args,
                                   rospy.get_rostime().to_nsec())
        self.action_pub.publish(Action(agent=agent, action_id=action_id, action=name,
                                       parameters=args))
        return True

    def action_listeners(self) -> int:
        """How many decomposers would hear an action now and could answer it: subscribers of
        jason/action whose jason/event publications this node is connected to as well (an
        action sent before the way back is up would have its acknowledgement lost). With
        ``~ack_timeout`` 0 (decomposers that never answer) every subscriber counts."""
        listeners, talkers = self._decomposer_ends()
        if self.ack_timeout <= 0 or self.event_sub is None or self.event_sub.impl is None:
            return len(listeners)
        return len(listeners & talkers)

    def decomposer_links(self) -> frozenset[str]:
        """The connections a decomposer makes to this node, as ``action:NODE`` (it subscribed
        to jason/action) and ``event:NODE`` (this node hears its jason/event); a change means
        a connection is under way or gone (see :meth:`RosAgArch.check_timeouts`)."""
        listeners, talkers = self._decomposer_ends()
        return frozenset({f"action:{n}" for n in listeners} | {f"event:{n}" for n in talkers})

    def _decomposer_ends(self) -> tuple[set[str], set[str]]:
        """The nodes subscribed to jason/action, and those whose jason/event this node hears."""
        listeners = {c.endpoint_id for c in self.action_pub.impl.connections}
        if self.event_sub is None or self.event_sub.impl is None:
            return listeners, set()
        talkers = {c.header.get("callerid") for c in self.event_sub.impl.connections
                   if getattr(c, "header", None)}
        return listeners, talkers

    def publish_cancel(self, agent: str, action_id: int, reason: str) -> None:
        """Tell the decomposers that `agent` gave action `action_id` up."""
        try:
            self.cancel_pub.publish(ActionCancel(agent=agent, action_id=action_id, reason=reason))
        except rospy.ROSException as err:     # shutting down: the goodbye still stops it
            rospy.logwarn("cannot cancel action %d of %s: %s", action_id, agent, err)
        else:
            rospy.loginfo("[%s] cancelled action %d (%s)", agent, action_id, reason)

    def publish_message(self, message: Message) -> None:
        """Publish an agent's message; one to an agent whose node has not yet subscribed to
        ours waits for it (see :class:`~rason.ros.holdback.HoldBack`)."""
        msg = AgentMessage(
            sender=message.sender, receiver=message.receiver or "",
            performative=message.performative, content=term_text(message.content),
            reply_with=message.msg_id or uuid.uuid4().hex[:12],
            in_reply_to=message.in_reply_to or "")
        if not msg.receiver:
            self._publish(msg)
            return
        for ready in self.hold_back.submit(msg.receiver, msg, rospy.get_time(),
                                           self._subscriber_nodes()):
            self._publish(ready)

    def _subscriber_nodes(self) -> set[str]:
        """The nodes subscribed to our /jason/messages publisher now."""
        impl = self.message_pub.impl
        return {c.endpoint_id for c in impl.connections} if impl is not None else set()

    def _release_held(self) -> None:
        """Publish the held messages whose node now listens, or that waited long enough."""
        if not self.hold_back.held():
            return          # the usual case, checked every presence period
        for released in self.hold_back.release(rospy.get_time(), self._subscriber_nodes()):
            if released.late:
                self.warnings.warn(f"late {released.receiver}", (
                    f"sent to {released.receiver} although its node has not subscribed to ours "
                    f"within {self.hold_back.max_hold:g} s: it may not get it"))
            self._publish(released.message)

    def _seal(self, msg: AgentMessage) -> AgentMessage:
        """Stamp `msg`, and sign it when this node has a key."""
        msg.stamp = rospy.Time.now()
        msg.nonce = new_nonce()
        if self.auth is not None:
            msg.signature = self.auth.sign(_signed_fields(msg))
        return msg

    def _publish(self, msg: AgentMessage, publisher: rospy.Publisher | None = None) -> None:
        """Stamp, and sign when this node has a key, then publish on /jason/messages (or on
        `publisher`)."""
        self._seal(msg)
        if publisher is not None:
            publisher.publish(msg)
            return
        self.message_pub.publish(msg)
        self._last_said[msg.sender] = msg.stamp.to_sec()

    # -- directory facilitator ----------------------------------------------------------------------
    def _publish_services(self) -> None:
        """Our agents' registrations changed: publish all of them (latched) for the other nodes;
        with a key, again every half ~auth_window, so the latched copy a newcomer gets is never
        stale (rason.ros.auth)."""
        regs = self.services.local_registrations()
        content = ListTerm(tuple(Literal("provider", (Literal(r.agent), r.service)) for r in regs))
        self._publish(AgentMessage(sender=rospy.get_name(), receiver="", performative=DF_PERFORMATIVE,
                                   content=term_text(content), reply_with="", in_reply_to=""),
                      self.directory_pub)
        if self.auth is not None and not hasattr(self, "_services_timer"):
            self._services_timer = rospy.Timer(rospy.Duration(self.auth.window / 2), guarded(
                "directory republish")(lambda _event: self._publish_services()))

    def _authentic(self, msg: AgentMessage, kind: str, dropped: Callable[[str], str]) -> bool:
        """True when this node has no key or ``msg`` verifies; else False and a rate-limited
        warning ``dropped <what dropped(verdict) says>``."""
        if self.auth is None:
            return True
        verdict = self.auth.verify(_signed_fields(msg), msg.signature,
                                   rospy.get_rostime().to_nsec())
        if verdict is Verdict.OK:
            return True
        key = " ".join(x for x in (verdict.value, kind, shorten(msg.sender, 64)) if x)
        self.warnings.warn(key, "dropped " + dropped(verdict.value))
        return False

    def on_directory(self, msg: AgentMessage) -> None:
        """Another node's registrations (it replaces what that node published before)."""
        if msg.sender == rospy.get_name() or msg.performative != DF_PERFORMATIVE:
            return
        if not self._authentic(msg, "directory",
                               lambda v: f"{v} directory registrations from '{msg.sender}'"):
            return
        content = self._read_content(msg)
        items = list_to_python(content) if content is not None else None
        if items is None:
            return
        regs = [Registration(term_str(p.args[0]), p.args[1]) for p in items
                if isinstance(p, Literal) and p.functor == "provider" and len(p.args) == 2
                and isinstance(p.args[1], str)]
        self.services.set_remote(msg.sender, regs)

    def _tell_provider(self, notice: ProviderNotice) -> None:
        """The directory facilitator tells a local subscriber of a provider (as Jason's ``df``)."""
        hosted = self.agents.get(notice.subscriber)
        if hosted is not None:
            message = Message(DF_NAME, notice.subscriber, "tell", notice.content())
            hosted.agent.receive(message)
            self.note_message(notice.subscriber, message, outgoing=False)

    # -- agents made and killed while the node runs ---------------------------------------------------
    def create_agent(self, creator: Agent, name: str | None, source: str | None) -> str:
        """``.create_agent``: a new agent hosted by this node (its mind service, its cycle);
        a name taken on the network gets a suffix. `source` is found beside the creator's file,
        then in the current folder."""
        base = name or "agent"
        final, k = base, 1
        now = rospy.get_time()
        while final in self.agents or self.directory.knows(final, now):
            final, k = f"{base}_{k}", k + 1
        if source is None:
            path, text = "<string>", ""
        else:
            path = _find_source(source, creator.filename)
            text = load_agent_source(path)
        hosted = self.host(final, text, path)
        if self._started:
            self._announce(final, HELLO)
            hosted.thread.start()
        return final

    def kill_agent(self, name: str, reason: str = CancelReason.DROPPED) -> bool:
        """``.kill_agent``: the agent stops, its actions are cancelled (``reason``), it says
        goodbye."""
        hosted = self.agents.pop(name, None)
        if hosted is None:
            return False
        hosted.agent.request_stop()
        hosted.agent.wake()
        hosted.arch.cancel_all(reason)
        self.directory.remove_local(name)
        self.services.forget_agent(name)
        if hosted.mind_service is not None:
            hosted.mind_service.shutdown("agent killed")
        try:
            self._announce(name, GOODBYE)
        except rospy.ROSException:
            pass
        return True

    def deliver_local(self, message: Message) -> bool:
        """Hand a message to the agents of this process it is for; True if it was only for them.

        Agents hosted together never go through the topic (a message published before the
        topic's connections are up would be lost, and the hop is pointless).
        """
        if message.receiver:
            hosted = self.agents.get(message.receiver)
            if hosted is None:
                return False
            self._receive(hosted, message)
            return True
        for name, hosted in list(self.agents.items()):
            if name != message.sender:
                self._receive(hosted, Message(sender=message.sender, receiver=name,
                                              performative=message.performative,
                                              content=message.content, msg_id=message.msg_id))
        return False

    def _receive(self, hosted: HostedAgent, message: Message, run_here: bool = False) -> None:
        """Give `message` to a hosted agent if its acceptance hook lets it in (``run_here``:
        a receiving thread that may reason for the agent, see ``Agent.receive``)."""
        refusal = hosted.arch.refusal(message)
        if refusal is not None:
            self.warnings.warn(f"refused {shorten(message.sender, 64)} "
                               f"{shorten(message.performative, 32)} {refusal[:60]}",
                               f"[{hosted.arch.name}] dropped {shorten(message.performative, 32)} "
                               f"from '{shorten(message.sender, 64)}': {refusal}")
            return
        self.note_message(hosted.agent.name, message, outgoing=False)
        hosted.agent.receive(message, run_here=run_here)

    def note_message(self, agent_name: str, message: Message, outgoing: bool) -> None:
        """Keep a message `agent_name` received or sent for its published mind."""
        hosted = self.agents.get(agent_name)
        if hosted is not None and hosted.mind_state is not None:
            hosted.mind_state.note_message(message, outgoing, ros_now())

    def console(self, agent_name: str, text: str) -> None:
        with self._console_lock:
            write_line(sys.stdout, f"[{agent_name}] {text}")

    def output(self, text: str) -> None:
        """Bare text of an agent with ``verbose=0`` (no name, no new line added)."""
        with self._console_lock:
            sys.stdout.write(text)
            sys.stdout.flush()

    def _announce(self, name: str, content: str = "") -> None:
        """Presence (``content``: "", HELLO or GOODBYE) on /jason/messages and jason/presence."""
        beat = _presence(name, content)
        self._publish(beat)
        self.presence_pub.publish(beat)        # the same signed beat, for our decomposers

    def greet(self, publish_to_newcomer: Callable[[AgentMessage], None]) -> None:
        """A node just subscribed to /jason/messages: tell it (only it) which agents we host."""
        if not self._started or self.stop.is_set():
            return      # start() says hello to everyone; a stopping node said goodbye
        impl = self.message_pub.impl
        if impl is None:
            return      # closing
        # rospy's publish to one subscriber shares the topic's serialisation buffer with every
        # publish but not its lock: unlocked, a greeting racing start()'s hello corrupted both
        # (struct.error, seen once in a fleet of twenty)
        impl.acquire()
        try:
            for name in list(self.agents):
                publish_to_newcomer(self._seal(_presence(name)))
        finally:
            impl.release()
        self._release_held()       # what waited for this node to listen

    # -- callbacks --------------------------------------------------------------------------------------
    def on_event(self, msg: Event) -> None:
        hosted = self.agents.get(msg.agent)
        if hosted is None:
            return  # another agent's event: ignored (thesis 5.2)
        msg = self._signed_event(msg)
        if msg is None:
            return
        accepted = parse_accepted(msg)
        if accepted is not None:
            hosted.arch.on_accepted(accepted, accepted_beat_period(msg))
            return
        running = parse_running(msg)
        if running is not None:
            hosted.arch.on_running(running)
            return
        feedback = parse_feedback(msg)
        if feedback is not None:
            hosted.arch.on_feedback(feedback)
        elif msg.event_type == "action_feedback":
            rospy.logwarn("unreadable action_feedback for %s: %s", msg.agent, list(msg.parameters))

    def _signed_event(self, msg: Event) -> Event | None:
        """`msg` without its signature parameter; None (and a rate-limited warning) when this
        node has a key and the signature is missing or wrong: anyone could fake feedback."""
        if self.auth is None:
            parameters, _ = split_signed(list(msg.parameters))
            return Event(agent=msg.agent, event_type=msg.event_type, parameters=parameters)
        parameters, verdict = verify_parameters(self.auth, EVENT_KIND, msg.agent,
                                                msg.event_type, list(msg.parameters),
                                                rospy.get_rostime().to_nsec())
        if verdict is not Verdict.OK:
            kind = shorten(msg.event_type, 32)
            self.warnings.warn(f"{verdict.value} event {kind} {shorten(msg.agent, 64)}",
                               f"[{shorten(msg.agent, 64)}] ignored a {verdict.value} {kind} "
                               "event on jason/event (not signed with ~auth_key_file)")
            return None
        return Event(agent=msg.agent, event_type=msg.event_type, parameters=parameters)

    def on_perception(self, msg: Perception) -> None:
        for hosted in list(self.agents.values()):
            hosted.arch.on_perception(msg.source, msg.perception)

    def on_message(self, msg: AgentMessage) -> None:
        if msg.sender in self.agents:
            return  # our own publication (delivered in-process already), or a forgery of it
        now = ros_now()
        if not self._authentic(msg, "", lambda v: f"a {v} {msg.performative or '?'} message "
                                                  f"claiming to be from '{msg.sender}'"):
            return
        header = getattr(msg, "_connection_header", None)    # set by rospy: who sent it
        if header:
            self.hold_back.heard(msg.sender, header.get("callerid", ""))
        if msg.performative == PRESENCE:
            if msg.content == GOODBYE:
                self.directory.forget(msg.sender)
                rospy.loginfo("agent %s said goodbye: forgotten", shorten(msg.sender, 80))
                return
            if self.directory.heard(msg.sender, now):   # new, or back after a lapse
                rospy.loginfo("agent %s present", shorten(msg.sender, 80))
            if msg.content == HELLO and not self.stop.is_set():   # a newcomer: know us now
                for name in list(self.agents):
                    self._announce(name)
            return
        if self.directory.heard(msg.sender, now):   # known from its message before its presence
            rospy.loginfo("agent %s present", shorten(msg.sender, 80))
        receivers = ([msg.receiver] if msg.receiver
                     else [n for n in list(self.agents) if n != msg.sender])
        content = None
        for name in receivers:
            hosted = self.agents.get(name)
            if hosted is None:
                continue
            if content is None:
                content = self._read_content(msg)
                if content is None:
                    return
            # this receiving thread reasons for an idle agent itself (one thread woken, not two)
            self._receive(hosted, Message(
                sender=msg.sender, receiver=name, performative=msg.performative,
                content=content, msg_id=msg.reply_with, in_reply_to=msg.in_reply_to or None),
                run_here=True)

    def _read_content(self, msg: AgentMessage) -> Any:
        """The message's content as a term, or None (with a rate-limited warning) when it is
        unreadable or holds a number that is not finite."""
        try:
            content = parse_term_text(msg.content)
        except Exception as err:
            self.bad_input.warn(msg.sender, msg.content, (
                f"dropped message from {shorten(msg.sender, 80)} with unreadable content "
                f"{shorten(repr(msg.content))}: {shorten(str(err))}"))
            return None
        bad = non_finite_part(content)
        if bad is not None:
            self.bad_input.warn(msg.sender, msg.content, (
                f"dropped message from {shorten(msg.sender, 80)}: {bad} is not a finite number "
                f"in {shorten(repr(msg.content))}"))
            return None
        return content

    def on_check_actions(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.get_time()
        for hosted in list(self.agents.values()):
            hosted.arch.check_timeouts(now, self.ack_timeout, self.action_timeout,
                                       self.decomposer_timeout)

    def on_check_perceptions(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.get_time()
        for hosted in list(self.agents.values()):
            hosted.arch.expire_perceptions(now)

    def perception_ttl(self, source: str) -> float:
        """A perception source's time to live: this node's map, the source's own declaration
        (parameter ``jason/perception_ttl/<source>``, read once), else ``~perception_ttl``."""
        if source in self.perception_ttls:
            return self.perception_ttls[source]
        if source in self._declared_ttls:
            declared = self._declared_ttls[source]
        else:
            declared = self._declared_ttl(source)
        return self.default_perception_ttl if declared is None else declared

    def _declared_ttl(self, source: str) -> float | None:
        """The TTL `source` declared (remembered), or None; not remembered if the master
        cannot be asked (the perception table asks again with the source's next message)."""
        if not rosgraph.names.is_legal_base_name(source):
            self._declared_ttls[source] = None
            return None
        key = self.topic(f"jason/perception_ttl/{source}")
        try:
            value = rospy.get_param(key, None)
        except (OSError, rospy.ROSException) as err:
            rospy.logwarn("cannot read %s (%s): using ~perception_ttl", key, err)
            return None
        self._declared_ttls[source] = self._checked_ttl(key, value)
        return self._declared_ttls[source]

    @staticmethod
    def _checked_ttl(key: str, value: object) -> float | None:
        if value is None:
            return None
        try:
            return _seconds(key, value)
        except ParamError as err:
            rospy.logwarn("%s: using ~perception_ttl", err)
            return None

    def on_presence(self, _event: rospy.timer.TimerEvent) -> None:
        if self.stop.is_set():
            return          # goodbye said: no beat may follow it
        now = rospy.get_time()
        for name in list(self.agents):
            # everyone hears any message as presence: an agent that spoke within the last half
            # period needs no announcement (a third fewer messages in a chatty fleet)
            last = self._last_said.get(name)
            if last is None or not 0 <= now - last < self._presence_period / 2:
                self._announce(name)
            else:   # our decomposers hear only jason/presence: they get the beat every period
                self._publish(_presence(name), self.presence_pub)
        for gone in self.directory.expire(now):
            rospy.loginfo("agent %s not heard for %.1f s: forgotten", shorten(gone, 80),
                          self.directory.timeout)
        self._release_held()

    def on_mind_state(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.get_time()
        for hosted in list(self.agents.values()):
            if hosted.mind_state is not None:
                try:
                    hosted.mind_state.tick(now)
                except Exception as err:  # the inspector's view must never stop the agent
                    rospy.logwarn_throttle(10.0, "[%s] mind_state not published: %s",
                                           hosted.agent.name, err)

    # -- services ---------------------------------------------------------------------------------------
    def mind(self, agent: Agent, arch: RosAgArch) -> MindResponse:
        mind = mind_text(agent)
        return MindResponse(agent=agent.name, beliefs=mind.get("beliefs", []),
                            desires=mind.get("desires", []),
                            intentions=mind.get("intentions", []),
                            pending_actions=arch.pending_texts())


def write_line(stream: TextIO, line: str) -> None:
    """Write ``line`` and its newline in one call, then flush: rospy's log lines share stdout
    and are written whole, from other threads; a ``print`` writes the newline apart, and a log
    line falling between the two once broke an agent's line in the middle."""
    stream.write(line + "\n")
    stream.flush()


def _find_source(source: str, near: str) -> str:
    """The path of an agent file for ``.create_agent``: as given, beside `near`, in the
    current folder (FileNotFoundError otherwise)."""
    folders = [os.path.dirname(os.path.abspath(near))] if near and not near.startswith("<") else []
    candidates = [source] + [os.path.join(d, source) for d in folders]
    if not source.endswith(".asl"):
        candidates += [c + ".asl" for c in candidates]
    for cand in candidates:
        if os.path.isfile(cand):
            return os.path.abspath(cand)
    raise FileNotFoundError(source)


def _message_auth(key_file: str, window: float) -> MessageAuth | None:
    """The node's authentication, or None (open) without a key file."""
    try:
        return message_auth(key_file, window, warn=rospy.logwarn)
    except AuthKeyError as err:
        raise ParamError(str(err)) from err


def _agent_trust(options: dict, default: TrustPolicy) -> TrustPolicy:
    """An agent's trusted senders: its ``.mas2j`` option ``trusted_senders``, else the node's."""
    value = options.get("trusted_senders")
    if value is None:
        return default
    if isinstance(value, (list, tuple)):
        names = [str(v) for v in value]
    else:
        names = str(value).strip().strip('"').strip("[]").split(",")
    return TrustPolicy.of(n.strip().strip('"') for n in names)


def _signed_fields(msg: AgentMessage) -> SignedFields:
    return SignedFields.of(msg)


def _seconds(name: str, value: object) -> float:
    """A duration parameter: a finite number of seconds >= 0."""
    try:
        seconds = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        seconds = math.nan
    if not math.isfinite(seconds) or seconds < 0:
        raise ParamError(f"{name} must be a number of seconds >= 0, not {value!r}")
    return seconds


