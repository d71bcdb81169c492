"""The directory facilitator (Jason's ``.df_register``, ``.df_deregister``, ``.df_search``,
``.df_subscribe``): which agent provides which service.

A service is a string (``.df_register("sell(book)")``; another term stands for its text). As
in Jason 3.3's local infrastructure the optional type is accepted and not used to match. A
subscriber is told ``provider(Agent, "service")`` by ``df`` for every provider it did not know
of: those present when it subscribes and every later one.

One :class:`ServiceDirectory` serves a host (a local MAS, or a ROS node and its agents). It
holds the registrations of its own agents and, on ROS, those other hosts published
(:meth:`ServiceDirectory.set_remote`); the host delivers the notices.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import NamedTuple

from .terms import Literal, java_map_order

#: The sender of the directory's ``provider(Agent, Service)`` notices.
DF_NAME = "df"


class Registration(NamedTuple):
    """Agent ``agent`` provides ``service``."""

    agent: str
    service: str


class ProviderNotice(NamedTuple):
    """``subscriber`` is to be told that ``provider`` provides ``service``."""

    subscriber: str
    provider: str
    service: str

    def content(self) -> Literal:
        """The told literal: ``provider(Agent, "service")``."""
        return Literal("provider", (Literal(self.provider), self.service))


class ServiceDirectory:
    """Registrations (local and per remote host) and local subscriptions; thread-safe.

    ``notify`` is called with each :class:`ProviderNotice` for a local subscriber;
    ``changed`` (if given) after the local registrations changed (a ROS node publishes them).
    """

    def __init__(self, notify: Callable[[ProviderNotice], None],
                 changed: Callable[[], None] | None = None) -> None:
        self._notify = notify
        self._changed = changed
        self._local: list[Registration] = []
        self._remote: dict[str, list[Registration]] = {}
        self._subscriptions: list[Registration] = []
        self._lock = threading.Lock()

    # ------------------------------------------------------------ queries
    def _all(self) -> list[Registration]:
        out = list(self._local)
        for regs in self._remote.values():
            out.extend(r for r in regs if r not in out)
        return out

    def search(self, service: str, alive: Callable[[str], bool] | None = None) -> list[str]:
        """The providers of ``service`` (those ``alive`` accepts), in the order Jason's
        ``HashSet`` of names gives them."""
        with self._lock:
            names: list[str] = []
            for r in self._all():
                if r.service == service and r.agent not in names and (alive is None or alive(r.agent)):
                    names.append(r.agent)
        return java_map_order(names, lambda n: n)

    def local_registrations(self) -> list[Registration]:
        with self._lock:
            return list(self._local)

    # ------------------------------------------------------------ changes
    def register(self, agent: str, service: str) -> None:
        reg = Registration(agent, service)
        with self._lock:
            if reg in self._local:
                return
            known = reg in self._all()
            self._local.append(reg)
            notices = [] if known else self._notices_for([reg])
        self._after_local_change(notices)

    def deregister(self, agent: str, service: str) -> None:
        reg = Registration(agent, service)
        with self._lock:
            if reg not in self._local:
                return
            self._local.remove(reg)
        self._after_local_change([])

    def forget_agent(self, agent: str) -> None:
        """A local agent left the host: its registrations and subscriptions go."""
        with self._lock:
            before = len(self._local)
            self._local = [r for r in self._local if r.agent != agent]
            self._subscriptions = [s for s in self._subscriptions if s.agent != agent]
            changed = len(self._local) != before
        if changed:
            self._after_local_change([])

    def subscribe(self, agent: str, service: str) -> None:
        sub = Registration(agent, service)
        with self._lock:
            if sub not in self._subscriptions:
                self._subscriptions.append(sub)
            providers = [r.agent for r in self._all() if r.service == service]
        for p in java_map_order(list(dict.fromkeys(providers)), lambda n: n):
            self._notify(ProviderNotice(agent, p, service))

    def set_remote(self, origin: str, registrations: list[Registration]) -> None:
        """Another host's registrations (all of them, replacing what it said before)."""
        with self._lock:
            before = set(self._all())
            self._remote[origin] = list(registrations)
            new = [r for r in self._all() if r not in before]
            notices = self._notices_for(new)
        for n in notices:
            self._notify(n)

    def _notices_for(self, regs: list[Registration]) -> list[ProviderNotice]:
        return [ProviderNotice(s.agent, r.agent, r.service)
                for r in regs for s in self._subscriptions if s.service == r.service]

    def _after_local_change(self, notices: list[ProviderNotice]) -> None:
        if self._changed is not None:
            self._changed()
        for n in notices:
            self._notify(n)
