"""Events, intended means and intentions (Jason's ``Event``, ``IntendedMeans``, ``Intention``)
and the records of what a suspended intention waits for."""

from __future__ import annotations

import itertools
from enum import Enum
from typing import Any, NamedTuple

from .plans import ACHIEVE, ADD, DEL, K_LOOP, Deed, Plan, Trigger, deed_str
from .terms import ListTerm, Literal, Var, fresh_name, java_map_order, make_list, term_str
from .unify import rename_vars, resolve, unify

_ids = itertools.count(1)


class Event:
    """A triggering event; ``intention`` is None for external events."""

    __slots__ = ("fail_target", "intention", "option", "reply", "trigger")

    def __init__(self, trigger: Trigger, intention: Intention | None = None,
                 fail_target: int | None = None, reply: Any = None,
                 option: tuple[Plan, dict] | None = None) -> None:
        self.trigger = trigger
        self.intention = intention
        # for +?g events created to answer an askOne: the question message
        self.reply = reply
        # for -!g events: index in the intention stack of the +!g means that failed
        self.fail_target = fail_target
        #: the plan and unifier chosen already (the event of a branch, Jason's Event.option)
        self.option = option

    def __repr__(self) -> str:
        return str(self.trigger)


class IntendedMeans:
    """A plan instance on an intention stack: its unifier and the deeds still to run.

    ``stack`` holds the remaining deeds in reverse order (the next deed is ``stack[-1]``).
    """

    __slots__ = ("current", "fail_target", "open_call", "plan", "result", "scope_u", "stack", "trigger",
                 "trigger_u", "u")

    def __init__(self, plan: Plan, trigger: Trigger, u: dict, fail_target: int | None = None,
                 open_call: bool = False) -> None:
        self.plan = plan
        self.trigger = trigger          # the event trigger (resolved literal, with annotations)
        self.u = u
        self.stack: list[Deed] = list(plan.rev_body)
        self.fail_target = fail_target  # for -!g means: stack index of the failed +!g means
        self.current: Deed | None = None  # the deed being executed (for intention dumps)
        # set when tail-recursion optimisation replaced the means below: (answer, call), what
        # the caller gets is ``answer`` once ``call`` is unified with this means' result
        self.result: tuple[Any, Any] | None = None
        # the event had variables (its caller may get bindings back from this means)
        self.open_call = open_call
        #: the unifier the means started with, for its plan's goal condition (``<:``)
        self.trigger_u = dict(u) if plan.goal_condition is not None else None
        #: the unifier the means started with, when its plan has sub-plans: theirs start
        #: from it (Jason's ``IntendedMeans.triggerUnif``)
        self.scope_u = dict(u) if plan.sub_library is not None else None

    @property
    def is_goal_add(self) -> bool:
        return self.trigger.op == ADD and self.trigger.is_goal

    @property
    def is_failure_plan(self) -> bool:
        return self.trigger.op == DEL and self.trigger.is_goal

    def __str__(self) -> str:
        deeds = list(reversed(self.stack))
        if self.current is not None and (not deeds or deeds[0] is not self.current):
            deeds.insert(0, self.current)
        # a running loop's next round as Jason's ``.loop``/``.foreach`` deed (as ``.intention``)
        rest = "; ".join(deed_str(d, d.kind == K_LOOP) for d in deeds)
        unif = ", ".join(f"{k}={term_str(v)}" for k, v in self.u.items())
        return f"{self.trigger} <- ... {rest} / {{{unif}}}"


class Fork:
    """One ``.fork(and|or, ...)``: its branch intentions and how many must still reach the
    ``.join`` (``and``: all of them; ``or``: the first one goes on, the others are dropped).

    This module's mutable records are plain classes with the methods ``@dataclass`` would
    make: every agent imports it at start-up, where ``dataclasses`` costs ~3.5 ms."""

    def __init__(self, is_and: bool, branches: list | None = None, to_finish: int = 0) -> None:
        self.is_and = is_and
        self.branches: list = branches if branches is not None else []
        self.to_finish = to_finish

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Fork):
            return NotImplemented
        return (self.is_and, self.branches, self.to_finish) == (other.is_and, other.branches,
                                                                  other.to_finish)

    __hash__ = None  # type: ignore[assignment]  # mutable and compared by value

    def __repr__(self) -> str:
        return f"Fork(is_and={self.is_and!r}, branches={self.branches!r}, to_finish={self.to_finish!r})"

    def __str__(self) -> str:
        ids = " ".join(str(i.id) for i in self.branches)
        return f"fork({'and' if self.is_and else 'or'}, [{ids}], waiting for {self.to_finish})"


class ForkBranch:
    """What a branch intention knows of its fork: the fork and the depth of its stack when
    forked (a failure handled at or below that depth ends the fork)."""

    def __init__(self, fork: Fork, point: int) -> None:
        self.fork = fork
        self.point = point

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, ForkBranch):
            return NotImplemented
        return self.fork == other.fork and self.point == other.point

    __hash__ = None  # type: ignore[assignment]  # mutable and compared by value

    def __repr__(self) -> str:
        return f"ForkBranch(fork={self.fork!r}, point={self.point!r})"


class Suspension(Enum):
    """Why an intention is not in the running queue (Jason keeps it in PA, PI or an event)."""

    SUBGOAL = "subgoal"         # the event of its subgoal (``!g``, ``?g``) is pending
    EVENT = "event"             # its own belief event (``+b`` in a body) is pending
    FAILURE = "failure"         # its ``-!g`` failure event is pending
    ACTION = "action"           # an environment action runs (Jason's PA)
    WAIT = "wait"               # ``.wait(ms)``
    EVENT_WAIT = "event_wait"   # ``.wait(Event|Condition)``
    ASK = "ask"                 # the answer to an askOne/askAll
    SUSPENDED = "suspended"     # ``.suspend``
    IA = "ia"                   # an internal action suspended it
    GOAL_CONDITION = "wait_goal_condition"   # its plan is done, its goal condition (``<:``) not yet


class Intention:
    """A stack of intended means; ``ims[-1]`` is the top."""

    __slots__ = ("atomic_count", "branch_of", "dropped", "fork", "id", "ims", "pi_key", "reply",
                 "sus_ia", "suspended", "wait_elapsed", "wait_reason")

    def __init__(self, ident: int | None = None, reply: Any = None) -> None:
        self.id = ident if ident is not None else next(_ids)
        self.dropped = False
        #: the question (an askOne/askAll message) this intention answers when it finishes
        self.reply: Any = reply
        self.ims: list[IntendedMeans] = []
        # None when runnable; otherwise what it waits for
        self.suspended: Suspension | None = None
        self.atomic_count = 0
        # Jason's Intention.isSuspended: suspended by .suspend (orthogonal to what it waits for)
        self.sus_ia = False
        # its key in Jason's pending intentions (PI): "suspended-<id>" (by .suspend),
        # "<id>/time<ms>" (.wait)... .resume and .intention follow the order of these keys
        self.pi_key: str | None = None
        # what a .wait waits for, as Jason's suspended reason (``wait(500)[time(500)]``)
        self.wait_reason: Any = None
        # .wait(E, T, Elapsed): (the Elapsed term, start time); a timeout then does not fail
        self.wait_elapsed: Any = None
        # a branch of ``.fork``: the fork it belongs to and its depth when forked, else None
        self.fork: ForkBranch | None = None
        #: a branch made for an external belief event that a sub-plan of this intention's
        #: plans handles: the intention it copies (Jason's ``gIntention``), else None
        self.branch_of: Intention | None = None

    def push(self, im: IntendedMeans) -> None:
        self.ims.append(im)
        if im.plan.atomic:
            self.atomic_count += 1

    def pop(self) -> IntendedMeans:
        im = self.ims.pop()
        if im.plan.atomic:
            self.atomic_count -= 1
        return im

    def truncate(self, n: int) -> None:
        while len(self.ims) > n:
            self.pop()

    def waits(self) -> bool:
        """Is it out of the running queue's reach now (it waits, or it was dropped)? A call, not
        an inline test, after whatever may have suspended it: compiled code trusts what a
        test of ``suspended`` earlier in the same function narrowed it to."""
        return self.suspended is not None or self.dropped

    def top(self) -> IntendedMeans | None:
        return self.ims[-1] if self.ims else None

    @property
    def is_atomic(self) -> bool:
        return self.atomic_count > 0

    def empty(self) -> bool:
        return not self.ims

    def dump(self, limit: int = 100) -> str:
        """Jason-like intention dump (used in warnings); of a stack deeper than ``limit``, only
        the top and bottom intended means are shown."""
        lines = [f"intention {self.id}: "]
        ims = list(reversed(self.ims))
        shown: list[IntendedMeans | None] = list(ims)
        if len(ims) > limit:
            keep = limit // 2
            hidden = len(ims) - 2 * keep
            shown = [*ims[:keep], None, *ims[-keep:]]
        for im in shown:
            lines.append("    " + (str(im) if im is not None else f"... {hidden} more intended means ..."))
        return "\n".join(lines) + "\n"

    def __repr__(self) -> str:
        return f"<intention {self.id} {[str(im.trigger) for im in self.ims]}>"


class TimerKind(Enum):
    """What a timer of the agent ends."""

    WAIT = "wait"                     # ``.wait(ms)``: the intention goes on
    EVENT_TIMEOUT = "event_timeout"   # ``.wait(E, ms)``: the intention fails
    ASK_TIMEOUT = "ask_timeout"       # ``.send(.., askOne, .., A, ms)``: A is ``timeout``
    AT = "at"                         # ``.at(When, Event)``: the event is posted
    DEADLINE = "deadline"             # ``!g[hard_deadline(ms)]``: the goal fails if still pursued


class Timer(NamedTuple):
    """An entry of the agent's timer heap (ordered by deadline, then creation)."""

    deadline: float
    seq: int
    kind: TimerKind
    intention: Intention | None
    msg_id: str | None = None   # for ASK_TIMEOUT: the question
    data: Any = None            # AT: the trigger; EVENT_TIMEOUT: the wait it ends (its reason);
    #                             DEADLINE: the goal's trigger and the intention's size then


class EventWait(NamedTuple):
    """An intention suspended by ``.wait`` for an event and/or a condition."""

    trigger: Trigger | None
    condition: Any
    intention: Intention
    means: IntendedMeans | None


class AskWait:
    """An intention waiting for the answer(s) to an ask message."""

    def __init__(self, intention: Intention, answer: Any, performative: str,
                 receivers: int | None, answers: list | None = None) -> None:
        self.intention = intention
        self.answer = answer                # the ``.send``'s fourth argument
        self.performative = performative    # askOne / askAll
        self.receivers = receivers          # how many receivers when they were given as a list
        #: the answers so far (list of receivers)
        self.answers: list = answers if answers is not None else []

    def _fields(self) -> tuple:
        return (self.intention, self.answer, self.performative, self.receivers, self.answers)

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, AskWait):
            return NotImplemented
        return self._fields() == other._fields()

    __hash__ = None  # type: ignore[assignment]  # mutable and compared by value

    def __repr__(self) -> str:
        return (f"AskWait(intention={self.intention!r}, answer={self.answer!r}, "
                f"performative={self.performative!r}, receivers={self.receivers!r}, "
                f"answers={self.answers!r})")


class PendingAction(NamedTuple):
    """An environment action started and not finished yet (Jason's PA)."""

    intention: Intention
    means: IntendedMeans
    action: Any
    deed: Deed


class PendingEvent(NamedTuple):
    """An event held by ``.suspend`` (Jason's PE) under its key."""

    key: str
    event: Event


class ActionResult(NamedTuple):
    """The environment's feedback on an action."""

    action_id: int
    ok: bool
    reason: str | None = None
    message: str = ""
    annots: list | None = None


def has_goal(i: Intention, pattern: Any, s: dict) -> dict | None:
    """Jason's ``Intention.hasTrigger(+!G)``: the unifier of the topmost ``+!g`` means
    that matches, or None."""
    for idx in range(len(i.ims) - 1, -1, -1):
        t = i.ims[idx].trigger
        if t.op == ADD and t.type == ACHIEVE:
            s2 = dict(s)
            if unify(pattern, t.literal, s2):
                return s2
    return None


def event_has_goal(ev: Event, pattern: Any, s: dict) -> dict | None:
    """The unifier when ``ev`` is ``+!G`` itself or an event of an intention that has ``+!G``
    (what ``.suspend``/``.resume`` look for in the events), or None."""
    t = ev.trigger
    if t.op == ADD and t.type == ACHIEVE:
        s2 = dict(s)
        if unify(pattern, t.literal, s2):
            return s2
    return None if ev.intention is None else has_goal(ev.intention, pattern, s)


def unifier_term(u: dict, ag: Any = None, through: dict | None = None) -> ListTerm:
    """A unifier as Jason's ``Unifier.getAsTerm`` gives it: ``[map(_N, Value), ...]``, one
    pair per bound variable, in the iteration order of Java's ``HashMap`` of the variable
    names. Each variable is a fresh unnamed one, its name kept after the number when longer
    than one character (``UnnamedVar.create``: ``X`` gives ``_32``, ``Ab`` gives ``_33Ab``);
    each value is resolved, and the variables inside it are fresh ones (``makeVarsAnnon``;
    a value that is a free variable stays that variable). ``through``: more bindings the
    values are resolved with (not listed)."""
    pairs = []
    look = u if not through else {**through, **u}
    for name in java_map_order([k for k in u if type(k) is str], str):
        value = resolve(Var(name), look, ag)
        if not isinstance(value, Var):
            value = rename_vars(value, {})
        key = Var(fresh_name() + (name if len(name) > 1 else ""))
        pairs.append(Literal("map", (key, value)))
    return make_list(pairs)


def short(x: Any) -> str:
    return term_str(x)
