"""A subscriber that reads its connections' messages with less work than rospy.

rospy's ``TCPROSTransport.receive_once`` goes through a ``BytesIO`` (seek, tell, read, a copy
to compact it), sets the socket blocking again and checks for shutdown around every message.
An agent node in a fleet hears every other agent's broadcasts and presence beats: twenty agents
on two cores make each broadcast wake nineteen processes at once, and what each spends before
its agent sees the message is what the last of them waits for. A :class:`FrameReader` takes the
place of ``receive_once`` on each connection of a :func:`framed_subscriber`: one ``bytearray``,
the frames (a 4-byte length, then the serialized message) cut out of it as they complete, the
same messages, headers and statistics as rospy's, and rospy's loop, reconnection and callbacks
around it unchanged.

A message type whose fields are all strings, string arrays and times (the agent nodes'
AgentMessage, Event and Perception) is read by a :class:`FlatDecoder`, a loop over its fields,
instead of genpy's generated ``deserialize``, which first fills a new message with defaults
(a ``genpy.Time`` among them) and then replaces every one of them: the same message for half
the work.

A framed subscriber can also lower the priority of its reading threads (``nice``; the agent
nodes do for ``/jason/messages``, their ``~receive_nice``) and ask a short scheduling slice for
them (``slice_s``, their ``~receive_slice``). A broadcast is written by its sender's agent
thread to every receiver in turn, and each write wakes a receiver: on a short CPU those woken
readers took the core from the sender between its writes, so the last receivers heard a
broadcast many milliseconds after the first. Readers at a lower priority let the sender finish
its writes first; the work is the same, its order favours what is under way. (In an agent node
a reader also runs the reasoning its message starts in an idle agent, see ``Agent.receive``'s
``run_here``: that work gives way too.) The slice is for Linux's EEVDF scheduler (6.12 and
later; older kernels ignore it): among the threads ready to run, one that asks for shorter
slices gets the CPU sooner, for less time at a time. A reader's work for a message takes a
fraction of a millisecond, the kernel's default slice 1.4 ms on a 2-core machine: with it a
woken reader waited behind whole slices of the others woken with it and of longer jobs.

One difference, on purpose: a frame that does not deserialize is dropped with a rate-limited
warning and the connection goes on (the length prefix keeps the stream in step), where rospy
would drop the connection and every message behind it.
"""

from __future__ import annotations

import ctypes
import errno
import os
import platform
import struct
import threading
import weakref
from typing import Any

import genpy
import rospy
from rospy.exceptions import TransportException, TransportTerminated
from rospy.impl.tcpros_base import TCPROSTransport

from rosnode_kit.badinput import shorten
from rosnode_kit.guard import WARNINGS

_LENGTH = struct.Struct("<I")
_TIME = struct.Struct("<2I")
_RETRY = (errno.EAGAIN, errno.EWOULDBLOCK, errno.EINTR)
#: the field types a :class:`FlatDecoder` reads
FLAT_FIELD_TYPES = frozenset({"string", "string[]", "time"})
_NSEC_PER_SEC = 1_000_000_000
#: the largest nice value (the lowest priority) Linux has
MAX_NICE = 19
#: the shortest and longest slice (s) Linux grants a thread that asks for one
MIN_SLICE_S, MAX_SLICE_S = 0.0001, 0.1
#: ``sched_setattr``'s system call number, by machine (``platform.machine()``)
_SYS_SCHED_SETATTR = {"x86_64": 314, "aarch64": 274, "armv7l": 380, "armv6l": 380, "i686": 351}
_SCHED_OTHER = 0


class FlatDecoder:
    """Deserializes one message type whose fields are all of :data:`FLAT_FIELD_TYPES`."""

    def __init__(self, data_class: Any) -> None:
        self.data_class = data_class
        # one type per slot (genpy); the robot side's Python 3.8 has no zip(strict=True)
        types = data_class._slot_types
        self.fields = [(name, types[i]) for i, name in enumerate(data_class.__slots__)]

    @staticmethod
    def reads(data_class: Any) -> bool:
        """Can a FlatDecoder read messages of `data_class`?"""
        return all(kind in FLAT_FIELD_TYPES for kind in data_class._slot_types)

    def decode(self, frame: bytes) -> Any:
        """The message `frame` holds, equal to genpy's; ``struct.error`` or ``ValueError`` when
        it holds none, ``UnicodeDecodeError`` for a string that is not UTF-8."""
        message = self.data_class.__new__(self.data_class)
        pos = 0
        for name, kind in self.fields:
            value: Any
            if kind == "string":
                (size,) = _LENGTH.unpack_from(frame, pos)
                pos += 4 + size
                value = frame[pos - size:pos].decode()
            elif kind == "time":
                secs, nsecs = _TIME.unpack_from(frame, pos)
                pos += 8
                value = genpy.Time.__new__(genpy.Time)
                value.secs, value.nsecs = secs, nsecs
                if nsecs >= _NSEC_PER_SEC:
                    value.canon()
            else:
                (count,) = _LENGTH.unpack_from(frame, pos)
                pos += 4
                value = []
                for _ in range(count):
                    (size,) = _LENGTH.unpack_from(frame, pos)
                    pos += 4 + size
                    value.append(frame[pos - size:pos].decode())
            setattr(message, name, value)
        if pos != len(frame):      # a string running past the end, or bytes left over
            raise ValueError(f"{len(frame)}-byte frame, {pos} bytes of fields")
        return message


class FrameReader:
    """Reads the messages of one subscriber connection (a rospy ``TCPROSTransport``) in place of
    its ``receive_once``: returns the messages complete so far, blocking until there is one."""

    def __init__(self, connection: TCPROSTransport, nice: int = 0, slice_s: float = 0.0) -> None:
        # weak: the connection holds this reader's method, and a cycle would keep a dropped
        # connection's socket open until the garbage collector runs (rospy leaves some sockets
        # of connections it dropped mid-connect to reference counting: a publisher waits up to
        # 60 s for the header of such a socket, and serves no other subscriber meanwhile)
        self._connection = weakref.ref(connection)
        self._socket: Any = None
        self._buffer = bytearray()
        # the decoder of the connection's message type, chosen for the first frames: a
        # FlatDecoder, or None for genpy's code (the type is the subscription's, fixed)
        self._decoded_class: Any = None
        self._flat: FlatDecoder | None = None
        self._nice = nice                  # added to the reading thread's nice value
        self._slice_s = slice_s            # the reading thread's slice (0: the kernel's)
        self._scheduled = False            # nice and slice set for the reading thread

    def receive_once(self) -> list[Any]:
        """The next messages, oldest first (rospy's contract: raises ``TransportTerminated``
        when the publisher closed the connection, ``TransportException`` when it is not made)."""
        connection = self._connection()
        if connection is None:
            raise TransportTerminated("connection dropped")
        sock = connection.socket
        protocol = connection.protocol      # the subscription's queue_size and buff_size
        handshake = connection.read_buff
        # None: not made yet, or closed meanwhile by another thread (rospy's close clears them)
        if sock is None or protocol is None or handshake is None:
            raise TransportException("connection not initialized")
        if sock is not self._socket:
            self._start_reading(sock, handshake)
        buffer = self._buffer
        while not connection.done and not rospy.is_shutdown():
            frames = self._complete_frames(protocol.queue_size)
            if frames:
                messages = self._messages(connection, frames, protocol.recv_data_class)
                if messages:
                    return messages
            try:
                data = sock.recv(protocol.buff_size)
            except OSError as err:
                if err.errno in _RETRY:
                    continue
                raise TransportTerminated(f"unable to receive data from sender: {err}") from err
            if not data:
                raise TransportTerminated("unable to receive data from sender, check sender's "
                                          "logs for details")
            buffer += data
            connection.stat_bytes += len(data)
        return []

    def _start_reading(self, sock: Any, handshake: Any) -> None:
        """A new socket (connected, or connected again): start from what its handshake read
        past the header, which rospy leaves in the connection's ``read_buff``."""
        self._socket = sock
        sock.setblocking(True)
        if not self._scheduled:      # once: a reconnection reads in the same thread
            self._scheduled = True
            if self._nice:
                lower_thread_priority(self._nice)
            if self._slice_s:
                request_thread_slice(self._slice_s)
        self._buffer = bytearray(handshake.getvalue()[:handshake.tell()])
        handshake.seek(0)
        handshake.truncate()

    def _complete_frames(self, queue_size: int | None) -> list[bytes]:
        """Cut the complete frames out of the buffer (only the newest ``queue_size``, as
        rospy keeps)."""
        buffer = self._buffer
        end = len(buffer)
        frames = []
        start = 0
        while end - start >= 4:
            (size,) = _LENGTH.unpack_from(buffer, start)
            if end - start - 4 < size:
                break
            frames.append(bytes(buffer[start + 4:start + 4 + size]))
            start += 4 + size
        if start:
            del buffer[:start]
        if queue_size and len(frames) > queue_size:
            del frames[:-queue_size]
        return frames

    def _messages(self, connection: TCPROSTransport, frames: list[bytes],
                  data_class: Any) -> list[Any]:
        if data_class is not self._decoded_class:
            self._decoded_class = data_class
            self._flat = FlatDecoder(data_class) if FlatDecoder.reads(data_class) else None
        flat = self._flat
        messages = []
        for frame in frames:
            try:
                message = _decode(frame, flat, data_class)
            except Exception as err:    # genpy raises DeserializationError, or worse
                WARNINGS.warn(f"undecodable {connection.name}", (
                    f"dropped a {len(frame)}-byte {data_class._type} from "
                    f"{connection.callerid_pub} on {connection.name} that does not "
                    f"deserialize: {type(err).__name__}: {shorten(str(err))}"))
                continue
            message._connection_header = connection.header
            messages.append(message)
        connection.stat_num_msg += len(messages)
        if connection.is_latched and messages:
            connection.latch = messages[-1]
        return messages


def _decode(frame: bytes, flat: FlatDecoder | None, data_class: Any) -> Any:
    """The message in `frame`: by `flat` when given, else (or for text that is not UTF-8,
    whose characters genpy replaces, and logs once) by genpy's generated code."""
    if flat is not None:
        try:
            return flat.decode(frame)
        except UnicodeDecodeError:
            pass
    message = data_class()
    message.deserialize(frame)
    return message


def lower_thread_priority(by: int) -> None:
    """Add `by` to the calling thread's nice value (Linux: a nice value per thread; raising it
    needs no privilege). A failure is a warning: the thread reads on at its priority."""
    thread = threading.get_native_id()
    try:
        nice = os.getpriority(os.PRIO_PROCESS, thread)
        os.setpriority(os.PRIO_PROCESS, thread, min(MAX_NICE, nice + by))
    except OSError as err:
        WARNINGS.warn("nice", f"a receiving thread keeps its priority: {err}")


class _SchedAttr(ctypes.Structure):
    """Linux's ``struct sched_attr`` (``sched_setattr(2)``)."""

    _fields_ = [("size", ctypes.c_uint32), ("sched_policy", ctypes.c_uint32),
                ("sched_flags", ctypes.c_uint64), ("sched_nice", ctypes.c_int32),
                ("sched_priority", ctypes.c_uint32), ("sched_runtime", ctypes.c_uint64),
                ("sched_deadline", ctypes.c_uint64), ("sched_period", ctypes.c_uint64),
                ("sched_util_min", ctypes.c_uint32), ("sched_util_max", ctypes.c_uint32)]


def request_thread_slice(seconds: float) -> None:
    """Ask Linux to run the calling thread in slices of `seconds` (clamped to
    [:data:`MIN_SLICE_S`, :data:`MAX_SLICE_S`]; EEVDF, Linux 6.12 and later, needs no privilege;
    older kernels ignore it). The thread keeps its policy and nice value. A failure is a
    warning: the thread runs on with the kernel's slice."""
    thread = threading.get_native_id()
    seconds = min(MAX_SLICE_S, max(MIN_SLICE_S, seconds))
    try:
        attr = _SchedAttr(size=ctypes.sizeof(_SchedAttr), sched_policy=_SCHED_OTHER,
                          sched_nice=os.getpriority(os.PRIO_PROCESS, thread),
                          sched_runtime=round(seconds * _NSEC_PER_SEC))
        number = _SYS_SCHED_SETATTR.get(platform.machine())
        if number is None:
            raise OSError(errno.ENOSYS, f"sched_setattr unknown on {platform.machine()}")
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.syscall(number, thread, ctypes.byref(attr), 0) != 0:
            raise OSError(ctypes.get_errno(), os.strerror(ctypes.get_errno()))
    except OSError as err:
        WARNINGS.warn("slice", f"a receiving thread keeps the kernel's slice: {err}")


def framed_subscriber(topic: str, data_class: type, callback: Any, queue_size: int | None = None,
                      nice: int = 0, slice_s: float = 0.0, **kwargs: Any) -> rospy.Subscriber:
    """A ``rospy.Subscriber`` whose connections are read by :class:`FrameReader`\\ s (arguments
    as ``rospy.Subscriber``'s); ``nice`` is added to the nice value of each connection's reading
    thread and ``slice_s`` (when not 0) is asked for as its slice (the topic's first framed
    subscriber in the process decides)."""
    subscriber = rospy.Subscriber(topic, data_class, callback, queue_size=queue_size, **kwargs)
    impl = subscriber.impl
    if not getattr(impl, "framed_reads", False):     # the topic's first framed subscriber here
        add_plain = impl.add_connection

        def add_connection(connection: Any) -> bool:
            if isinstance(connection, TCPROSTransport):
                connection.receive_once = FrameReader(connection, nice, slice_s).receive_once
            return add_plain(connection)

        impl.add_connection = add_connection
        impl.framed_reads = True
    return subscriber
