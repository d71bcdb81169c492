"""The action protocol between agents and decomposers (thesis 5.1-5.3), without rospy.

An agent publishes ``Action(agent, action_id, action, parameters)``. A decomposer that handles
it may acknowledge with ``Event(agent, "action_accepted", [action_id])`` and, when done, answers
``Event(agent, "action_feedback", [result, action_id, message])``: ``result`` is ``OK`` or the
failure reason (``no_progress``, ``bad_move``...), in the thesis' order. The public Rason code
used ``[action_id, result, message]``; :func:`parse_feedback` accepts that order too when it is
unambiguous (first parameter an integer, second not). An agent that gives an action up
publishes ``ActionCancel(agent, action_id, reason)`` on ``jason/cancel`` (rason's addition):
the decomposer stops it and answers ``cancelled``.

Supervision of the decomposer (rason's addition, #37): a decomposer may announce in its
``action_accepted`` a second parameter, the period (s, ROS time) of its beats, and then publish
``Event(agent, "action_running", [action_id, ...])`` that often while the actions run. An
agent fails an action whose decomposer announced beats and fell silent for its
``~decomposer_timeout`` with ``decomposer_lost`` (a killed decomposer, a lost link). Thesis
agents ignore both additions; a decomposer that announces nothing is not supervised.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

ACTION_ACCEPTED = "action_accepted"
ACTION_FEEDBACK = "action_feedback"
ACTION_RUNNING = "action_running"
OK = "OK"


class CancelReason:
    """Why an agent cancels an action (``jason_msgs/ActionCancel.reason`` on ``jason/cancel``)."""

    ACTION_TIMEOUT = "action_timeout"   # accepted, but not finished within ~action_timeout
    NO_DECOMPOSER = "no_decomposer"     # not acknowledged within ~ack_timeout
    DECOMPOSER_LOST = "decomposer_lost"  # its decomposer's beats stopped (killed, link lost)
    DROPPED = "dropped"                 # its intention was dropped, or failed or ended above it
    SHUTDOWN = "shutdown"               # the agent's node is shutting down
    STOP_MAS = "stop_mas"               # an agent of its node called .stopMAS: the node stops
    AGENT_ENDED = "agent_ended"         # the agent's reasoning ended on an error


class EventLike(Protocol):
    agent: str
    event_type: str
    parameters: list[str]


@dataclass(frozen=True)
class Feedback:
    """The outcome of one action, as a decomposer reported it."""

    action_id: int
    result: str
    message: str = ""

    @property
    def ok(self) -> bool:
        return self.result == OK


def _as_int(text: str) -> int | None:
    try:
        return int(text.strip())
    except ValueError:
        return None


def parse_feedback(event: EventLike) -> Feedback | None:
    """The Feedback carried by an ``action_feedback`` Event, or None if it is not one / unreadable."""
    if event.event_type != ACTION_FEEDBACK or len(event.parameters) < 2:
        return None
    first, second = event.parameters[0], event.parameters[1]
    message = event.parameters[2] if len(event.parameters) > 2 else ""
    second_id = _as_int(second)
    if second_id is not None and _as_int(first) is None:
        return Feedback(second_id, first.strip(), message)        # thesis order
    first_id = _as_int(first)
    if first_id is not None and second_id is None:
        return Feedback(first_id, second.strip(), message)        # public Rason code's order
    if first_id is not None and second_id is not None:
        return Feedback(second_id, first.strip(), message)        # ambiguous: thesis order wins
    return None


def parse_accepted(event: EventLike) -> int | None:
    """The action id acknowledged by an ``action_accepted`` Event, or None."""
    if event.event_type != ACTION_ACCEPTED or not event.parameters:
        return None
    return _as_int(event.parameters[0])


def accepted_beat_period(event: EventLike) -> float | None:
    """The beat period an ``action_accepted`` Event announces (its second parameter, a
    positive finite number of seconds), or None (a decomposer that does not beat)."""
    if len(event.parameters) < 2:
        return None
    try:
        period = float(event.parameters[1])
    except ValueError:
        return None
    return period if 0 < period < float("inf") else None


def parse_running(event: EventLike) -> list[int] | None:
    """The action ids an ``action_running`` beat names, or None if it is not one."""
    if event.event_type != ACTION_RUNNING:
        return None
    ids = [_as_int(p) for p in event.parameters]
    return [i for i in ids if i is not None]


def split_top_level(text: str) -> tuple[list[str], int, bool]:
    """Split ``text`` at the commas outside brackets and quotes, up to the first unmatched
    closing bracket.

    Returns the stripped parts, the index where scanning stopped (that bracket, or
    ``len(text)``) and whether every bracket and quote opened on the way was closed.
    ``'1, f(a, b), "x,y") [z]'`` gives ``(['1', 'f(a, b)', '"x,y"'], 19, True)``.
    """
    parts: list[str] = []
    depth, quote, start = 0, "", 0
    for i, ch in enumerate(text):
        if quote:
            if ch == quote and text[i - 1] != "\\":
                quote = ""
        elif ch in "\"'":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            if depth == 0:
                parts.append(text[start:i].strip())
                return parts, i, True
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return parts, len(text), depth == 0 and not quote


def split_action(text: str) -> tuple[str, list[str]]:
    """Split Jason action text ``move(1, "a,b")`` into ``("move", ["1", '"a,b"'])``.

    Commas inside parentheses, brackets, braces and quotes do not split. Raises ValueError
    for text that is not ``name`` or ``name(args)``.
    """
    text = text.strip()
    if "(" not in text:
        if not text or not (text[0].islower() and text.replace("_", "").isalnum()):
            raise ValueError(f"not an action: {text!r}")
        return text, []
    name, _, rest = text.partition("(")
    name = name.strip()
    if not name or not name[0].islower() or not rest.endswith(")"):
        raise ValueError(f"not an action: {text!r}")
    body = rest[:-1]
    params, stop, balanced = split_top_level(body)
    if stop != len(body) or not balanced:
        raise ValueError(f"unbalanced brackets or quotes in {text!r}")
    if params == [""]:
        return name, []
    if any(not p for p in params):
        raise ValueError(f"empty parameter in {text!r}")
    return name, params
