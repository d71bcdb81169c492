"""Control and program internal actions: ``.if_then_else .foreach .loop`` (the statements
``if``/``for``/``while`` called as actions), ``.include``, ``.internal_action`` and
``.drop_future_intention``."""

from __future__ import annotations

from typing import Any

from .. import reasoning
from ..ia import IAContext, IAError, internal_action, wrong_arg
from ..parser import AslSyntaxError, include_namespace, parse_include, path_include_resolver
from ..plans import K_ACHIEVE, K_ACHIEVE_NEW, K_FOR, K_IF, K_WHILE, Deed
from ..terms import AnnotVar, Literal, LogExpr, PlanTerm, RelExpr, Var, is_internal_action, term_str
from ..unify import resolve, unify

#: what a condition may be (Jason: a ``LogicalFormula``)
_FORMULAS = (Literal, LogExpr, RelExpr, Var, AnnotVar)


def _body(t: Any, which: str) -> tuple:
    """The deeds of a plan-body argument (``{ a; b }``)."""
    if not (isinstance(t, PlanTerm) and t.plan is None and t.rule is None):
        raise wrong_arg(f"{which} argument must be a plan body term.")
    return t.body


def _run_now(ctx: IAContext, deed: Deed) -> dict:
    """Run the statement ``deed`` now, in this step, as Jason's actions do (the condition
    tested, the block put in place); the unifier it leaves."""
    im, i = ctx.im, ctx.intention
    if im is None or i is None:
        raise IAError(f"'{term_str(deed.term)}' runs only in a plan body")
    im.u = ctx.s
    reasoning.run_statement(ctx.ag, i, im, deed)
    return im.u


def _line(ctx: IAContext) -> int:
    return ctx.deed.line if ctx.deed is not None else 0


@internal_action(".if_then_else", arity=(2, 3))
def if_then_else(ctx: IAContext, args: list) -> dict:
    """``.if_then_else(Cond, {Then}[, {Else}])``: the ``if`` statement as an action."""
    if not isinstance(args[0], _FORMULAS):
        raise wrong_arg("first argument (test) must be a logical formula.")
    then = _body(args[1], "second")
    els = _body(args[2], "third") if len(args) == 3 else None
    return _run_now(ctx, Deed(K_IF, args[0], _line(ctx), ([(args[0], then)], els)))


@internal_action(".foreach", arity=2)
def foreach(ctx: IAContext, args: list) -> dict:
    """``.foreach(Cond, {Body})``: the ``for`` statement as an action (the body once per
    solution of Cond, taken lazily; bindings as before the loop afterwards)."""
    if not isinstance(args[0], _FORMULAS):
        raise wrong_arg("first argument must be a logical formula.")
    return _run_now(ctx, Deed(K_FOR, args[0], _line(ctx), _body(args[1], "second")))


@internal_action(".loop", arity=2)
def loop(ctx: IAContext, args: list) -> dict:
    """``.loop(Cond, {Body})``: the ``while`` statement as an action."""
    if not isinstance(args[0], _FORMULAS):
        raise wrong_arg("first argument (test) must be a logical formula.")
    return _run_now(ctx, Deed(K_WHILE, args[0], _line(ctx), _body(args[1], "second")))


@internal_action(".internal_action", arity=1)
def internal_action_(ctx: IAContext, args: list) -> bool:
    """``.internal_action(T)``: T is an internal action (``.print``, ``my.act(1)``)."""
    return isinstance(args[0], Literal) and is_internal_action(args[0].functor)


@internal_action(".include", arity=(1, 2))
def include(ctx: IAContext, args: list) -> bool:
    """``.include("f.asl"[, NS])``: add the file's plans, beliefs and goals to this agent, as
    the ``include`` directive does (NS free: a new namespace, bound to it)."""
    if not isinstance(args[0], str):
        raise wrong_arg("first argument must be a string.")
    if len(args) > 1 and not (isinstance(args[1], (Var, AnnotVar))
                              or (isinstance(args[1], Literal) and not args[1].args)):
        raise wrong_arg("second argument (the namespace) must be an atom or a variable.")
    ag = ctx.ag
    ns = include_namespace(args[1]) if len(args) > 1 else None
    try:
        parsed = parse_include(args[0], ag.filename, path_include_resolver(ag.source_path), ns)
    except OSError:
        raise IAError(f"the included file '{args[0]}' was not found") from None
    except AslSyntaxError as err:
        raise IAError(f"cannot include '{args[0]}': {err}") from None
    ag.include(parsed)
    return ns is None or ctx.unify(args[1], Literal(ns))


@internal_action(".drop_future_intention", arity=1)
def drop_future_intention(ctx: IAContext, args: list) -> bool:
    """``.drop_future_intention(G)``: drop each intention whose current plan has ``!G`` (or
    ``!!G``) still to do; no event is posted."""
    if not isinstance(args[0], Literal):
        raise wrong_arg(f"first argument '{term_str(args[0])}' must be a literal")
    ag = ctx.ag
    for i in list(ag.circ.all_intentions()):
        if not i.ims:
            continue
        im = i.ims[-1]
        for d in reversed(im.stack):
            if d.kind in (K_ACHIEVE, K_ACHIEVE_NEW) and unify(resolve(d.term, im.u, ag), args[0],
                                                                dict(ctx.s), ag):
                ag.circ.remove_intention(i)
                break
    return True
