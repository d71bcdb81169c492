"""``rosrun rason mind_inspector [_port:=3272] [_host:=127.0.0.1] [_history:=300]``.

One web page for every agent on the ROS graph (beliefs, events, intentions, actions, messages,
with a history to step back through) and for the robots (poses, what Helper's synthesizer sees,
the camera, the fault injector's diagnostics, a mission's waypoints and who has them). It
listens on the loopback interface unless ``_host:=0.0.0.0`` opens it to other machines.

Its private parameters: ``rosrun rason mind_inspector --help``.
"""

from __future__ import annotations

import asyncio
import contextlib
import signal
import sys
from dataclasses import dataclass

import rospy
from aiohttp import web

from rason.inspector.graph import GraphWatcher
from rason.inspector.store import InspectorStore
from rason.inspector.web import allowed_hosts, make_app
from rosnode_kit.params import exit_on_help, load_or_exit, param

LOOPBACK = ("127.0.0.1", "localhost", "::1")


@dataclass(frozen=True)
class InspectorParams:
    """The mind inspector's private parameters."""

    host: str = param("127.0.0.1", "address to listen on (0.0.0.0: every interface)")
    port: int = param(3272, "TCP port; 0 picks a free one (the address is logged either way)",
                      minimum=0, maximum=65535)
    history: int = param(300, "mind states kept per agent for the page's history", minimum=1)
    history_bytes: int = param(64 * 1024 * 1024, "bytes of mind-state JSON kept for all agents "
                               "together (oldest states go first; a larger state than half of "
                               "it is refused)", minimum=1024)
    max_agents: int = param(1000, "agents listed at most (names heard beyond it are ignored "
                            "until one leaves)", minimum=1)
    allowed_hosts: list = param([], "Host names the page may be reached by besides the address "
                                "listened on (requests naming another host get 403)")
    presence_timeout: float = param(3.5, "s (ROS time) after which a silent agent leaves the page",
                                    minimum=0.01)


async def serve(app: web.Application, host: str, port: int) -> int:
    """Serve until SIGINT/SIGTERM or ROS shutdown; 1 if the address cannot be bound."""
    runner = web.AppRunner(app, access_log=None)
    await runner.setup()
    site = web.TCPSite(runner, host, port)
    try:
        await site.start()
    except OSError as err:
        rospy.logerr("mind inspector: cannot listen on %s:%d: %s", host, port, err)
        await runner.cleanup()
        return 1
    bound = runner.addresses[0][1] if runner.addresses else port
    shown = "127.0.0.1" if host in ("0.0.0.0", "") else host
    scope = ("loopback only; _host:=0.0.0.0 opens it to other machines" if host in LOOPBACK
             else f"listening on {host}: reachable from other machines")
    rospy.loginfo("mind inspector: http://%s:%d/ (%s)", shown, bound, scope)
    loop = asyncio.get_running_loop()
    stop = asyncio.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        loop.add_signal_handler(sig, stop.set)
    rospy.on_shutdown(lambda: _wake(loop, stop))
    await stop.wait()
    await runner.cleanup()
    return 0


def _wake(loop: asyncio.AbstractEventLoop, stop: asyncio.Event) -> None:
    """ROS shutdown: end `serve`; nothing to do once its loop has closed (the server stopped
    first, e.g. on SIGTERM, and main's own signal_shutdown runs this hook afterwards)."""
    with contextlib.suppress(RuntimeError):      # "Event loop is closed"
        loop.call_soon_threadsafe(stop.set)


def main() -> int:
    exit_on_help(sys.argv, InspectorParams, "rosrun rason mind_inspector [_name:=value ...]",
                 "A web page for every agent on the ROS graph and for the robots.")
    rospy.init_node("mind_inspector", disable_signals=True)
    params = load_or_exit(InspectorParams, "mind_inspector")
    store = InspectorStore(params.history, history_bytes=params.history_bytes,
                           max_agents=params.max_agents)
    watcher = GraphWatcher(store, params.presence_timeout)
    watcher.start()
    app = make_app(store, rospy.get_time, lambda pages: watcher.want_camera(pages > 0),
                   allowed_hosts(params.host, params.allowed_hosts))
    try:
        return asyncio.run(serve(app, params.host, params.port))
    finally:
        rospy.signal_shutdown("mind inspector stopped")


if __name__ == "__main__":
    sys.exit(main())
