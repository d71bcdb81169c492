"""How an action ends, as a decomposer reports it (thesis 5.3), without rospy.

The ``result`` of ``action_feedback [RESULT, action_id, message]``: ``OK`` or a failure reason
the agent's plans can match (``-!g[error(no_progress)]``).
"""

from __future__ import annotations

from dataclasses import dataclass

OK = "OK"
#: The motion decomposer's checks (thesis 6.3).
NO_PROGRESS = "no_progress"
BAD_MOVE = "bad_move"
#: The base's safety events (:mod:`rason.execution.safety`): a bumper pressed, a cliff sensor
#: over a drop, a wheel dropped; the motion stopped at once, or a new one was refused.
BUMPER = "bumper"
CLIFF = "cliff"
WHEEL_DROP = "wheel_drop"
#: The protocol's own endings (every decomposer built on rason.execution.decomposer).
BAD_PARAMETERS = "bad_parameters"   # parse() refused the parameters; the action never started
PREEMPTED = "preempted"             # a newer action took the actuator over
CANCELLED = "cancelled"             # the agent cancelled it, said goodbye or stopped announcing
TIMEOUT = "timeout"                 # the decomposer's own ~timeout ran out
ACTION_FAILED = "action_failed"     # the decomposer's code raised


@dataclass(frozen=True)
class Verdict:
    """How an action ended: ``result`` (OK or a failure reason) and a human message."""

    result: str
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.result == OK
