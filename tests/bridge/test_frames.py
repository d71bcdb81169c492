"""rason.ros.fastpath.frames: a subscriber connection's messages read without rospy's per-message work.

The connection-level tests drive a real rospy ``TCPROSTransport`` over a real socket pair, with
a real TCPROS handshake written by the publishing end; the last test is a framed subscriber in
this process hearing a real publisher process.
"""

from __future__ import annotations

import gc
import io
import os
import socket
import struct
import sys
import threading
import weakref
from collections.abc import Iterator

import genpy
import pytest
from geometry_msgs.msg import Twist
from hypothesis import given, settings
from hypothesis import strategies as st
from jason_msgs.msg import AgentMessage, Event, Perception
from nav_msgs.msg import Odometry
from polling import wait_until
from rosgraph.network import write_ros_handshake_header
from rospy.exceptions import TransportException, TransportTerminated
from rospy.impl.tcpros_base import TCPROSTransport
from rospy.impl.tcpros_pubsub import TCPROSSub

from rason.process.procstat import sched_slice
from rason.ros.fastpath.frames import FlatDecoder, FrameReader, framed_subscriber


def _message(seq: int, content: str = "") -> AgentMessage:
    return AgentMessage(sender=f"a{seq}", receiver="", performative="tell",
                        content=content or f"ping({seq})", reply_with=str(seq), in_reply_to="")


def _frame(message: AgentMessage) -> bytes:
    body = io.BytesIO()
    message.serialize(body)
    data = body.getvalue()
    return len(data).to_bytes(4, "little") + data


def _handshake() -> bytes:
    """What a publisher answers a subscriber: its TCPROS header."""
    out = io.BytesIO()

    class Sink:
        def sendall(self, data: bytes) -> None:
            out.write(data)

    write_ros_handshake_header(Sink(), {"md5sum": AgentMessage._md5sum, "type": AgentMessage._type,
                                        "callerid": "/publisher", "topic": "/t"})
    return out.getvalue()


def _tcp_pair() -> tuple[socket.socket, socket.socket]:
    """Both ends of a TCP connection on loopback (as TCPROS runs), Nagle off."""
    with socket.create_server(("127.0.0.1", 0)) as server:
        client = socket.create_connection(server.getsockname())
        accepted, _ = server.accept()
    for end in (client, accepted):
        end.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
    return accepted, client


class Link:
    """A subscriber connection (rospy's class, FrameReader installed) and its publisher's end."""

    def __init__(self, queue_size: int | None = None, nice: int = 0, slice_s: float = 0.0) -> None:
        self.publisher, subscriber = _tcp_pair()
        self.connection = TCPROSTransport(TCPROSSub("/t", AgentMessage, queue_size=queue_size),
                                          "/t")
        self.connection.socket = subscriber
        self.connection.receive_once = FrameReader(self.connection, nice, slice_s).receive_once

    def handshake(self, then: bytes = b"") -> None:
        """The publisher's header (and ``then`` in the same write); the subscriber reads it
        as rospy does after connecting."""
        self.publisher.sendall(_handshake() + then)
        self.connection.read_header()

    def read(self, count: int) -> list[AgentMessage]:
        messages: list[AgentMessage] = []
        while len(messages) < count:
            messages += self.connection.receive_once()
        return messages

    def close(self) -> None:
        self.publisher.close()
        self.connection.close()


@pytest.fixture
def link() -> Iterator[Link]:
    made = Link()
    yield made
    made.close()


@settings(max_examples=40, deadline=None)
@given(sizes=st.lists(st.integers(0, 3000), min_size=1, max_size=12),
       cuts=st.lists(st.integers(1, 700), min_size=1, max_size=30))
def test_messages_cut_anywhere_by_the_network_arrive_whole_and_in_order(sizes, cuts) -> None:
    link = Link()
    try:
        sent = [_message(i, "x" * size) for i, size in enumerate(sizes)]
        stream = b"".join(_frame(m) for m in sent)
        link.handshake()
        received: list[AgentMessage] = []
        start = 0
        for cut in cuts * (len(stream) // sum(cuts) + 1):
            if start >= len(stream):
                break
            link.publisher.sendall(stream[start:start + cut])
            start = min(len(stream), start + cut)
            # read what is complete so far (receive_once blocks only when nothing is)
            while _complete_up_to(stream, start) > len(received):
                received += link.connection.receive_once()
        received += link.read(len(sent) - len(received))
        assert [(m.sender, m.content) for m in received] == [(m.sender, m.content) for m in sent]
        assert all(m._connection_header["callerid"] == "/publisher" for m in received)
        assert link.connection.stat_num_msg == len(sent)
    finally:
        link.close()


def _complete_up_to(stream: bytes, end: int) -> int:
    """How many whole frames ``stream[:end]`` holds."""
    count, start = 0, 0
    while start + 4 <= end:
        size = int.from_bytes(stream[start:start + 4], "little")
        if start + 4 + size > end:
            break
        count, start = count + 1, start + 4 + size
    return count


def test_what_the_handshake_read_past_the_header_comes_first(link) -> None:
    # the publisher's header and its first two messages in one write: rospy's handshake reads
    # them together and leaves the messages in the connection's read buffer
    link.handshake(then=_frame(_message(0)) + _frame(_message(1)))
    link.publisher.sendall(_frame(_message(2)))
    assert [m.content for m in link.read(3)] == ["ping(0)", "ping(1)", "ping(2)"]


def test_a_frame_that_does_not_deserialize_is_dropped_and_the_stream_goes_on(ros, link) -> None:
    ros.init_rospy()            # the warning is rate-limited in ROS time
    link.handshake()
    garbage = b"\xff" * 9                       # a string length far beyond the frame
    link.publisher.sendall(_frame(_message(0)) + len(garbage).to_bytes(4, "little") + garbage
                           + _frame(_message(2)))
    assert [m.content for m in link.read(2)] == ["ping(0)", "ping(2)"]


def test_more_complete_frames_than_the_queue_keeps_only_the_newest() -> None:
    link = Link(queue_size=3)
    try:
        link.handshake(then=b"".join(_frame(_message(i)) for i in range(10)))
        assert [m.content for m in link.connection.receive_once()] == \
            ["ping(7)", "ping(8)", "ping(9)"]
    finally:
        link.close()


def test_the_publisher_closing_ends_the_connection(link) -> None:
    link.handshake(then=_frame(_message(0)))
    link.publisher.close()
    assert [m.content for m in link.connection.receive_once()] == ["ping(0)"]
    with pytest.raises(TransportTerminated):
        link.connection.receive_once()


def test_a_connection_closed_by_another_thread_meanwhile_is_not_initialized(link) -> None:
    # rospy's close clears the socket, the read buffer and the protocol one after the other: a
    # reader between two of them sees a connection not (or no longer) made, as rospy's own does
    link.handshake(then=_frame(_message(0)))
    assert [m.content for m in link.connection.receive_once()] == ["ping(0)"]
    link.connection.protocol = None
    with pytest.raises(TransportException):
        link.connection.receive_once()


def test_a_dropped_connection_is_freed_at_once_with_its_socket() -> None:
    # rospy leaves the socket of a connection it dropped mid-connect to reference counting: a
    # cycle through the reader would keep it open (and its publisher waiting) until a collection
    link = Link()
    dropped = weakref.ref(link.connection)
    gc.disable()
    try:
        link.connection = None
        assert dropped() is None
    finally:
        gc.enable()
        link.publisher.close()


_TEXT = st.text(max_size=40)
_TIME = st.builds(genpy.Time, st.integers(0, 2**32 - 1), st.integers(0, 999_999_999))
#: every message type an agent node reads with a FlatDecoder, with any field values
_FLAT_MESSAGES = st.one_of(
    st.builds(AgentMessage, sender=_TEXT, receiver=_TEXT, performative=_TEXT, content=_TEXT,
              reply_with=_TEXT, in_reply_to=_TEXT, stamp=_TIME, nonce=_TEXT, signature=_TEXT),
    st.builds(Event, agent=_TEXT, event_type=_TEXT, parameters=st.lists(_TEXT, max_size=5)),
    st.builds(Perception, source=_TEXT, perception=st.lists(_TEXT, max_size=5)))


def _body(message) -> bytes:
    return _frame(message)[4:]


@settings(max_examples=200, deadline=None)
@given(message=_FLAT_MESSAGES)
def test_a_flat_decoder_reads_what_genpy_reads(message) -> None:
    data_class = type(message)
    assert FlatDecoder.reads(data_class)
    body = _body(message)
    by_genpy = data_class()
    by_genpy.deserialize(body)
    decoded = FlatDecoder(data_class).decode(body)
    assert decoded == by_genpy == message
    for name, kind in zip(data_class.__slots__, data_class._slot_types, strict=True):
        assert type(getattr(decoded, name)) is type(getattr(by_genpy, name)), (name, kind)


@settings(max_examples=50, deadline=None)
@given(message=_FLAT_MESSAGES, data=st.data())
def test_a_flat_decoder_refuses_a_frame_cut_short_or_too_long(message, data) -> None:
    body = _body(message)
    decoder = FlatDecoder(type(message))
    cut = data.draw(st.integers(0, len(body) - 1))
    with pytest.raises((struct.error, ValueError)):
        decoder.decode(body[:cut])
    with pytest.raises(ValueError):
        decoder.decode(body + b"\0")


def test_a_message_type_with_other_fields_is_read_by_genpy() -> None:
    assert not FlatDecoder.reads(Twist) and not FlatDecoder.reads(Odometry)


def test_text_that_is_not_utf8_arrives_with_its_characters_replaced_as_genpy_does(link) -> None:
    link.handshake()
    body = bytearray(_body(_message(0, "caf\u00e9")))
    body[body.index("\u00e9".encode())] = 0xFF     # the e-acute's first byte, now invalid
    link.publisher.sendall(len(body).to_bytes(4, "little") + bytes(body) + _frame(_message(1)))
    received = link.read(2)
    assert received[0].content == "caf\ufffd\ufffd"       # both bytes of the broken character
    assert received[1].content == "ping(1)"


def _thread_nice() -> int:
    return os.getpriority(os.PRIO_PROCESS, threading.get_native_id())


def test_a_reader_lowers_the_priority_of_its_own_thread_once() -> None:
    link = Link(nice=3)
    seen: dict[str, object] = {}

    def read() -> None:               # as rospy does: a thread of its own per connection
        seen["before"] = _thread_nice()
        link.handshake(then=_frame(_message(0)))
        seen["first"] = [m.content for m in link.read(1)]
        seen["after"] = _thread_nice()
        link.publisher.close()        # the publisher comes back: a new socket, the same thread
        link.publisher, link.connection.socket = _tcp_pair()
        link.publisher.sendall(_frame(_message(1)))
        seen["again"] = [m.content for m in link.read(1)]
        seen["after reconnecting"] = _thread_nice()

    caller = _thread_nice()
    reader = threading.Thread(target=read)
    try:
        reader.start()
        reader.join(10)
        assert seen["first"] == ["ping(0)"] and seen["again"] == ["ping(1)"]
        assert seen["before"] == caller
        assert seen["after"] == seen["after reconnecting"] == min(caller + 3, 19)
        assert _thread_nice() == caller           # only the reading thread
    finally:
        link.close()


def thread_slice() -> int:
    """The scheduling slice (ns) Linux gives the calling thread."""
    return sched_slice("/proc/thread-self/sched")


def test_a_reader_asks_its_slice_for_its_own_thread_once() -> None:
    link = Link(slice_s=0.0003)
    seen: dict[str, object] = {}

    def read() -> None:
        seen["before"] = thread_slice()
        link.handshake(then=_frame(_message(0)))
        seen["first"] = [m.content for m in link.read(1)]
        seen["after"] = thread_slice()
        seen["nice"] = _thread_nice()

    caller, nice = thread_slice(), _thread_nice()
    reader = threading.Thread(target=read)
    try:
        reader.start()
        reader.join(10)
        assert seen["first"] == ["ping(0)"]
        assert seen["before"] == caller != 300_000
        assert seen["after"] == 300_000 and seen["nice"] == nice    # the nice value is kept
        assert thread_slice() == caller           # only the reading thread
    finally:
        link.close()


def test_a_framed_subscriber_hears_a_publisher_process(ros, tmp_path) -> None:
    ros.init_rospy()
    heard: list[AgentMessage] = []
    subscriber = framed_subscriber("/frames_test/messages", AgentMessage, heard.append,
                                   queue_size=1000)
    script = tmp_path / "talker.py"
    script.write_text(TALKER)
    try:
        ros.run([sys.executable, str(script), "/frames_test/messages"], label="talker")
        wait_until(lambda: len(heard) >= 300, "300 messages heard", timeout=30, period=0.05)
        assert [m.content for m in heard] == [f"ping({i})" for i in range(300)]
        # big ones in between: frames cut across reads
        assert {len(m.reply_with) for m in heard} == {1, 100_000}
        assert all(m._connection_header["callerid"].startswith("/talker") for m in heard)
    finally:
        subscriber.unregister()


TALKER = """
import sys
import rospy
from jason_msgs.msg import AgentMessage

rospy.init_node("talker", anonymous=True)
pub = rospy.Publisher(sys.argv[1], AgentMessage, queue_size=1000)
while pub.get_num_connections() == 0:      # a child process: no tests/polling.py here
    rospy.sleep(0.05)
rospy.sleep(0.5)
for i in range(300):
    pub.publish(AgentMessage(sender="t", performative="tell", content=f"ping({i})",
                             reply_with="x" * (100_000 if i % 50 == 7 else 1)))
rospy.spin()
"""
