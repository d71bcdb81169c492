"""Ctrl-C and SIGTERM that stop a rospy node at any moment, its start included.

rospy's own handler runs ``rospy.signal_shutdown`` inside the interrupted main thread. When
that thread is in the middle of a call to the master (registering a publisher, a subscriber or
a service while the node starts), the shutdown's own calls (unregistering) wait for the lock the
interrupted call holds, which is never released: the node hangs until SIGKILL. Here the
shutdown runs on a thread of its own; the handler waits for it a moment (the whole shutdown,
as with rospy, in the common case), then lets the interrupted thread go on and release what it
holds, so the shutdown completes.

Usage, in place of ``rospy.init_node``::

    from rosnode_kit.signals import init_node
    init_node("my_node", argv=argv)
"""

from __future__ import annotations

import signal
import threading
from types import FrameType
from typing import Any

import rospy

#: how long (s) the interrupted thread waits for the shutdown it started before going on
SHUTDOWN_WAIT = 1.0


def shutdown_on_signal(sig: int, frame: FrameType | None = None) -> None:
    """The SIGINT/SIGTERM handler: ``rospy.signal_shutdown`` on a thread of its own."""
    worker = threading.Thread(target=rospy.signal_shutdown, args=(f"signal-{sig}",),
                              name="signal-shutdown")
    worker.start()
    worker.join(SHUTDOWN_WAIT)


def init_node(name: str, **kwargs: Any) -> None:
    """``rospy.init_node(name, **kwargs)`` with :func:`shutdown_on_signal` handling SIGINT and
    SIGTERM from before the node's first call to the master on (call from the main thread)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, shutdown_on_signal)
    rospy.init_node(name, disable_signals=True, **kwargs)
