"""RasonNode: one ROS node hosting one or more Jason agents (thesis 5.2).

``rosrun rason agent NAME FILE.asl [__ns:=/robot]`` runs the node ``jason/NAME``;
``rosrun rason mas FILE.mas2j`` hosts every agent of a project file in one node.

Topics (relative names, so one robot per namespace works; un-namespaced it is the thesis):
  jason/action        publish   jason_msgs/Action      actions for the decomposers
  jason/cancel        publish   jason_msgs/ActionCancel  actions the agent gave up (stop them)
  jason/event         subscribe jason_msgs/Event       action_accepted / action_feedback
  jason/perception    subscribe jason_msgs/Perception  per-source perception lists
  /jason/messages     both      jason_msgs/AgentMessage  agent communication and presence (global)
Services:
  jason/NAME/mind     jason_msgs/Mind   the agent's beliefs, desires, intentions, pending actions
Topic jason/NAME/mind_state (std_msgs/String, latched): the mind as JSON for the mind inspector
  (rason.ros.mind_state), published on change at most ~mind_state_rate times a second.

Private parameters (``_name:=value`` on the rosrun line):
  ~ack_timeout (2.0)        s of ROS time a decomposer has to acknowledge an action, else the
                            action fails with ``no_decomposer``; 0 disables (thesis decomposers)
  ~action_timeout (120.0)   s an accepted action may run before it fails with ``action_timeout``
  ~perception_mode (replace)  ``replace`` (per-source replacement) or ``queue`` (every message)
  ~perception_functors ([])   functors the agent wants, e.g. [robot, "robot/4"]; [] = all
  ~perception_sources ([])    perception sources the agent wants; [] = all
  ~presence_period (1.0)    s between presence announcements on /jason/messages
  ~presence_timeout (3.5)   s after which a silent agent is forgotten
  ~internal_actions ([])    Python modules whose @internal_action functions the agents get
                            (read by rason.ros.main before the agents load)
  ~perception_ttl (0.0)     s of ROS time a perception source may stay silent before its list is
                            cleared (its percepts are removed); 0 = a list stands until replaced.
                            Applies to sources that declare no TTL of their own (see below)
  ~perception_ttls ({})     per-source TTLs, e.g. "{robot_synthesizer_robot: 0.3}"; they win
                            over the source's own declaration and over ~perception_ttl
  ~auth_key_file ("")       file holding the shared key that signs and checks every message on
                            /jason/messages; "" = no authentication (anyone may send anything)
  ~auth_window (10.0)       s of ROS time a signed message stays acceptable (replay protection)
  ~trusted_senders ([])     senders that may use tellHow, untellHow, askHow, achieve, unachieve
                            with the agents of this node; [] = everyone (in a .mas2j, per agent:
                            ``trusted_senders="[boss]"``)
A perception source declares its own TTL as the parameter ``jason/perception_ttl/<source>`` in
the robot's namespace (the robot synthesizer does, from its ``~perception_ttl``).
  ~tro (true)               tail-recursion optimisation (Jason's ``tro`` agent option)
  ~max_intention_depth (10000)  an intention deeper than this fails with error(intention_too_deep)
  ~mind_state_rate (10.0)   Hz at most of jason/NAME/mind_state (on change); 0 = not published
"""

from __future__ import annotations

import math
import threading
import time
import uuid
from dataclasses import dataclass

import rosgraph.names
import rospy
import yaml
from jason_msgs.msg import Action, ActionCancel, AgentMessage, Event, Perception
from jason_msgs.srv import Mind, MindResponse

from rason.asl import Agent, AgentOptions, Message, parse_term, term_str
from rason.ros.arch import RosAgArch
from rason.ros.auth import (
    AuthKeyError,
    MessageAuth,
    SignedFields,
    TrustPolicy,
    Verdict,
    load_key,
    new_nonce,
)
from rason.ros.feedback import CancelReason, parse_accepted, parse_feedback
from rason.ros.guard import RateLimitedWarnings, clip, guarded
from rason.ros.mind_state import MindStatePublisher, latched_publisher, mind_state_topic
from rason.ros.perceptions import PerceptionFilter
from rason.ros.presence import GOODBYE, HELLO, MESSAGES_TOPIC, PRESENCE, Directory


@dataclass
class HostedAgent:
    """An agent, its architecture and the thread running its reasoning cycle."""

    agent: Agent
    arch: RosAgArch
    thread: threading.Thread
    mind_state: MindStatePublisher | None = None


class RasonNode:
    """The ROS side of a process hosting agents: topics, services, timers, presence."""

    def __init__(self, base_ns: str = "/") -> None:
        self.base_ns = base_ns if base_ns.endswith("/") else base_ns + "/"
        # -- parameters ---------------------------------------------------------------------------
        self.ack_timeout = float(rospy.get_param("~ack_timeout", 2.0))
        self.action_timeout = float(rospy.get_param("~action_timeout", 120.0))
        self.perception_mode = str(rospy.get_param("~perception_mode", "replace"))
        self.default_filter = PerceptionFilter.from_lists(
            _as_list(rospy.get_param("~perception_functors", [])),
            _as_list(rospy.get_param("~perception_sources", [])))
        presence_period = float(rospy.get_param("~presence_period", 1.0))
        self.directory = Directory(float(rospy.get_param("~presence_timeout", 3.5)))
        self.agent_options = AgentOptions(
            tro=bool(rospy.get_param("~tro", AgentOptions.tro)),
            max_intention_depth=int(rospy.get_param("~max_intention_depth",
                                                    AgentOptions.max_intention_depth)))
        self.mind_state_rate = float(rospy.get_param("~mind_state_rate", 10.0))
        self.default_perception_ttl = _seconds("~perception_ttl", rospy.get_param(
            "~perception_ttl", 0.0))
        self.perception_ttls = {str(source): _seconds(f"~perception_ttls/{source}", ttl)
                                for source, ttl in _as_map(rospy.get_param("~perception_ttls",
                                                                           {})).items()}
        self._declared_ttls: dict[str, float | None] = {}
        self.auth = _message_auth(str(rospy.get_param("~auth_key_file", "") or ""),
                                  _seconds("~auth_window", rospy.get_param("~auth_window", 10.0)))
        self.trust = TrustPolicy.of(_as_list(rospy.get_param("~trusted_senders", [])))
        self.drops = RateLimitedWarnings(period=10.0)
        self.agents: dict[str, HostedAgent] = {}
        self.stop = threading.Event()
        self._console_lock = threading.Lock()

        # -- topics (subscriptions start with the agents: see start) -------------------------------
        self.action_pub = rospy.Publisher(self.topic("jason/action"), Action, queue_size=100)
        self.cancel_pub = rospy.Publisher(self.topic("jason/cancel"), ActionCancel, queue_size=100)
        self.message_pub = rospy.Publisher(MESSAGES_TOPIC, AgentMessage, queue_size=100)
        self._presence_period = presence_period

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
        agent = Agent(name, source, arch, filename=filename,
                      options=AgentOptions.from_options(options or {}, self.agent_options))
        arch.agent = agent
        self.directory.add_local(name)
        rospy.Service(self.topic(f"jason/{name}/mind"), Mind, lambda _req, a=agent, r=arch: self.mind(a, r))
        thread = threading.Thread(target=self._run_agent, args=(agent,), name=f"agent-{name}",
                                  daemon=True)
        hosted = HostedAgent(agent, arch, thread)
        if self.mind_state_rate > 0:
            hosted.mind_state = MindStatePublisher(
                agent, arch.pending_actions,
                latched_publisher(mind_state_topic(self.base_ns, name)),
                rospy.get_name(), self.base_ns)
            arch.on_cycle = hosted.mind_state.at_cycle
        self.agents[name] = hosted
        return hosted

    def start(self) -> None:
        """Subscribe (latched messages may arrive at once), announce the agents, start them."""
        # Every callback is guarded: a bad message costs a warning, never a timer or the node.
        rospy.Subscriber(self.topic("jason/event"), Event, guarded("jason/event")(self.on_event),
                         queue_size=100)
        rospy.Subscriber(self.topic("jason/perception"), Perception,
                         guarded("jason/perception")(self.on_perception),
                         queue_size=100, tcp_nodelay=True)
        rospy.Subscriber(MESSAGES_TOPIC, AgentMessage, guarded(MESSAGES_TOPIC)(self.on_message),
                         queue_size=200, tcp_nodelay=True)
        rospy.Timer(rospy.Duration(0.05), guarded("action timeouts")(self.on_check_actions))
        rospy.Timer(rospy.Duration(0.05), guarded("perception TTLs")(self.on_check_perceptions))
        rospy.Timer(rospy.Duration(self._presence_period), guarded("presence")(self.on_presence))
        if self.mind_state_rate > 0:
            rospy.Timer(rospy.Duration(1.0 / self.mind_state_rate),
                        guarded("mind_state")(self.on_mind_state))
        for name in self.agents:
            self._announce(name, HELLO)
        for hosted in self.agents.values():
            hosted.thread.start()

    def on_master_restarted(self) -> None:
        """Registered again with a restarted master: ask everyone to announce themselves."""
        for name in self.agents:
            self._announce(name, "hello")

    def _run_agent(self, agent: Agent) -> None:
        try:
            agent.run(self.stop)
        except Exception as err:
            rospy.logerr("agent %s stopped: %s", agent.name, err)

    def shutdown(self) -> None:
        """Stop every reasoning cycle, cancel the pending actions, say goodbye on the network."""
        self.stop.set()
        cancelled = 0
        for name, hosted in self.agents.items():
            hosted.agent.wake()
            cancelled += hosted.arch.cancel_all(CancelReason.SHUTDOWN)
            try:
                self._announce(name, GOODBYE)
            except rospy.ROSException:
                pass
        if cancelled:
            time.sleep(0.1)       # let the cancels leave before the connections close
        for hosted in self.agents.values():
            hosted.thread.join(2.0)

    # -- output -----------------------------------------------------------------------------------------
    def publish_action(self, agent: str, action_id: int, action) -> None:
        name, args = action.functor, [term_str(arg) for arg in action.args]
        self.action_pub.publish(Action(agent=agent, action_id=action_id, action=name,
                                       parameters=args))

    def publish_cancel(self, agent: str, action_id: int, reason: str) -> None:
        """Tell the decomposers that `agent` gave action `action_id` up."""
        try:
            self.cancel_pub.publish(ActionCancel(agent=agent, action_id=action_id, reason=reason))
        except rospy.ROSException as err:     # shutting down: the goodbye still stops it
            rospy.logwarn("cannot cancel action %d of %s: %s", action_id, agent, err)
        else:
            rospy.loginfo("[%s] cancelled action %d (%s)", agent, action_id, reason)

    def publish_message(self, message: Message) -> None:
        self._publish(AgentMessage(
            sender=message.sender, receiver=message.receiver or "",
            performative=message.performative, content=term_str(message.content),
            reply_with=message.msg_id or uuid.uuid4().hex[:12],
            in_reply_to=message.in_reply_to or ""))

    def _publish(self, msg: AgentMessage) -> None:
        """Stamp, and sign when this node has a key, then publish on /jason/messages."""
        msg.stamp = rospy.Time.now()
        msg.nonce = new_nonce()
        if self.auth is not None:
            msg.signature = self.auth.sign(_signed_fields(msg))
        self.message_pub.publish(msg)

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
        for name, hosted in self.agents.items():
            if name != message.sender:
                self._receive(hosted, Message(sender=message.sender, receiver=name,
                                              performative=message.performative,
                                              content=message.content, msg_id=message.msg_id))
        return False

    def _receive(self, hosted: HostedAgent, message: Message) -> None:
        """Give `message` to a hosted agent if its acceptance hook lets it in."""
        if not hosted.arch.accepts(message):
            self.drops.warn(f"untrusted {clip(message.sender, 64)}",
                            f"[{hosted.arch.name}] dropped {message.performative} from "
                            f"'{message.sender}': not a trusted sender")
            return
        hosted.agent.receive(message)
        self.note_message(hosted.agent.name, message, outgoing=False)

    def note_message(self, agent_name: str, message: Message, outgoing: bool) -> None:
        """Keep a message `agent_name` received or sent for its published mind."""
        hosted = self.agents.get(agent_name)
        if hosted is not None and hosted.mind_state is not None:
            hosted.mind_state.note_message(message, outgoing, rospy.get_time())

    def console(self, agent_name: str, text: str) -> None:
        with self._console_lock:
            print(f"[{agent_name}] {text}", flush=True)

    def _announce(self, name: str, content: str = "") -> None:
        self._publish(AgentMessage(sender=name, receiver="", performative=PRESENCE,
                                   content=content, reply_with="", in_reply_to=""))

    # -- callbacks --------------------------------------------------------------------------------------
    def on_event(self, msg: Event) -> None:
        hosted = self.agents.get(msg.agent)
        if hosted is None:
            return  # another agent's event: ignored (thesis 5.2)
        accepted = parse_accepted(msg)
        if accepted is not None:
            hosted.arch.on_accepted(accepted)
            return
        feedback = parse_feedback(msg)
        if feedback is not None:
            hosted.arch.on_feedback(feedback)
        elif msg.event_type == "action_feedback":
            rospy.logwarn("unreadable action_feedback for %s: %s", msg.agent, list(msg.parameters))

    def on_perception(self, msg: Perception) -> None:
        for hosted in self.agents.values():
            hosted.arch.on_perception(msg.source, msg.perception)

    def on_message(self, msg: AgentMessage) -> None:
        if msg.sender in self.agents:
            return  # our own publication (delivered in-process already), or a forgery of it
        now = rospy.get_time()
        if self.auth is not None:
            verdict = self.auth.verify(_signed_fields(msg), msg.signature,
                                       rospy.get_rostime().to_nsec())
            if verdict is not Verdict.OK:
                self.drops.warn(f"{verdict.value} {clip(msg.sender, 64)}",
                                f"dropped a {verdict.value} {msg.performative or '?'} message "
                                f"claiming to be from '{msg.sender}'")
                return
        if msg.performative == PRESENCE:
            if msg.content == GOODBYE:
                self.directory.forget(msg.sender)
                rospy.loginfo("agent %s said goodbye: forgotten", msg.sender)
                return
            if self.directory.heard(msg.sender, now):   # new, or back after a lapse
                rospy.loginfo("agent %s present", msg.sender)
            if msg.content == HELLO:           # a newcomer: let it know us at once
                for name in self.agents:
                    self._announce(name)
            return
        if self.directory.heard(msg.sender, now):   # known from its message before its presence
            rospy.loginfo("agent %s present", msg.sender)
        receivers = ([msg.receiver] if msg.receiver
                     else [n for n in self.agents if n != msg.sender])
        for name in receivers:
            hosted = self.agents.get(name)
            if hosted is None:
                continue
            try:
                content = parse_term(msg.content)
            except Exception as err:
                rospy.logwarn("[%s] dropped message from %s with unreadable content %r: %s",
                              name, msg.sender, msg.content, err)
                continue
            self._receive(hosted, Message(
                sender=msg.sender, receiver=name, performative=msg.performative,
                content=content, msg_id=msg.reply_with, in_reply_to=msg.in_reply_to or None))

    def on_check_actions(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.get_time()
        for hosted in self.agents.values():
            hosted.arch.check_timeouts(now, self.ack_timeout, self.action_timeout)

    def on_check_perceptions(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.get_time()
        for hosted in self.agents.values():
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
        except ParameterError as err:
            rospy.logwarn("%s: using ~perception_ttl", err)
            return None

    def on_presence(self, _event: rospy.timer.TimerEvent) -> None:
        for name in self.agents:
            self._announce(name)
        for gone in self.directory.expire(rospy.get_time()):
            rospy.loginfo("agent %s not heard for %.1f s: forgotten", gone, self.directory.timeout)

    def on_mind_state(self, _event: rospy.timer.TimerEvent) -> None:
        now = rospy.get_time()
        for hosted in self.agents.values():
            if hosted.mind_state is not None:
                try:
                    hosted.mind_state.tick(now)
                except Exception as err:  # the inspector's view must never stop the agent
                    rospy.logwarn_throttle(10.0, "[%s] mind_state not published: %s",
                                           hosted.agent.name, err)

    # -- services ---------------------------------------------------------------------------------------
    def mind(self, agent: Agent, arch: RosAgArch) -> MindResponse:
        mind = agent.mind()
        return MindResponse(agent=agent.name, beliefs=mind.get("beliefs", []),
                            desires=mind.get("desires", []),
                            intentions=mind.get("intentions", []),
                            pending_actions=arch.pending_texts())


class ParameterError(ValueError):
    """A node parameter with an unusable value."""


def _message_auth(key_file: str, window: float) -> MessageAuth | None:
    """The node's authentication, or None (open) without a key file."""
    if not key_file:
        return None
    try:
        return MessageAuth(load_key(key_file, warn=rospy.logwarn), window)
    except AuthKeyError as err:
        raise ParameterError(f"~auth_key_file: {err}") from err


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
    return SignedFields(msg.sender, msg.receiver, msg.performative, msg.content, msg.reply_with,
                        msg.in_reply_to, msg.stamp.to_nsec(), msg.nonce)


def _seconds(name: str, value: object) -> float:
    """A duration parameter: a finite number of seconds >= 0."""
    try:
        seconds = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        seconds = math.nan
    if not math.isfinite(seconds) or seconds < 0:
        raise ParameterError(f"{name} must be a number of seconds >= 0, not {value!r}")
    return seconds


def _as_map(value: object) -> dict[str, object]:
    """A map parameter given as a YAML map (rosrun's ``_p:="{a: 1}"``) or as a YAML string."""
    if isinstance(value, str):
        try:
            value = yaml.safe_load(value) if value.strip() else {}
        except yaml.YAMLError as err:
            raise ParameterError(f"not a map: {value!r} ({err})") from err
    if not isinstance(value, dict):
        raise ParameterError(f"not a map: {value!r}")
    return value


def _as_list(value: object) -> list[str]:
    """A list parameter given as a YAML list or as one comma-separated string."""
    if isinstance(value, str):
        return [v for v in value.split(",") if v.strip()]
    return [str(v) for v in value] if isinstance(value, (list, tuple)) else []
