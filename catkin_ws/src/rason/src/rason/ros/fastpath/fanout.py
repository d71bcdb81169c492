"""A publisher that writes to its subscribers from the publishing thread, never blocking it.

With ``queue_size`` set, rospy gives every subscriber connection of a publisher its own writer
thread: a message to twenty subscribers wakes twenty threads, one after the other, each waiting
for the GIL before its ``sendall``. In a fleet of twenty agents that hand-off chain was most of
a broadcast's latency (a quarter of a millisecond per subscriber at the median, the twentieth
subscriber served 5 ms after the first and up to 17 ms in the 99th percentile). Without
``queue_size`` rospy writes from the publishing thread with a blocking ``sendall``: one
subscriber that stops reading (a cut link, a stopped process) would then block the agent that
publishes, once the socket's buffer is full.

:func:`direct_publisher` keeps both properties: a :class:`DirectConnection` hands each message
to the kernel at once, from the publishing thread, with a send that never waits; only what the
socket cannot take now (its buffer full) goes to a queue of that connection, which a thread of
its own (started the first time it is needed) writes out, dropping the oldest whole messages
beyond ``queue_size`` as rospy does. A slow subscriber delays only its own messages.
"""

from __future__ import annotations

import collections
import socket
import threading
import warnings
from typing import Any

import rospy
from rospy.exceptions import TransportTerminated


class DirectConnection:
    """Wraps a publisher's connection to one subscriber (a rospy ``TCPROSTransport``).

    ``write_data`` sends from the caller's thread without waiting; the part of a message the
    socket does not take, and every message after it, is written by the connection's own thread
    while the caller goes on. Any other attribute is the wrapped connection's.
    """

    def __init__(self, connection: Any, queue_size: int) -> None:
        self._connection = connection
        self._queue_size = queue_size
        self._lock = threading.Lock()
        self._ready = threading.Condition(self._lock)
        self._rest = b""                      # the unsent end of a message begun by write_data
        self._queue: collections.deque[bytes] = collections.deque()   # whole messages, in order
        self._writing = False                 # the thread is writing outside the lock
        self._error: Exception | None = None  # the thread's write failed: raised to the publisher
        self._thread: threading.Thread | None = None
        connection.set_cleanup_callback(self._on_closed)

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return getattr(self._connection, name)

    def write_data(self, data: bytes) -> bool:
        """Send ``data`` now as far as the socket takes it; queue the rest (never blocks)."""
        failure: OSError | None = None
        with self._lock:
            if self._error is not None:
                error, self._error = self._error, None
                raise error
            if self._rest or self._queue or self._writing:
                self._enqueue(data)           # keep the order behind what waits
                return True
            sock = self._connection.socket
            if sock is None or self._connection.done:
                raise TransportTerminated("connection closed")
            try:
                sent = sock.send(data, socket.MSG_DONTWAIT)
            except (BlockingIOError, InterruptedError):
                sent = 0
            except OSError as err:
                failure = err
            else:
                if sent < len(data):
                    self._rest = data[sent:]  # the message's end cannot be dropped: it is begun
                    self._start_thread()
                    self._ready.notify()
                else:
                    self._connection.stat_bytes += sent
                    self._connection.stat_num_msg += 1
        if failure is not None:
            # outside the lock: closing calls back into _on_closed
            self._connection.close()
            raise TransportTerminated(f"{self._connection.endpoint_id}: {failure}") from failure
        return True

    def _enqueue(self, data: bytes) -> None:
        if self._queue_size > 0 and len(self._queue) >= self._queue_size:
            self._queue.popleft()             # the oldest whole message, as rospy's queue does
        self._queue.append(data)
        self._start_thread()
        self._ready.notify()

    def _start_thread(self) -> None:
        if self._thread is None:
            self._thread = threading.Thread(
                target=self._run, daemon=True,
                name=f"direct-writer-{self._connection.endpoint_id}")
            self._thread.start()

    def _on_closed(self, _connection: Any) -> None:
        with self._lock:
            self._ready.notify()

    def _run(self) -> None:
        while True:
            with self._lock:
                while not (self._rest or self._queue) and not self._connection.done:
                    self._ready.wait()
                if self._connection.done:
                    return
                if self._rest:
                    data, whole, self._rest = self._rest, False, b""
                else:
                    data, whole = self._queue.popleft(), True
                self._writing = True
            try:
                sock = self._connection.socket
                if sock is None:
                    raise TransportTerminated("connection closed")
                sock.sendall(data)            # blocks this thread only
                if whole:
                    self._connection.stat_bytes += len(data)
                    self._connection.stat_num_msg += 1
            except Exception as err:          # the publisher drops the connection on its next write
                self._connection.close()
                with self._lock:
                    self._error = err if isinstance(err, TransportTerminated) else \
                        TransportTerminated(f"{self._connection.endpoint_id}: {err}")
                    self._writing = False
                return
            with self._lock:
                self._writing = False


def direct_publisher(topic: str, data_class: type, queue_size: int, **kwargs: Any) -> rospy.Publisher:
    """A ``rospy.Publisher`` whose subscriber connections are :class:`DirectConnection`\\ s
    (``queue_size``: messages kept per subscriber that cannot take them now; other keyword
    arguments as ``rospy.Publisher``'s)."""
    with warnings.catch_warnings():
        # rospy warns that a publisher without queue_size publishes synchronously: here the
        # connections themselves make publishing asynchronous
        warnings.simplefilter("ignore")
        publisher = rospy.Publisher(topic, data_class, queue_size=None, **kwargs)
    impl = publisher.impl
    if not getattr(impl, "direct_writes", False):     # the topic's first direct publisher here
        add_plain = impl.add_connection
        impl.add_connection = lambda connection: add_plain(DirectConnection(connection, queue_size))
        impl.direct_writes = True
    return publisher
