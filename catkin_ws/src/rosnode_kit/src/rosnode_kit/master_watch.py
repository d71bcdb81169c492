"""Register a rospy node again when the ROS master restarts.

rospy registers a node's publishers, subscribers and services once, at start (and each new one
as it is created). A master that is restarted (same URI) starts empty: the node keeps running,
its existing peer-to-peer connections keep working, but nobody new can find it, its services
are gone from ``rosservice list`` and it never hears of publishers that start later.

:class:`MasterWatch` asks the master every ``period`` seconds whether it knows this node
(``lookupNode``), over one HTTP connection kept alive between questions (a new connection for
each question made the master accept it and start a thread for it, every second for every node:
in a fleet of twenty robots, half of the master's CPU). When a master answers that does not know
the node, it registers everything the node has again, hands each subscription the publishers
the master lists (so connections to them are made, as rospy does at start) and runs the node's
own re-announcement callbacks (e.g. to set its parameters again). The watch uses wall time on
purpose: while there is no master, simulated time (``/clock``) may have stopped too.

Usage, right after ``rospy.init_node``::

    MasterWatch(on_registered=[declare_params]).start()
"""

from __future__ import annotations

import http.client
import threading
import xmlrpc.client
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

import rosgraph
import rospy
import rospy.core
import rospy.impl.registration as registration

#: Seconds between two questions to the master.
DEFAULT_PERIOD = 1.0
#: Seconds an XML-RPC call to the master may take before it counts as unanswered.
CALL_TIMEOUT = 2.0


class _TimeoutTransport(xmlrpc.client.Transport):
    """XML-RPC over HTTP with a socket timeout (a hung master must not hang the watch)."""

    def make_connection(self, host: tuple[str, dict[str, str]] | str) -> http.client.HTTPConnection:
        connection = super().make_connection(host)
        connection.timeout = CALL_TIMEOUT
        return connection


@dataclass
class Registration:
    """What one re-registration registered again."""

    publishers: int
    subscribers: int
    services: int


class MasterWatch:
    """A daemon thread that re-registers this rospy node with a restarted master."""

    def __init__(self, period: float = DEFAULT_PERIOD,
                 on_registered: Iterable[Callable[[], None]] = ()) -> None:
        self.period = period
        self.on_registered = list(on_registered)
        self.registrations: list[Registration] = []
        self._stop = threading.Event()
        self._master_missing = False
        self._replaced = False
        self._thread = threading.Thread(target=self._run, name="master-watch", daemon=True)
        # one connection, kept alive between questions (the master speaks HTTP/1.1); a failed
        # question closes it (xmlrpc.client does), and a master that restarted closed it: the
        # transport connects again for the next question
        self._master: Any = xmlrpc.client.ServerProxy(rosgraph.get_master_uri(),   # untyped
                                                      transport=_TimeoutTransport())

    def start(self) -> MasterWatch:
        rospy.on_shutdown(self._stop.set)
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()

    def _run(self) -> None:
        while not self._stop.wait(self.period) and not rospy.is_shutdown():
            try:
                self.check()
            except Exception as err:            # never let the watch die: it is the safety net
                rospy.logwarn_throttle(30.0, f"master watch: {err}")

    def check(self) -> Registration | None:
        """Ask the master about this node once; register again if it does not know it."""
        master = self._master
        caller_id = rospy.get_caller_id()
        try:
            code, _msg, uri = master.lookupNode(caller_id, caller_id)
        except (OSError, http.client.HTTPException, xmlrpc.client.Error):
            if not self._master_missing:
                self._master_missing = True
                rospy.logwarn("the ROS master at %s does not answer; will register again "
                              "when it is back", rosgraph.get_master_uri())
            return None
        if code == 1:
            if uri != rospy.core.get_node_uri() and not self._replaced:
                self._replaced = True      # registering would make the master shut that one down
                rospy.logwarn("another node (%s) now has the name %s on the ROS master: not "
                              "registering again", uri, caller_id)
            self._master_missing = False
            return None
        if not _registered_at_start():
            return None                          # rospy's own first registration is running
        done = self._register(master, caller_id)
        self._master_missing = False
        self.registrations.append(done)
        rospy.loginfo("registered again with the restarted ROS master: %d publishers, "
                      "%d subscribers, %d services", done.publishers, done.subscribers,
                      done.services)
        for callback in self.on_registered:
            try:
                callback()
            except Exception as err:
                rospy.logwarn("after registering again with the master: %s", err)
        return done

    def _register(self, master: Any, caller_id: str) -> Registration:
        node_uri = rospy.core.get_node_uri()
        topics = registration.get_topic_manager()
        services = registration.get_service_manager()
        publications = topics.get_publications()
        subscriptions = topics.get_subscriptions()
        served = services.get_services()
        for name, data_type in publications:
            _ok(master.registerPublisher(caller_id, name, data_type, node_uri), name)
        manager = _reg_manager()
        for name, data_type in subscriptions:
            publishers = _ok(master.registerSubscriber(caller_id, name, data_type, node_uri),
                             name)
            if manager is not None:
                manager.publisher_update(name, publishers)   # connect to those already back
        for name, service_uri in served:
            _ok(master.registerService(caller_id, name, service_uri, node_uri), name)
        return Registration(len(publications), len(subscriptions), len(served))


def _ok(answer: tuple[int, str, object], name: str) -> object:
    code, msg, value = answer
    if code != 1:
        raise RuntimeError(f"the master refused {name}: {msg}")
    return value


def _reg_manager() -> registration.RegManager | None:
    """rospy's registration manager (it makes the connections to publishers we are told of)."""
    listeners = registration.get_registration_listeners()
    with listeners.lock:
        for listener in listeners.listeners:
            if isinstance(listener, registration.RegManager):
                return listener
    return None


def _registered_at_start() -> bool:
    manager = _reg_manager()
    return manager is not None and manager.is_registered()


def watch_master(on_registered: Iterable[Callable[[], None]] = ()) -> MasterWatch:
    """Start a :class:`MasterWatch` for this rospy node (call after ``rospy.init_node``)."""
    return MasterWatch(on_registered=on_registered).start()

