"""Helpers of the ROS tests: write and start real ``rosrun rason agent`` nodes, read their minds."""

from __future__ import annotations

import textwrap
import xmlrpc.client
from collections.abc import Iterable
from pathlib import Path

import rosgraph
import rospy
import yaml
from polling import wait_until
from std_srvs.srv import SetBool

from rason.process.harness import HarnessError, Process, RosHarness
from rason.ros.auth import write_new_key


def write_agent(folder: Path, name: str, source: str) -> Path:
    """``folder/NAME.asl`` holding `source` (dedented), in UTF-8 as agents read it."""
    path = folder / f"{name}.asl"
    path.write_text(textwrap.dedent(source), encoding="utf-8")
    return path


def start_agent(ros: RosHarness, folder: Path, name: str, source: str, ns: str,
                env: dict[str, str] | None = None, cwd: Path | None = None,
                **params: object) -> Process:
    """``rosrun rason agent NAME FILE.asl __ns:=ns _param:=value...`` (with ``env`` added to
    its environment, run in ``cwd``), waited for until its ``jason/NAME/mind`` service is up."""
    path = write_agent(folder, name, source)
    proc = ros.rosrun("rason", "agent", name, str(path), ns=ns, params=params, env=env, cwd=cwd)
    ros.wait_for_service(f"{ns}/jason/{name}/mind", watch=[proc])
    return proc


def mind(ros: RosHarness, ns: str, name: str, timeout: float = 10.0) -> dict[str, list[str]]:
    """The agent's mind through its service (``rosservice call``, a separate process)."""
    out = ros.check_output(["rosservice", "call", f"{ns}/jason/{name}/mind"], timeout=timeout)
    answer = yaml.safe_load(out)
    return {key: list(answer.get(key) or []) for key in
            ("beliefs", "desires", "intentions", "pending_actions")}


def connected_to(publisher, node: str) -> bool:
    """True once rospy `publisher` has a connection to the subscriber node `node` (full name)."""
    return any(getattr(c, "endpoint_id", "") == node for c in publisher.impl.connections)


def outgoing_connections(ros: RosHarness, node: str) -> set[tuple[str, str]] | None:
    """The (topic, subscriber node) pairs node ``node`` (full name, another process) publishes
    to now: its bus info (the ROS slave API's ``getBusInfo``); None if it cannot be asked."""
    caller = "/rason_test_bus_info"
    try:
        uri = rosgraph.Master(caller, master_uri=ros.master_uri).lookupNode(node)
        code, _, info = xmlrpc.client.ServerProxy(uri).getBusInfo(caller)
    except (OSError, rosgraph.MasterException, xmlrpc.client.Error):
        return None
    # each connection: (id, other end, direction, transport, topic, ...)
    return {(c[4], c[1]) for c in info if c[2] == "o"} if code == 1 else None


def connected_from(ros: RosHarness, node: str, topic: str, subscriber: str) -> bool:
    """True once node ``node`` publishes ``topic`` to the subscriber node ``subscriber``."""
    return (topic, subscriber) in (outgoing_connections(ros, node) or set())


def wait_heard(ros: RosHarness, node: str, topics: Iterable[str], timeout: float = 20.0,
               watch: Iterable[Process] = ()) -> None:
    """Wait until node ``node`` (full name, another process) publishes each of ``topics`` to
    this process's rospy node (its bus info): what it then publishes once, unlatched, reaches
    our subscribers (a subscriber registered with the master may connect seconds later)."""
    wanted = {(topic, rospy.get_name()) for topic in topics}
    wait_until(lambda: wanted <= (outgoing_connections(ros, node) or set()),
               f"our subscribers of {sorted(t for t, _ in wanted)} connected to {node}",
               timeout=timeout, watch=watch)


def subscribed_by(ros: RosHarness, topic: str, node: str) -> bool:
    """True once node ``node`` (full name) is a subscriber of ``topic`` on the master (on a
    global topic such as /jason/messages, any subscriber may be another test's node: a node
    killed by SIGKILL stays registered)."""
    return node in ros.subscribers(topic)


def player_connected(ros: RosHarness, player: str) -> bool:
    """True once every subscriber of every topic the ``rosbag play`` node ``player`` (full name:
    start it with ``__name:=``, so that an earlier player the master still lists is not taken
    for it) publishes is connected to it (its bus info, read once): a player started with
    ``--pause`` may then be resumed (:func:`resume_player`) without a subscriber missing the
    first messages, however long connecting took."""
    try:
        published = [topic for topic, nodes in ros.topics().items() if player in nodes]
        wanted = {(topic, sub) for topic in published for sub in ros.subscribers(topic)}
    except (OSError, HarnessError):
        return False
    if not published:
        return False
    connected = outgoing_connections(ros, player)
    return connected is not None and wanted <= connected


def resume_player(player: str) -> None:
    """Resume a ``rosbag play --pause`` node (its ``pause_playback`` service, false); rospy
    initialised on ``ros`` (``ros.init_rospy()``)."""
    rospy.wait_for_service(f"{player}/pause_playback", timeout=20)
    rospy.ServiceProxy(f"{player}/pause_playback", SetBool)(False)


def key_file(folder: Path, name: str) -> Path:
    """A fresh shared key (``~auth_key_file``) in ``folder/NAME``, readable by its owner only."""
    return write_new_key(folder / name)
