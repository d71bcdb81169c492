"""An ``agentArchClass`` for ``python -m rason.asl run``: every message the agent sends reaches
its receiver ``ms`` milliseconds later, as on an infrastructure slower than rason's.

    elf worker.asl [beliefs="..."] agentArchClass _latency_arch.delayed("3.2") #10;

(with this folder on ``PYTHONPATH``, or the module beside the ``.mas2j``). Used by
``stclaus_latency.py`` to give rason the per-message latency measured on Jason. The messages
wait in one delivery thread (in order of their due time, so a fixed delay keeps each sender's
order) and are then handed to the receiver as any message is (``Agent.receive``). So that the
run does not end while a message is still on its way (every agent idle, no timer left), the
sender also gets an ``.at``-like timer due a second after the message arrives, whose event
(``+latency_arch_delivered``) no plan handles.
"""

from __future__ import annotations

import heapq
import itertools
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass, field

from rason.asl import Agent
from rason.asl.arch import Message
from rason.asl.plans import ADD, BELIEF, Trigger
from rason.asl.terms import Literal

#: seconds the keep-alive timer outlasts the delivery (the delivery thread may run late)
KEEP_ALIVE_MARGIN = 1.0
#: the event the keep-alive timer posts (no plan is relevant for it)
KEEP_ALIVE = Trigger(ADD, BELIEF, Literal("latency_arch_delivered"))


@dataclass(order=True)
class Delivery:
    """A message on its way: when it is due, in what order it was sent, what delivers it."""

    due: float
    seq: int
    deliver: Callable[[], None] = field(compare=False)


class DelayLine:
    """One thread that delivers messages when they fall due (monotonic seconds)."""

    def __init__(self) -> None:
        self._queue: list[Delivery] = []
        self._seq = itertools.count()
        self._changed = threading.Condition()
        self._thread = threading.Thread(target=self._run, name="latency-arch", daemon=True)
        self._thread.start()

    def put(self, delay: float, deliver: Callable[[], None]) -> None:
        """Deliver (call ``deliver``) ``delay`` seconds from now."""
        with self._changed:
            heapq.heappush(self._queue, Delivery(time.monotonic() + delay, next(self._seq), deliver))
            self._changed.notify()

    def _run(self) -> None:
        while True:
            with self._changed:
                while not self._queue or self._queue[0].due > time.monotonic():
                    timeout = self._queue[0].due - time.monotonic() if self._queue else None
                    self._changed.wait(timeout)
                item = heapq.heappop(self._queue)
            item.deliver()


_LINE: DelayLine | None = None
_LINE_LOCK = threading.Lock()


def delay_line() -> DelayLine:
    """The process's delivery thread (started at the first use)."""
    global _LINE
    with _LINE_LOCK:
        if _LINE is None:
            _LINE = DelayLine()
        return _LINE


def delayed(agent: Agent, ms: str) -> None:
    """agentArchClass: the agent's messages to others arrive ``ms`` milliseconds after it sends
    them (to itself: at once, as before)."""
    delay = float(ms) / 1000.0
    arch = agent.arch
    send = arch.send
    line = delay_line()

    def send_later(sender: Agent, message: Message) -> None:
        # a receiver that does not exist is still reported at once, by the send itself
        if message.receiver not in arch.agent_names():
            send(sender, message)
            return
        sender.circ.schedule_event(KEEP_ALIVE, delay + KEEP_ALIVE_MARGIN)
        line.put(delay, lambda: send(sender, message))

    arch.send = send_later  # type: ignore[method-assign]
