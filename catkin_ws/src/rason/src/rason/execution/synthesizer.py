"""Write a synthesizer in a few lines: sensor messages in, an agent's percepts out (thesis 5.4).

A synthesizer turns sensor data into the complete list of percepts of one perception *source*,
published as ``jason_msgs/Perception`` on ``jason/perception``; each message replaces that
source's previous list in the agents. Subclass :class:`Synthesizer`, name its inputs and say
what a message means::

    class BatterySynthesizer(Synthesizer):
        inputs = (("battery", BatteryState),)

        def perceive(self, msg: BatteryState) -> list[str]:
            if not 0.0 <= msg.percentage <= 1.0:        # NaN too
                raise BadFrame(f"charge {msg.percentage} out of [0, 1]")
            return [f"battery({round(msg.percentage * 100)})"]

    if __name__ == "__main__":
        run(BatterySynthesizer, "battery_synthesizer")

What the base does (names relative, so ``__ns:=/robot`` puts them under the robot):

* subscribes the ``inputs``; with more than one, pairs them by header stamp
  (``message_filters.ApproximateTimeSynchronizer``, ``~slop`` s apart at most);
* calls :meth:`Synthesizer.perceive` with each message (or synchronized tuple) and publishes
  its list with source ``~source`` (default: the node's name plus ``source_suffix``);
* guards every frame: whatever :meth:`Synthesizer.perceive` raises (:class:`BadFrame` for
  a frame it refuses, or any bug) rejects that frame with a rate-limited warning and publishes
  nothing for it; the node keeps running (a message_filters synchronizer never keeps its lock).
  Percepts must be strings; check sizes before viewing message data as arrays (see
  ``rason_vision.convert``).

Private parameters: :class:`SynthesizerParams` (``--help`` prints them); a synthesizer with
parameters of its own declares a subclass of it as ``Params`` and reads them as ``self.params``.
``~perception_ttl`` (s; 0 = none) is how long the source's list stays valid, declared as the
parameter ``jason/perception_ttl/<source>`` (again after a master restart), so that agents clear
this source's percepts when no frame has been published for that long (camera unplugged, node
dead); a synthesizer sets its own default by overriding the field in its ``Params``.
"""

from __future__ import annotations

import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, ClassVar

import rospy
from jason_msgs.msg import Perception

from rason.ros import fastpath
from rosnode_kit.badinput import shorten
from rosnode_kit.guard import RateLimitedWarnings
from rosnode_kit.master_watch import watch_master
from rosnode_kit.params import load_or_exit, param, start_node

__all__ = ["BadFrame", "Synthesizer", "SynthesizerParams", "run"]

#: Longest percept accepted from perceive() (characters) and most percepts per frame.
MAX_PERCEPT = 1000
MAX_PERCEPTS = 1000


class BadFrame(ValueError):
    """A sensor message the synthesizer refuses (empty, truncated, inconsistent, non-finite)."""


@dataclass(frozen=True)
class SynthesizerParams:
    """The private parameters every synthesizer has."""

    source: str | None = param(None, "the perception source (default: the node's name plus the "
                               "synthesizer's suffix)")
    queue_size: int = param(10, "queue of the subscribers (and the synchronizer)", minimum=1)
    buff_size: int = param(1 << 20, "receive buffer of the subscribers (bytes)", minimum=1024)
    slop: float = param(0.05, "s by which synchronized inputs' stamps may differ", minimum=0.0)
    timing: bool = param(False, "log per frame: stamp age at the callback, processing time, "
                         "stamp age when published")
    perception_ttl: float = param(0.0, "s this source's percepts stay valid in the agents after "
                                  "its last frame (0 = forever)", minimum=0.0)


class Synthesizer:
    """Base class of synthesizers; set :attr:`inputs`, override :meth:`perceive` (and
    :meth:`setup` for parameters of your own)."""

    #: ``(topic, message type)`` per input; several are synchronized by header stamp.
    inputs: tuple[tuple[str, type], ...] = ()
    #: Appended to the node's name to make the default perception source.
    source_suffix: str = ""
    #: The private parameters (a subclass of :class:`SynthesizerParams`), read as ``params``.
    Params: ClassVar[type[SynthesizerParams]] = SynthesizerParams

    def __init__(self) -> None:
        self.name = rospy.get_name().rsplit("/", 1)[-1]
        self.params: Any = load_or_exit(self.Params, self.name)
        self.source: str = self.params.source or self.name + self.source_suffix
        self.timing: bool = self.params.timing
        self.perception_ttl: float = self.params.perception_ttl
        self.warnings = RateLimitedWarnings()
        self.frames = 0           # frames published
        self.rejected = 0         # frames refused
        self.setup()
        self.declare_ttl()        # before the first publication, so agents find it at once
        self.publisher = fastpath.publisher("jason/perception", Perception, queue_size=10)
        queue = self.params.queue_size
        # rospy's receive buffer: 1 MB measured faster than 64 kB or 16 MB for 5 MB clouds.
        buff = self.params.buff_size
        if not self.inputs:
            raise ValueError(f"{type(self).__name__} names no inputs")
        if len(self.inputs) == 1:
            topic, msg_type = self.inputs[0]
            rospy.Subscriber(topic, msg_type, self.on_frame, queue_size=queue, buff_size=buff,
                             tcp_nodelay=True)
        else:
            import message_filters  # only synchronizing synthesizers need it

            subs = [message_filters.Subscriber(topic, msg_type, queue_size=queue,
                                               buff_size=buff, tcp_nodelay=True)
                    for topic, msg_type in self.inputs]
            self.sync = message_filters.ApproximateTimeSynchronizer(
                subs, queue_size=queue, slop=self.params.slop)
            self.sync.registerCallback(self.on_frame)

    # -- to override ----------------------------------------------------------------------
    def setup(self) -> None:
        """Read parameters of your own (called before the subscriptions start)."""

    def perceive(self, *msgs: Any) -> list[str]:
        """The complete percept list for one message (or synchronized tuple of messages);
        raise :class:`BadFrame` for a frame you refuse."""
        raise NotImplementedError

    def declare_ttl(self) -> None:
        """Tell agents how long this source's list stays valid (``~perception_ttl`` > 0)."""
        if self.perception_ttl > 0:
            rospy.set_param(f"jason/perception_ttl/{self.source}", self.perception_ttl)

    # -- the guarded frame path -----------------------------------------------------------
    def on_frame(self, *msgs: Any) -> None:
        """Perceive and publish one frame; any exception rejects the frame (never the node)."""
        start = time.perf_counter()
        entry_age = self._age(msgs) if self.timing else 0.0
        try:
            percepts = self._checked(self.perceive(*msgs))
        except Exception as err:  # a bad frame (or a bug) must not stop the node
            self.rejected += 1
            kind = "bad frame" if isinstance(err, BadFrame) else type(err).__name__
            self.warnings.warn(f"frame:{kind}", f"{self.name}: frame rejected ({kind}: "
                                                f"{shorten(str(err))}); {self.rejected} so far")
            return
        try:
            self.publisher.publish(Perception(source=self.source, perception=percepts))
        except rospy.ROSException as err:     # shutting down
            self.warnings.warn("publish", f"{self.name}: cannot publish: {err}")
            return
        self.frames += 1
        if self.timing:
            done = time.perf_counter()
            rospy.loginfo(f"timing frame {self.frames}: stamp to callback "
                          f"{entry_age * 1000:.1f} ms, processing {(done - start) * 1000:.1f} ms, "
                          f"stamp to published {self._age(msgs) * 1000:.1f} ms")
        rospy.logdebug(f"frame {self.frames}: {percepts}")

    @staticmethod
    def _checked(percepts: Sequence[str]) -> list[str]:
        if not isinstance(percepts, (list, tuple)):
            raise TypeError(f"perceive() returned {type(percepts).__name__}, not a list")
        if len(percepts) > MAX_PERCEPTS:
            raise BadFrame(f"{len(percepts)} percepts in one frame (at most {MAX_PERCEPTS})")
        for p in percepts:
            if not isinstance(p, str) or not p or len(p) > MAX_PERCEPT:
                raise TypeError(f"a percept must be a non-empty string of at most "
                                f"{MAX_PERCEPT} chars, got {shorten(repr(p), 80)}")
        return list(percepts)

    @staticmethod
    def _age(msgs: Sequence[Any]) -> float:
        """Seconds from the newest header stamp among `msgs` to now (0 without headers)."""
        stamps = [m.header.stamp for m in msgs if hasattr(m, "header")]
        if not stamps:
            return 0.0
        return (rospy.Time.now() - max(stamps)).to_sec()


def run(synthesizer: type[Synthesizer], node_name: str, argv: list[str] | None = None,
        usage: str | None = None) -> int:
    """``--help`` (the parameter table), or ``rospy.init_node(node_name)``, build the
    synthesizer and spin; the exit status (2 for a bad parameter)."""
    argv = argv if argv is not None else sys.argv
    summary = (synthesizer.__doc__ or "").strip().split("\n")[0]
    node = start_node(synthesizer, synthesizer.Params, node_name, argv, usage,
                      f"{node_name}: {summary}")
    if node is None:
        return 2
    watch_master(on_registered=[node.declare_ttl])
    rospy.loginfo(f"{node_name}: publishing {rospy.resolve_name('jason/perception')} "
                  f"as {node.source}")
    rospy.spin()
    return 0
