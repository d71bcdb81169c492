"""RasonNode: one ROS node hosting one or more Jason agents (thesis 5.2).

``rosrun rason agent NAME FILE.asl [__ns:=/robot]`` runs the node ``jason/NAME``;
``rosrun rason mas FILE.mas2j`` hosts every agent of a project file in one node.

Topics (relative names, so one robot per namespace works; un-namespaced it is the thesis):
  jason/action        publish   jason_msgs/Action      actions for the decomposers
  jason/event         subscribe jason_msgs/Event       action_accepted / action_feedback
  jason/perception    subscribe jason_msgs/Perception  per-source perception lists
  /jason/messages     both      jason_msgs/AgentMessage  agent communication and presence (global)
Services:
  jason/NAME/mind     jason_msgs/Mind   the agent's beliefs, desires, intentions, pending actions

Private parameters (``_name:=value`` on the rosrun line):
  ~ack_timeout (2.0)        s of ROS time a decomposer has to acknowledge an action, else the
                            action fails with ``no_decomposer``; 0 disables (thesis decomposers)
  ~action_timeout (120.0)   s an accepted action may run before it fails with ``action_timeout``
  ~perception_mode (replace)  ``replace`` (per-source replacement) or ``queue`` (every message)
  ~perception_functors ([])   functors the agent wants, e.g. [robot, "robot/4"]; [] = all
  ~perception_sources ([])    perception sources the agent wants; [] = all
  ~presence_period (1.0)    s between presence announcements on /jason/messages
  ~presence_timeout (3.5)   s after which a silent agent is forgotten
  ~tro (true)               tail-recursion optimisation (Jason's ``tro`` agent option)
  ~max_intention_depth (10000)  an intention deeper than this fails with error(intention_too_deep)
"""

from __future__ import annotations

import threading
import uuid
from dataclasses import dataclass
from typing import Any

import rospy
from jason_msgs.msg import Action, AgentMessage, Event, Perception
from jason_msgs.srv import Mind, MindResponse

from rason.asl import Agent, AgentOptions, Message, parse_term_text, term_str, term_text
from rason.asl.terms import non_finite_part
from rason.ros.arch import RosAgArch
from rason.ros.badinput import BadInputLog, shorten
from rason.ros.feedback import parse_accepted, parse_feedback
from rason.ros.perceptions import PerceptionFilter
from rason.ros.presence import Directory

MESSAGES_TOPIC = "/jason/messages"
PRESENCE = "presence"     # content "hello": a newcomer asks everyone to announce themselves
GOODBYE = "goodbye"


@dataclass
class HostedAgent:
    """An agent, its architecture and the thread running its reasoning cycle."""

    agent: Agent
    arch: RosAgArch
    thread: threading.Thread


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
        self.agents: dict[str, HostedAgent] = {}
        self.stop = threading.Event()
        self._console_lock = threading.Lock()
        self.bad_input = BadInputLog(rospy.logwarn, rospy.get_time)

        # -- topics (subscriptions start with the agents: see start) -------------------------------
        self.action_pub = rospy.Publisher(self.topic("jason/action"), Action, queue_size=100)
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
        arch = RosAgArch(self, name, perception_filter or self.default_filter)
        agent = Agent(name, source, arch, filename=filename,
                      options=AgentOptions.from_options(options or {}, self.agent_options))
        arch.agent = agent
        self.directory.add_local(name)
        rospy.Service(self.topic(f"jason/{name}/mind"), Mind, lambda _req, a=agent, r=arch: self.mind(a, r))
        thread = threading.Thread(target=self._run_agent, args=(agent,), name=f"agent-{name}",
                                  daemon=True)
        hosted = HostedAgent(agent, arch, thread)
        self.agents[name] = hosted
        return hosted

    def start(self) -> None:
        """Subscribe (latched messages may arrive at once), announce the agents, start them."""
        rospy.Subscriber(self.topic("jason/event"), Event, self.on_event, queue_size=100)
        rospy.Subscriber(self.topic("jason/perception"), Perception, self.on_perception,
                         queue_size=100, tcp_nodelay=True)
        rospy.Subscriber(MESSAGES_TOPIC, AgentMessage, self.on_message, queue_size=200,
                         tcp_nodelay=True)
        rospy.Timer(rospy.Duration(0.05), self.on_check_actions)
        rospy.Timer(rospy.Duration(self._presence_period), self.on_presence)
        for name in self.agents:
            self._announce(name, "hello")
        for hosted in self.agents.values():
            hosted.thread.start()

    def _run_agent(self, agent: Agent) -> None:
        try:
            agent.run(self.stop)
        except Exception as err:
            rospy.logerr("agent %s stopped: %s", agent.name, err)

    def shutdown(self) -> None:
        """Stop every reasoning cycle and say goodbye on the network."""
        self.stop.set()
        for name, hosted in self.agents.items():
            hosted.agent.wake()
            try:
                self._announce(name, GOODBYE)
            except rospy.ROSException:
                pass
        for hosted in self.agents.values():
            hosted.thread.join(2.0)

    # -- output -----------------------------------------------------------------------------------------
    def publish_action(self, agent: str, action_id: int, action) -> None:
        name, args = action.functor, [term_str(arg) for arg in action.args]
        self.action_pub.publish(Action(agent=agent, action_id=action_id, action=name,
                                       parameters=args))

    def publish_message(self, message: Message) -> None:
        self.message_pub.publish(AgentMessage(
            sender=message.sender, receiver=message.receiver or "",
            performative=message.performative, content=term_text(message.content),
            reply_with=message.msg_id or uuid.uuid4().hex[:12],
            in_reply_to=message.in_reply_to or ""))

    def deliver_local(self, message: Message) -> bool:
        """Hand a message to the agents of this process it is for; True if it was only for them.

        Agents hosted together never go through the topic (a message published before the
        topic's connections are up would be lost, and the hop is pointless).
        """
        if message.receiver:
            hosted = self.agents.get(message.receiver)
            if hosted is None:
                return False
            hosted.agent.receive(message)
            return True
        for name, hosted in self.agents.items():
            if name != message.sender:
                hosted.agent.receive(Message(sender=message.sender, receiver=name,
                                             performative=message.performative,
                                             content=message.content, msg_id=message.msg_id))
        return False

    def console(self, agent_name: str, text: str) -> None:
        with self._console_lock:
            print(f"[{agent_name}] {text}", flush=True)

    def _announce(self, name: str, content: str = "") -> None:
        self.message_pub.publish(AgentMessage(sender=name, receiver="", performative=PRESENCE,
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
        now = rospy.get_time()
        if msg.performative == PRESENCE:
            if msg.sender in self.agents:
                return
            if msg.content == GOODBYE:
                self.directory.forget(msg.sender)
                return
            self.directory.heard(msg.sender, now)
            if msg.content == "hello":           # a newcomer: let it know us at once
                for name in self.agents:
                    self._announce(name)
            return
        if msg.sender in self.agents:
            return  # our own publication: delivered in-process already
        self.directory.heard(msg.sender, now)
        receivers = ([msg.receiver] if msg.receiver
                     else [n for n in self.agents if n != msg.sender])
        content = None
        for name in receivers:
            hosted = self.agents.get(name)
            if hosted is None:
                continue
            if content is None:
                content = self._read_content(msg)
                if content is None:
                    return
            hosted.agent.receive(Message(
                sender=msg.sender, receiver=name, performative=msg.performative,
                content=content, msg_id=msg.reply_with, in_reply_to=msg.in_reply_to or None))

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
        for hosted in self.agents.values():
            hosted.arch.check_timeouts(now, self.ack_timeout, self.action_timeout)

    def on_presence(self, _event: rospy.timer.TimerEvent) -> None:
        for name in self.agents:
            self._announce(name)
        for gone in self.directory.expire(rospy.get_time()):
            rospy.loginfo("agent %s not heard for %.1f s: forgotten", gone, self.directory.timeout)

    # -- services ---------------------------------------------------------------------------------------
    def mind(self, agent: Agent, arch: RosAgArch) -> MindResponse:
        mind = agent.mind()
        return MindResponse(agent=agent.name, beliefs=mind.get("beliefs", []),
                            desires=mind.get("desires", []),
                            intentions=mind.get("intentions", []),
                            pending_actions=arch.pending_texts())


def _as_list(value: object) -> list[str]:
    """A list parameter given as a YAML list or as one comma-separated string."""
    if isinstance(value, str):
        return [v for v in value.split(",") if v.strip()]
    return [str(v) for v in value] if isinstance(value, (list, tuple)) else []
