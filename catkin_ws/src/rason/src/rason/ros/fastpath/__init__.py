"""rospy's internals replaced for speed, behind one switch back to stock rospy.

Three changes reach into rospy 1.15's internals (``rospy.impl``): :mod:`.frames` reads a
subscriber's connections with one buffer per connection instead of rospy's per-message
``BytesIO`` work (and decodes flat messages without genpy's defaults), :mod:`.fanout` writes a
publisher's messages to each subscriber from the publishing thread without ever blocking it,
:mod:`.accept` handles each inbound connection in a thread of its own (installed with the first
publisher), so one that never sends its header cannot stop the node accepting others.
Nodes ask this module, never those two, for their publishers and subscribers:
:func:`publisher` and :func:`subscriber` give the fast ones, or plain ``rospy.Publisher`` /
``rospy.Subscriber`` when the environment variable ``RASON_STOCK_ROSPY`` is set to ``1``
(read when each one is made). The fast paths were written against :data:`ROSPY_VERSION`;
``tests/bridge/test_fastpath.py`` fails once the installed rospy is another, so an upgrade is
checked before it is trusted.
"""

from __future__ import annotations

import os
import threading
from typing import Any

import rospy

from rason.ros.fastpath.accept import threaded_accept
from rason.ros.fastpath.fanout import direct_publisher
from rason.ros.fastpath.frames import MAX_NICE, MAX_SLICE_S, framed_subscriber

__all__ = ["MAX_NICE", "MAX_SLICE_S", "ROSPY_VERSION", "STOCK_ENV", "publisher", "stock",
           "subscriber"]

#: the rospy release whose internals frames and fanout replace (Debian 12's python3-rospy)
ROSPY_VERSION = "1.15.15"
#: set to 1 to run every node on stock rospy: no fast path is installed
STOCK_ENV = "RASON_STOCK_ROSPY"


_announced = threading.Event()


def stock() -> bool:
    """Whether the environment asks for stock rospy (``RASON_STOCK_ROSPY=1``)."""
    return os.environ.get(STOCK_ENV, "0").strip() not in ("", "0")


def _stock_announced() -> bool:
    """:func:`stock`, logged the first time it holds in this process."""
    if not stock():
        return False
    if not _announced.is_set():
        _announced.set()
        rospy.loginfo("%s=1: stock rospy publishers and subscribers, no fast path", STOCK_ENV)
    return True


def publisher(topic: str, data_class: type, queue_size: int, **kwargs: Any) -> rospy.Publisher:
    """A publisher that never blocks its caller (:func:`.fanout.direct_publisher`; the node's
    inbound connections then handled in threads, :func:`.accept.threaded_accept`), or rospy's
    with the same ``queue_size`` under stock rospy; other keyword arguments as rospy's."""
    if _stock_announced():
        return rospy.Publisher(topic, data_class, queue_size=queue_size, **kwargs)
    publisher = direct_publisher(topic, data_class, queue_size, **kwargs)
    threaded_accept()
    return publisher


def subscriber(topic: str, data_class: type, callback: Any, queue_size: int | None = None,
               nice: int = 0, slice_s: float = 0.0, **kwargs: Any) -> rospy.Subscriber:
    """A subscriber read by frame readers (:func:`.frames.framed_subscriber`, with their
    reading threads' ``nice`` and ``slice_s``), or rospy's under stock rospy (which has no
    reading-thread priority: ``nice`` and ``slice_s`` are then ignored)."""
    if _stock_announced():
        return rospy.Subscriber(topic, data_class, callback, queue_size=queue_size, **kwargs)
    return framed_subscriber(topic, data_class, callback, queue_size=queue_size, nice=nice,
                             slice_s=slice_s, **kwargs)
