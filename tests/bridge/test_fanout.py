"""rason.ros.fastpath.fanout: a publisher that writes from the publishing thread and never blocks on a
subscriber that stops reading (real subscriber processes, real TCPROS sockets)."""

from __future__ import annotations

import signal
import sys
import threading
from pathlib import Path

import pytest
import rospy
from polling import wait_until
from std_msgs.msg import String

from rason.process.harness import Process, RosHarness
from rason.ros.fastpath.fanout import direct_publisher

# A subscriber node: prints the sequence number of every message it hears.
READER = """
import sys
import rospy
from std_msgs.msg import String

rospy.init_node("reader", anonymous=True)
rospy.Subscriber(sys.argv[1], String, lambda msg: print("heard", msg.data.split(" ", 1)[0],
                                                         flush=True))
print("reading", flush=True)
rospy.spin()
"""


def _start_readers(ros: RosHarness, tmp_path: Path, topic: str, count: int) -> list[Process]:
    script = tmp_path / "reader.py"
    script.write_text(READER)
    readers = [ros.run([sys.executable, str(script), topic], label=f"reader{i}")
               for i in range(count)]
    for reader in readers:
        reader.wait_for_line("reading", timeout=30)
    return readers


def _wait_connections(publisher: rospy.Publisher, count: int, timeout: float = 20.0) -> None:
    wait_until(lambda: publisher.get_num_connections() == count, f"{count} subscribers connected",
               timeout=timeout, period=0.05)


def _heard(reader: Process) -> list[int]:
    return [int(line.split()[1]) for line in reader.lines() if line.startswith("heard ")]


def _publish_all(publisher: rospy.Publisher, count: int, size: int) -> threading.Thread:
    """Publish messages ``0 .. count-1`` (``size`` bytes each) from a thread of their own."""
    padding = "x" * size

    def publish() -> None:
        for seq in range(count):
            publisher.publish(String(data=f"{seq} {padding}"))

    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    return thread


def test_every_reading_subscriber_gets_every_message_in_order(ros, tmp_path) -> None:
    ros.init_rospy()
    topic = "/fanout_order/chatter"
    publisher = direct_publisher(topic, String, queue_size=1000)
    readers = _start_readers(ros, tmp_path, topic, 3)
    _wait_connections(publisher, 3)

    _publish_all(publisher, 500, 1000).join(30)
    for reader in readers:
        reader.wait_for_line(r"^heard 499$", timeout=30)
        assert _heard(reader) == list(range(500))


@pytest.mark.parametrize("fault", ["stopped", "killed"])
def test_a_subscriber_that_stops_reading_holds_up_neither_the_publisher_nor_the_others(
        ros, tmp_path, fault) -> None:
    """80 MB to a subscriber that reads nothing fill any socket buffers; the publishing thread
    must still return from every publish, and the subscriber that reads must get the last
    message. A stopped subscriber, once it reads again, gets what its queue kept (the newest
    messages, the oldest dropped), in order and unbroken."""
    ros.init_rospy()
    topic = f"/fanout_{fault}/chatter"
    publisher = direct_publisher(topic, String, queue_size=10)
    stuck, reading = _start_readers(ros, tmp_path, topic, 2)
    _wait_connections(publisher, 2)
    stuck.signal_group(signal.SIGSTOP if fault == "stopped" else signal.SIGKILL)

    count = 800
    publishing = _publish_all(publisher, count, 100_000)
    publishing.join(60)
    assert not publishing.is_alive(), "publish() blocked on the subscriber that does not read"
    reading.wait_for_line(rf"^heard {count - 1}$", timeout=60)
    heard = _heard(reading)
    assert heard == sorted(set(heard))          # in order, none twice

    if fault == "stopped":
        stuck.signal_group(signal.SIGCONT)
        stuck.wait_for_line(rf"^heard {count - 1}$", timeout=60)
        late = _heard(stuck)
        assert late == sorted(set(late))
        assert len(late) < count                # the queue dropped the oldest beyond its size
    else:
        _wait_connections(publisher, 1)         # the dead subscriber's connection is dropped
        publisher.publish(String(data=f"{count} after"))
        reading.wait_for_line(rf"^heard {count}$", timeout=30)
