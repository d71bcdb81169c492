"""The inspector's web server (aiohttp): the page, its static files, a JSON API, pushed events.

Routes (anything else is 404; a wrong method 405; a malformed query 400):

  GET /                              the page (static/index.html)
  GET /static/{file}                 its JavaScript and CSS, served from the package
  GET /api/agents                    the agents present: name, topic, namespace, history bounds
  GET /api/agents/{name}/mind        the latest mind state; ?index=N for state N of the history
  GET /api/robots                    poses, trails, perceptions, diagnostics, camera frame info,
                                     the missions the agents believe they have
  GET /api/camera/{robot}.jpg        the robot's last camera frame as JPEG
  GET /api/events                    server-sent events: ``hello`` (every agent, the robots),
                                     then ``agent`` (one agent's summary: new or changed),
                                     ``gone`` (its name), ``mind`` (agent, index), ``robots``
                                     (at most ROBOTS_HZ a second), ``clock``

Every request whose ``Host`` header does not name the address the inspector listens on (or one
of ``~allowed_hosts``) gets 403: a web page the browser loaded from elsewhere cannot read the
agents' minds by making its own name resolve to this address (DNS rebinding).
"""

from __future__ import annotations

import asyncio
import contextlib
import fcntl
import json
import re
import socket
import struct
from collections.abc import Callable, Iterable
from importlib import resources
from pathlib import Path

import cv2
import numpy as np
from aiohttp import web

from rason.inspector.store import MAX_NAME, CameraFrame, InspectorStore

ROBOTS_HZ = 5.0
KEEPALIVE_S = 15.0
MAX_CLIENTS = 32
CLIENT_QUEUE = 256
NAME = re.compile(rf"^[A-Za-z0-9_][A-Za-z0-9_.-]{{0,{MAX_NAME - 1}}}$")
LOOPBACK_NAMES = frozenset({"127.0.0.1", "localhost", "::1"})
EVERY_INTERFACE = ("0.0.0.0", "", "::")
SIOCGIFADDR = 0x8915            # Linux ioctl: an interface's IPv4 address


def allowed_hosts(listen: str, extra: Iterable[str] = ()) -> frozenset[str]:
    """Host names a request may carry: the address listened on (with the loopback names when
    that is a loopback or every interface, and then also this machine's name and addresses),
    plus `extra`."""
    names = {host_name(listen)} | {host_name(h) for h in extra if h.strip()}
    if listen in LOOPBACK_NAMES or listen in EVERY_INTERFACE:
        names |= LOOPBACK_NAMES
    if listen in EVERY_INTERFACE:
        machine = socket.gethostname()
        names |= {machine.lower(), socket.getfqdn().lower()} | interface_addresses()
        try:
            names |= set(socket.gethostbyname_ex(machine)[2])
        except OSError:
            pass
    return frozenset(names - {""})


def interface_addresses() -> set[str]:
    """This machine's IPv4 (one per interface) and IPv6 addresses (Linux)."""
    found: set[str] = set()
    with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as sock:
        for _index, interface in socket.if_nameindex():
            try:
                request = struct.pack("256s", interface[:15].encode())
                found.add(socket.inet_ntoa(fcntl.ioctl(sock.fileno(), SIOCGIFADDR,
                                                       request)[20:24]))
            except OSError:          # no IPv4 address on this interface
                pass
    with contextlib.suppress(OSError):
        for line in Path("/proc/net/if_inet6").read_text().split("\n"):
            if line.strip():
                packed = bytes.fromhex(line.split()[0])
                found.add(socket.inet_ntop(socket.AF_INET6, packed))
    return found


def host_name(host: str) -> str:
    """The name part of a Host header (``[::1]:80`` -> ``::1``, ``Example.org.:80`` ->
    ``example.org``)."""
    host = host.strip().lower()
    if host.startswith("["):
        return host[1:host.find("]")] if "]" in host else host
    if host.count(":") == 1:
        host = host.rsplit(":", 1)[0]
    return host.rstrip(".")


def static_dir() -> Path:
    """The page's files, inside the installed package (devel or install space alike)."""
    return Path(str(resources.files("rason.inspector") / "static"))


class EventHub:
    """Fan-out of pushed events to the connected pages (each has a bounded queue)."""

    def __init__(self, on_clients: Callable[[int], None] | None = None) -> None:
        self.queues: set[asyncio.Queue] = set()
        self.on_clients = on_clients or (lambda n: None)

    def publish(self, kind: str, payload: dict) -> None:
        text = f"event: {kind}\ndata: {json.dumps(payload, separators=(',', ':'))}\n\n"
        for queue in list(self.queues):
            if queue.full():        # a page that does not read: drop it, it reconnects
                self.queues.discard(queue)
                _close(queue)
                continue
            queue.put_nowait(text)

    def connect(self) -> asyncio.Queue | None:
        if len(self.queues) >= MAX_CLIENTS:
            return None
        queue: asyncio.Queue = asyncio.Queue(maxsize=CLIENT_QUEUE)
        self.queues.add(queue)
        self.on_clients(len(self.queues))
        return queue

    def disconnect(self, queue: asyncio.Queue) -> None:
        self.queues.discard(queue)
        self.on_clients(len(self.queues))


def _close(queue: asyncio.Queue) -> None:
    """End a page's event stream: what it did not read yet is dropped."""
    while not queue.empty():
        queue.get_nowait()
    queue.put_nowait(None)


def host_check(hosts: frozenset[str]):
    """Middleware refusing (403) the requests whose Host header is not one of `hosts`."""
    @web.middleware
    async def check(request: web.Request, handler):
        given = request.headers.get("Host", "")
        if host_name(given) not in hosts:
            raise _error(web.HTTPForbidden, f"Host {given[:100]!r} is not this inspector's "
                         "address (see ~allowed_hosts)")
        return await handler(request)
    return check


#: The application's state, typed (aiohttp's AppKey): the store, the page hub, ROS time, and
#: the task pushing the robots' poses.
STORE = web.AppKey("store", InspectorStore)
HUB = web.AppKey("hub", EventHub)
CLOCK: web.AppKey[Callable[[], float]] = web.AppKey("clock")
ROBOTS_TASK = web.AppKey("robots_task", asyncio.Task)


def make_app(store: InspectorStore, clock: Callable[[], float],
             on_clients: Callable[[int], None] | None = None,
             hosts: frozenset[str] = LOOPBACK_NAMES) -> web.Application:
    """The application; `clock` gives ROS time (for action ages), `on_clients` the page count,
    `hosts` the Host names it answers (:func:`allowed_hosts`)."""
    app = web.Application(middlewares=[host_check(hosts)])
    hub = EventHub(on_clients)
    app[STORE], app[HUB], app[CLOCK] = store, hub, clock

    async def bind_loop(app: web.Application) -> None:
        loop = asyncio.get_running_loop()
        def push(kind: str, payload: dict) -> None:
            loop.call_soon_threadsafe(hub.publish, kind, payload)

        store.on_change = push
        app[ROBOTS_TASK] = asyncio.create_task(_push_robots(app))

    async def stop_tasks(app: web.Application) -> None:
        app[ROBOTS_TASK].cancel()
        for queue in list(hub.queues):
            _close(queue)
        store.on_change = lambda kind, payload: None

    app.on_startup.append(bind_loop)
    app.on_shutdown.append(stop_tasks)
    static = static_dir()
    async def index(_request: web.Request) -> web.StreamResponse:
        return web.FileResponse(static / "index.html")

    app.router.add_get("/", index)
    app.router.add_static("/static", static, show_index=False, follow_symlinks=False)
    app.router.add_get("/api/agents", agents)
    app.router.add_get("/api/agents/{name}/mind", mind)
    app.router.add_get("/api/robots", robots)
    app.router.add_get("/api/camera/{robot}.jpg", camera)
    app.router.add_get("/api/events", events)
    return app


def _error(status: type[web.HTTPException], text: str) -> web.HTTPException:
    return status(text=json.dumps({"error": text}), content_type="application/json")


async def agents(request: web.Request) -> web.Response:
    store: InspectorStore = request.app[STORE]
    return web.json_response({"agents": store.agents(), "now": request.app[CLOCK]()})


async def mind(request: web.Request) -> web.Response:
    store: InspectorStore = request.app[STORE]
    name = request.match_info["name"]
    if not NAME.match(name):
        raise _error(web.HTTPBadRequest, f"not an agent name: {name!r}")
    index = None
    unknown = set(request.query) - {"index"}
    if unknown:
        raise _error(web.HTTPBadRequest, f"unknown query parameter(s): {', '.join(sorted(unknown))}")
    if "index" in request.query:
        text = request.query["index"]
        if not text.isdigit() or len(text) > 18:
            raise _error(web.HTTPBadRequest, f"index must be a whole number >= 0, not {text!r}")
        index = int(text)
    if not store.known(name):
        raise _error(web.HTTPNotFound, f"no agent named {name!r} has been seen")
    found = store.mind_text(name, index)
    if found is None:
        what = "no mind state yet" if index is None else f"state {index} is not in the history"
        raise _error(web.HTTPNotFound, f"agent {name!r}: {what}")
    bounds, state = found            # the state as it came, spliced in (never parsed again)
    head = json.dumps({**bounds, "now": request.app[CLOCK]()})
    return web.Response(text=f'{head[:-1]}, "state": {state}}}', content_type="application/json")


async def robots(request: web.Request) -> web.Response:
    store: InspectorStore = request.app[STORE]
    return web.json_response({**store.robots.snapshot(), "now": request.app[CLOCK]()})


async def camera(request: web.Request) -> web.Response:
    store: InspectorStore = request.app[STORE]
    robot = request.match_info["robot"]
    if not NAME.match(robot):
        raise _error(web.HTTPBadRequest, f"not a robot name: {robot!r}")
    frame = store.robots.frame(robot)
    if frame is None:
        raise _error(web.HTTPNotFound, f"no camera frame from {robot!r} (yet)")
    data = await asyncio.get_running_loop().run_in_executor(None, _jpeg, frame)
    if data is None:
        raise _error(web.HTTPNotFound, f"cannot show {robot}'s frame ({frame.encoding})")
    return web.Response(body=data, content_type="image/jpeg",
                        headers={"Cache-Control": "no-store"})


def _jpeg(frame: CameraFrame) -> bytes | None:
    channels = {"rgb8": 3, "bgr8": 3, "mono8": 1}.get(frame.encoding)
    if channels is None or len(frame.data) < frame.width * frame.height * channels:
        return None
    pixels = np.frombuffer(frame.data, np.uint8)[:frame.width * frame.height * channels]
    image: np.ndarray = pixels.reshape(frame.height, frame.width, channels)
    if frame.encoding == "rgb8":
        image = cv2.cvtColor(image, cv2.COLOR_RGB2BGR)
    ok, encoded = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, 80])
    return encoded.tobytes() if ok else None


async def events(request: web.Request) -> web.StreamResponse:
    hub: EventHub = request.app[HUB]
    store: InspectorStore = request.app[STORE]
    queue = hub.connect()
    if queue is None:
        raise _error(web.HTTPServiceUnavailable, "too many pages open")
    response = web.StreamResponse(headers={"Content-Type": "text/event-stream",
                                           "Cache-Control": "no-store"})
    try:
        await response.prepare(request)
        hello = {"agents": store.agents(), "robots": store.robots.snapshot(),
                 "now": request.app[CLOCK]()}
        await response.write(f"event: hello\ndata: {json.dumps(hello)}\n\n".encode())
        while True:
            try:
                text = await asyncio.wait_for(queue.get(), KEEPALIVE_S)
            except TimeoutError:
                text = ": keep-alive\n\n"
            if text is None:
                break
            await response.write(text.encode())
    except (ConnectionResetError, asyncio.CancelledError):
        pass
    finally:
        hub.disconnect(queue)
    return response


async def _push_robots(app: web.Application) -> None:
    """The robots' view and the ROS clock, at most ROBOTS_HZ a second, when something changed."""
    store: InspectorStore = app[STORE]
    hub: EventHub = app[HUB]
    sent = -1
    while True:
        await asyncio.sleep(1.0 / ROBOTS_HZ)
        if not hub.queues:
            continue
        now = app[CLOCK]()
        if store.robots.version != sent:
            snapshot = store.robots.snapshot()
            sent = snapshot["version"]
            hub.publish("robots", {**snapshot, "now": now})
        else:
            hub.publish("clock", {"now": now})
