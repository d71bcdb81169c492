"""Which internal actions a message from another agent may make an agent run (#37 item 1).

The default KQML plans evaluate what a message carries: an ``askOne`` is answered with a test
goal ``?Content``, an ``askAll`` with a query, a told rule is queried later. When the content
is (or holds) an internal action, evaluating it runs that action in the receiver: an
``askOne .add_plan({...})`` installs a plan, an ``askOne .list_files(D, P, F)`` sends the
receiver's file listing back, an ``askOne .stopMAS`` stops it. :class:`RemoteActions` is the
explicit allow-list of the internal actions a remote message may cause, for every sender,
trusted or not (``~remote_internal_actions``, default none): a message whose content calls
any other is dropped before it reaches the agent.

Only the content of performatives whose content is evaluated is checked: ``tellHow``,
``untellHow`` and ``askHow`` carry plans and triggers, which are installed, removed or looked
up, never run; they are for trusted senders only (:class:`rason.ros.auth.TrustPolicy`).
A plan term (``{ ... }``) in any other message is refused too: it holds code.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Any

from rason.asl.terms import (
    ArithExpr,
    ListTerm,
    Literal,
    LogExpr,
    NsLit,
    PlanTerm,
    RelExpr,
    Rule,
    is_internal_action,
)

#: Performatives whose content is a plan or a trigger, never evaluated by the receiver.
PLAN_PERFORMATIVES = frozenset({"tellHow", "untellHow", "askHow"})
#: The expression classes (an operator and one or two terms).
_EXPRESSIONS = (ArithExpr, RelExpr, LogExpr)
#: What :func:`code_in` yields for a plan term.
PLAN_TERM = "a plan term"


def code_in(content: Any) -> Iterator[str]:
    """The internal actions (their functors) a term would run when evaluated, and
    :data:`PLAN_TERM` for each plan term in it; iterative, so a deep term costs no stack."""
    stack = [content]
    while stack:
        t = stack.pop()
        tt = type(t)
        if tt is Literal:
            if is_internal_action(t.functor):
                yield t.functor
            stack.extend(t.args)
            stack.extend(t.annots)
            if t.tail is not None:
                stack.append(t.tail)
        elif tt is ListTerm:
            stack.extend(t.items)
            if t.tail is not None:
                stack.append(t.tail)
        elif tt in _EXPRESSIONS:
            stack.append(t.left)
            if t.right is not None:
                stack.append(t.right)
        elif tt is Rule:
            stack.append(t.head)
            stack.append(t.body)
        elif tt is NsLit:
            stack.append(t.ns)
            stack.append(t.lit)
        elif tt is PlanTerm:
            yield PLAN_TERM


@dataclass(frozen=True)
class RemoteActions:
    """The internal actions a message from another agent may cause (empty: none)."""

    allowed: frozenset[str] = frozenset()

    @classmethod
    def of(cls, names: Iterable[str]) -> RemoteActions:
        return cls(frozenset(str(n).strip() for n in names if str(n).strip()))

    def refusal(self, performative: str, content: Any) -> str | None:
        """Why a message `performative` `content` may not reach an agent, or None."""
        if performative in PLAN_PERFORMATIVES:
            return None
        for code in code_in(content):
            if code not in self.allowed:
                return (f"its content calls {code} (not in ~remote_internal_actions)"
                        if code != PLAN_TERM else "its content holds a plan term")
        return None
