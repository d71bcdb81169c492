"""Communication internal actions: ``.send`` and ``.broadcast``."""

from __future__ import annotations

import itertools
from typing import Any

from ..arch import Message, new_msg_id
from ..ia import SUSPEND, IAContext, IAError, internal_action
from ..intentions import Event
from ..plans import ADD, BELIEF, Trigger
from ..terms import (
    LOCAL_NS_PREFIX,
    ListTerm,
    Literal,
    Var,
    fresh_name,
    in_ns,
    list_to_python,
    merge_annots,
    split_ns,
    term_str,
    with_nested_source,
)
from ..unify import eval_arith, resolve, unify

PERFORMATIVES = {"tell", "untell", "achieve", "unachieve", "askOne", "askAll", "tellHow",
                 "untellHow", "askHow", "signal"}


def _name(t: Any) -> str:
    if isinstance(t, Literal) and not t.args:
        return t.functor
    if isinstance(t, str):
        return t
    raise IAError(f"invalid receiver {term_str(t)}", "wrong_arguments")


def _perf(t: Any) -> str:
    if not (isinstance(t, Literal) and not t.args):
        raise IAError(f"illocutionary force parameter ('{term_str(t)}') must be an atom!",
                      "wrong_arguments")
    return t.functor


_sync_ids = itertools.count(1)


@internal_action(".send", arity=(3, 5))
def send(ctx: IAContext, args: list) -> Any:
    """``.send(Receiver(s), Performative, Content[, Answer|MsgId[, Timeout]])`` (jason.stdlib.send):
    an ask with an answer argument suspends the intention until the answer (one message id for
    every receiver); a tell/untell/unknown performative with a fourth argument is a reply."""
    ag = ctx.ag
    to = args[0]
    if not isinstance(to, (Literal, ListTerm, str)) or (isinstance(to, Literal) and to.args):
        raise IAError(f"TO parameter ('{term_str(to)}') must be an atom, a string or a list of "
                      "receivers!", "wrong_arguments")
    perf = _perf(args[1])
    content = args[2]
    receivers = list_to_python(to) if isinstance(to, ListTerm) else [to]
    sync_ask = perf.startswith("ask") and len(args) > 3
    reply_to = None
    if (perf.startswith(("tell", "untell")) or perf not in PERFORMATIVES) and len(args) > 3:
        if not (isinstance(args[3], Literal) and not args[3].args):
            raise IAError(f"The Message ID ('{term_str(args[3])}') parameter of the internal action "
                          "'send' is not an atom!")
        reply_to = args[3].functor
    msg_id = f"samid{next(_sync_ids)}" if sync_ask else new_msg_id()
    if sync_ask:
        timeout = None
        if len(args) == 5:
            timeout = ag.arch.clock.now() + eval_arith(args[4], ctx.s, ctx.ag) / 1000.0
        n = len(receivers or []) if isinstance(to, ListTerm) else None
        ag.comm.register_ask(msg_id, ctx.intention, args[3], timeout, perf, n)
    for r in receivers or []:
        name = _name(r)
        if name == "self":
            name = ag.name
        ag.comm.send_message(Message(ag.name, name, perf, content, msg_id=msg_id, in_reply_to=reply_to))
    return SUSPEND if sync_ask else True


def _strip(t: Any) -> Any:
    if isinstance(t, ListTerm):
        return ListTerm(tuple(_strip(x) for x in t.items), t.tail)
    if isinstance(t, Literal) and t.annots:
        return t.with_annots(tuple(a for a in t.annots
                                   if not (isinstance(a, Literal) and a.functor == "source")), t.tail)
    return t


@internal_action(".add_nested_source", arity=3)
def add_nested_source(ctx: IAContext, args: list) -> bool:
    """``.add_nested_source(Content, Source, Result)``: adds ``source(Source)``."""
    return ctx.unify(args[2], with_nested_source(args[0], args[1]))


@internal_action(".kqml_belief_answer", arity=3)
def kqml_belief_answer(ctx: IAContext, args: list) -> Any:
    """``.kqml_belief_answer(NS, Content, Ans)``: rason's form of Jason 3.3's
    ``kqml::bel_no_source_self`` rule (askOne/askAll answers). Content and Ans are literals
    without namespace; NS is their namespace (free: each namespace of the belief base, in
    Jason's order, never a local one). Each belief ``NS::Content`` gives Ans, the belief
    without namespace and with every annotation but ``source(self)`` when Content names none;
    when it names some, with none (the rule's ``NS::Content[|LA]`` leaves ``LA`` free then,
    and ``clear_source_self`` makes it ``[]``: checked with Jason 3.3.2)."""
    ns_arg, content = args[0], args[1]
    if not isinstance(content, Literal):
        return False
    if isinstance(ns_arg, Literal) and not ns_arg.args:
        spaces = [ns_arg.functor]
    elif isinstance(ns_arg, Var):
        spaces = [ns for ns in ctx.ag.bb.namespaces() if not ns.startswith(LOCAL_NS_PREFIX)]
    else:
        return False
    tail = content.tail if content.tail is not None else Var(fresh_name())
    bare = Literal(content.functor, content.args, content.annots, tail, content.neg)
    self_src = Literal("source", (Literal("self"),))

    def gen():
        for ns in spaces:
            pattern = in_ns(ns, bare)
            for sol in ctx.query_beliefs(pattern):
                b = split_ns(resolve(pattern, sol))[1]
                others = [] if content.annots else list_to_python(resolve(tail, sol)) or []
                ans = b.with_annots(merge_annots((), [a for a in others if a != self_src]), None)
                s2 = dict(ctx.s)
                if (unify(ns_arg, Literal(ns), s2) and unify(content.with_annots(()), ans.with_annots(()), s2)
                        and unify(args[2], ans, s2)):
                    yield s2
    return gen()


@internal_action(".remove_source_annot", arity=2)
def remove_source_annot(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], _strip(args[0]))


@internal_action(".clear_source_self", arity=2)
def clear_source_self(ctx: IAContext, args: list) -> bool:
    """Remove ``source(self)`` from each literal of a list (askAll answers)."""
    items = list_to_python(args[0]) or []
    out = []
    self_src = Literal("source", (Literal("self"),))
    for x in items:
        if isinstance(x, Literal):
            x = x.with_annots(tuple(a for a in x.annots if a != self_src), x.tail)
        out.append(x)
    return ctx.unify(args[1], ListTerm(tuple(out)))


@internal_action(".signal", arity=1)
def signal(ctx: IAContext, args: list) -> bool:
    if isinstance(args[0], Literal):
        ctx.ag.circ.add_event(Event(Trigger(ADD, BELIEF, args[0])))
    return True


@internal_action(".broadcast", arity=2)
def broadcast(ctx: IAContext, args: list) -> bool:
    ag = ctx.ag
    msg = Message(ag.name, "", _perf(args[0]), args[1])
    ag.arch.broadcast(ag, msg)
    return True
