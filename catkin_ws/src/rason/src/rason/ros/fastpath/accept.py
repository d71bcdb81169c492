"""Inbound TCPROS connections handled each in a thread of its own, not in rospy's accept loop.

rospy's ``TCPServer.run`` accepts a connection and calls its handler in the same thread
("leave threading decisions up to inbound_handler"); the handler reads the connection's
handshake header with the socket's default timeout, which rospy sets to 60 s. One connection
that never sends its header (a client that gave up half-way, a port probe) therefore stops the
node from accepting any other subscriber or service client for 60 s: a decomposer so blocked
leaves a freshly started agent's ``jason/event`` subscription unconnected, and the agent's first
action fails ``no_decomposer`` (#39, the warning ``Inbound TCP/IP connection failed: timed
out`` a minute later). :func:`threaded_accept` hands each accepted connection to a thread: a
silent one still times out after 60 s, alone.
"""

from __future__ import annotations

import socket
import threading
from typing import Any

import rospy
from rospy.impl import tcpros_base


def threaded_accept() -> bool:
    """Have this node's TCPROS server handle each inbound connection in its own thread (starting
    the server if no publisher or service has yet); False if rospy has no server to change."""
    tcpros_base.start_tcpros_server()
    server = getattr(tcpros_base._tcpros_server, "tcp_ros_server", None)
    if server is None:
        return False
    handler = server.inbound_handler
    if getattr(handler, "threaded", False):
        return True

    def handle(sock: Any, address: Any) -> None:
        try:
            handler(sock, address)
        except OSError as err:       # what rospy's loop logs for its handler
            if not rospy.is_shutdown():
                rospy.logwarn("Failed to handle inbound connection due to socket error: %s", err)

    def inbound(sock: socket.socket, address: Any) -> None:
        threading.Thread(target=handle, args=(sock, address), daemon=True,
                         name=f"tcpros-inbound-{address}").start()

    inbound.threaded = True          # type: ignore[attr-defined]
    server.inbound_handler = inbound
    return True
