"""``rosrun rason echo_decomposer``: a decomposer for tests that answers what it is asked.

Handles the actions named in ``~actions`` (default ``[move]``) on ``jason/action``, acknowledges
each (``action_accepted``), waits ``~delay`` seconds of ROS time, then answers
``action_feedback [RESULT, action_id, message]``. RESULT is the action's last parameter when it
is an atom (``move(1, no_progress)`` fails with ``no_progress``), else ``~result`` (``OK``).
``~ack:=false`` behaves like a decomposer written to the thesis alone (no acknowledgement).
Actions run side by side; a cancel (``jason/cancel``) or the agent's absence ends one
``cancelled`` (see :mod:`rason.execution.decomposer`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from rason.execution.decomposer import Decomposer, DecomposerParams, Goal, Verdict, run
from rosnode_kit.params import param

ATOM = re.compile(r"^[a-z][A-Za-z0-9_]*$")


@dataclass(frozen=True)
class EchoParams(DecomposerParams):
    """The echo decomposer's private parameters, besides those of every decomposer."""

    actions: list[str] = param(["move"], "the actions answered")
    result: str = param("OK", "the result, unless the action's last parameter is an atom")
    delay: float = param(0.0, "seconds (ROS time) before the answer", minimum=0.0)
    ack: bool = param(True, "acknowledge with action_accepted (false: a thesis-only "
                      "decomposer)")


class EchoDecomposer(Decomposer):
    """Answers handled actions with the result they ask for."""

    exclusive = False
    Params = EchoParams

    def setup(self) -> None:
        self.actions = tuple(self.params.actions)
        self.result = self.params.result
        self.delay = self.params.delay
        self.acknowledge = self.params.ack

    def start(self, goal: Goal) -> Verdict | None:
        last = goal.parameters[-1] if goal.parameters else ""
        goal.state = Verdict(last if ATOM.match(last) else self.result,
                             f"echo: {goal.action}({', '.join(goal.parameters)})")
        return goal.state if self.delay <= 0 else None

    def step(self, goal: Goal, now: float) -> Verdict | None:
        return goal.state if now - goal.started >= self.delay else None


def main() -> int:
    return run(EchoDecomposer, "echo_decomposer",
               usage="rosrun rason echo_decomposer [__ns:=/robot] [_name:=value ...]")
