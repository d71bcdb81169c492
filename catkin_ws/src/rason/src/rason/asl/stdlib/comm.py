"""Communication internal actions: ``.send`` and ``.broadcast``."""

from __future__ import annotations

from typing import Any

from ..arch import Message
from ..terms import ListTerm, Literal, list_to_python, term_str, to_print_str
from ..unify import eval_arith
from . import SUSPEND, IAError, arg_count, internal_action

PERFORMATIVES = {"tell", "untell", "achieve", "unachieve", "askOne", "askAll", "tellHow",
                 "untellHow", "askHow", "signal"}


def _name(t: Any) -> str:
    if isinstance(t, Literal) and not t.args:
        return t.functor
    if isinstance(t, str):
        return t
    raise IAError(f"invalid receiver {term_str(t)}", "wrong_arguments")


def _perf(t: Any) -> str:
    p = to_print_str(t)
    if p not in PERFORMATIVES:
        raise IAError(f"unknown performative {p}", "wrong_arguments")
    return p


@internal_action(".send")
def send(ctx: Any, args: list) -> Any:
    """``.send(Receiver(s), Performative, Content[, Answer[, Timeout]])``."""
    arg_count(args, 3, 4, 5)
    ag = ctx.ag
    perf = _perf(args[1])
    content = args[2]
    receivers = list_to_python(args[0]) if isinstance(args[0], ListTerm) else [args[0]]
    wait_answer = perf in ("askOne", "askAll") and len(args) >= 4
    last_id = None
    for r in receivers or []:
        msg = Message(ag.name, _name(r), perf, content)
        last_id = msg.msg_id
        if wait_answer:
            timeout = None
            if len(args) == 5:
                timeout = ag.arch.clock.now() + eval_arith(args[4], ctx.s) / 1000.0
            ag.register_ask(msg.msg_id, ctx.intention, args[3], timeout)
        ag.send_message(msg)
    if wait_answer and last_id is not None:
        return SUSPEND
    return True


@internal_action(".broadcast")
def broadcast(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    ag = ctx.ag
    msg = Message(ag.name, "", _perf(args[0]), args[1])
    ag.arch.broadcast(ag, msg)
    return True
