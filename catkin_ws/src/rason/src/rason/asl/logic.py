"""Logical consequence (Jason's ``logicalConsequence``): contexts, rules, test goals, queries."""

from __future__ import annotations

import operator
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from .functions import FunctionHost
from .ia import IAContext, call_ia
from .plans import Plan, body_str, plan_term_trigger
from .terms import (
    LOCAL_NS_PREFIX,
    AnnotVar,
    ArithExpr,
    ListTerm,
    Literal,
    LogExpr,
    NsLit,
    PlanTerm,
    RelExpr,
    Rule,
    Var,
    in_ns,
    is_constant,
    is_internal_action,
    make_list,
    split_ns,
)
from .unify import (
    ArithError,
    Operand,
    annot_options,
    compare_terms,
    eval_arith,
    rename_vars,
    resolve,
    term_equals,
    unify,
    unify_annots,
    walk,
)

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent
    from .intentions import Intention


def solve(ag: Agent, f: Any, s: dict, intention: Intention | None = None) -> Iterator[dict]:
    """Yield every substitution extending ``s`` under which ``f`` follows from the agent's state."""
    if isinstance(f, Var):
        f = walk(f, s)
        if isinstance(f, Var):
            yield from _query_var(ag, f, s)
            return
    tf = type(f)
    if tf is AnnotVar:
        f = resolve(f, s, ag)   # bound: the value with the variable's annotations (VarTerm.capply)
        if type(f) is AnnotVar:
            yield from _query_var(ag, f, s)
            return
        tf = type(f)
    if tf is Literal:
        fn = f.functor
        if is_internal_action(fn):
            yield from _solve_ia(ag, f, s, intention)
            return
        if not f.args and not f.annots and not f.neg:
            if fn == "true":
                yield s
                return
            if fn == "false":
                return
        yield from query_bb(ag, f, s)
        return
    if tf is NsLit:
        f = resolve(f, s, ag)
        if type(f) is NsLit:
            yield from _query_ns(ag, f, s)
            return
        yield from solve(ag, f, s, intention)
        return
    if tf is LogExpr:
        op = f.op
        if op == "&":
            for s1 in solve(ag, f.left, s, intention):
                yield from solve(ag, f.right, s1, intention)
        elif op == "|":
            yield from solve(ag, f.left, s, intention)
            yield from solve(ag, f.right, s, intention)
        else:  # not
            for _ in solve(ag, f.left, s, intention):
                return
            yield s
        return
    if tf is RelExpr:
        r = eval_rel(f, s, ag)
        if r is not None:
            yield r
        return
    return


def first_solution(ag: Agent, f: Any, s: dict, intention: Intention | None = None) -> dict | None:
    """The first solution of ``f`` extending ``s``, or None (see also :func:`compile_context`)."""
    if type(f) is RelExpr:
        return eval_rel(f, s, ag)
    for sol in solve(ag, f, s, intention):
        return sol
    return None


#: the numeric comparisons, by operator (the one home of this set: :func:`eval_rel` calls them,
#: a :class:`BeliefContext` makes them itself by their position here)
_NUMERIC_COMPARE = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
_COMPARE_CODES = {op: code for code, op in enumerate(_NUMERIC_COMPARE)}


class BeliefContext:
    """``first_solution(ag, f, s)`` for the commonest context shape, prepared once per plan.

    The shape is ``b(T1, ..., Tn) & L op R``: a belief literal without annotations whose
    arguments are variables or constants, then a numeric comparison of variables and numbers,
    e.g. ``value(X) & X < 3700`` (see :func:`compile_context`). Rules, non-numbers and bound
    variables are handed to :func:`unify`, :func:`eval_rel` or :func:`first_solution`, so both
    always give the same answer. The beliefs are read live (:meth:`~.beliefs.BeliefBase.live`):
    nothing in this loop changes them, and it returns at the first call that could.
    """

    __slots__ = ("arg_names", "args", "first", "first_name", "formula", "key", "left", "op",
                 "rel", "right")

    def __init__(self, f: LogExpr, belief: Literal, rel: RelExpr) -> None:
        self.formula = f
        self.rel = rel
        self.key = belief.key
        self.args: tuple = belief.args
        #: per argument: the variable's name, or None for a constant
        self.arg_names: list[str | None] = [a.name if type(a) is Var else None for a in belief.args]
        self.first: Any = belief.args[0]
        self.first_name = self.arg_names[0]
        self.left = Operand(rel.left)
        self.right = Operand(rel.right)
        self.op: int = _COMPARE_CODES[rel.op]

    def solve(self, ag: Agent, s: dict) -> dict | None:
        """The first solution extending ``s``, or None."""
        bb = ag.bb
        if self.first_name is None:
            cands: Any = bb.candidates_by_first(self.key, self.first)
        else:
            # bound: only the beliefs with that first argument are looked at
            f0 = s.get(self.first_name)
            cands = bb.live(self.key) if f0 is None else bb.candidates_by_first(self.key, walk(f0, s))
        n = len(self.args)
        for b in cands:
            if type(b) is not Literal:
                return first_solution(ag, self.formula, s)   # rules: the general way
            held = b.args
            s1 = dict(s) if s else {}
            k = 0
            while k < n:
                name = self.arg_names[k]
                if name is not None and name not in s1:
                    s1[name] = held[k]
                elif not unify(self.args[k], held[k], s1, ag):
                    break
                k += 1
            if k < n:
                continue
            x = self.left.value(s1)
            y = self.right.value(s1)
            if type(x) is float and type(y) is float:
                op = self.op
                if x < y if op == 0 else x <= y if op == 1 else x > y if op == 2 else x >= y:
                    return s1
                continue
            s2 = eval_rel(self.rel, s1, ag)
            if s2 is not None:
                return s2
        return None


def compile_context(f: Any) -> BeliefContext | None:
    """A :class:`BeliefContext` for the context ``f``, or None when its shape is another."""
    if not (type(f) is LogExpr and f.op == "&" and type(f.right) is RelExpr
            and f.right.op in _COMPARE_CODES):
        return None
    left, rel = f.left, f.right
    if (type(left) is not Literal or not left.args or is_internal_action(left.functor) or left.annots
            or left.tail is not None
            or not all(type(a) is Var or is_constant(a) for a in left.args)
            or not all(type(x) in (Var, float) for x in (rel.left, rel.right))):
        return None
    return BeliefContext(f, left, rel)


def eval_rel(f: RelExpr, s: dict, ag: FunctionHost | None = None) -> dict | None:
    """Evaluate a relational expression; returns the (possibly extended) substitution or None
    (``ag``: the agent of ``math.random`` and ``.count``)."""
    op = f.op
    compare = _NUMERIC_COMPARE.get(op)
    if compare is not None:
        try:   # the common case: two numbers (NaN fails)
            return s if compare(eval_arith(f.left, s, ag), eval_arith(f.right, s, ag)) else None
        except ArithError:
            pass   # not two numbers: compared as terms below
    if op == "=":
        s2 = dict(s)
        if unify(resolve(f.left, s, ag), resolve(f.right, s, ag), s2, ag):
            return s2
        return None
    if op == "==":
        return s if term_equals(f.left, f.right, s) else None
    if op == "\\==":
        return None if term_equals(f.left, f.right, s) else s
    if op == "=..":
        return _univ(f, s, ag)
    a = resolve(f.left, s, ag)
    b = resolve(f.right, s, ag)
    if isinstance(a, (Var, ArithExpr)) or isinstance(b, (Var, ArithExpr)):
        return None
    c = compare_terms(a, b)
    if isinstance(a, float) and isinstance(b, float) and (a != a or b != b):
        return None
    ok = (c < 0 if op == "<" else c <= 0 if op == "<=" else c > 0 if op == ">" else c >= 0)
    return s if ok else None


def _univ(f: RelExpr, s: dict, ag: FunctionHost | None) -> dict | None:
    """``T =.. L`` as Jason 3: a literal is ``[Namespace, Functor, Args, Annots]`` (a list of
    three items leaves the namespace out), a labelled plan term ``[Label, {Trigger}, {Context},
    {Body}]``; a list builds the literal, or the plan when its fourth item is a body term."""
    a = resolve(f.left, s, ag)
    s2 = dict(s)
    b = resolve(f.right, s, ag)
    if isinstance(a, PlanTerm) and a.plan is not None:
        plan = a.plan
        if not isinstance(plan.label, Literal):
            return None   # as Jason (it has no label to put first)
        trig = Plan(None, plan.trigger, None, (), in_file=False)
        lst = make_list([plan.label, PlanTerm((), str(plan.trigger), trig, braces=False),
                         Literal("true") if plan.context is None else plan.context,
                         PlanTerm(plan.body, body_str(plan.body), braces=False)])
        return s2 if unify(f.right, lst, s2, ag) else None
    if isinstance(a, Literal):
        ns, bare = split_ns(a)
        items = [Literal(ns), Literal(bare.functor, neg=bare.neg), make_list(a.args), make_list(a.annots)]
        if isinstance(b, ListTerm) and b.tail is None and len(b.items) == 3:
            items = items[1:]
        return s2 if unify(f.right, make_list(items), s2, ag) else None
    if not isinstance(b, ListTerm) or b.tail is not None or not b.items:
        return None
    items = list(b.items)
    if len(items) == 4 and isinstance(items[3], PlanTerm) and items[3].plan is None:
        made = _plan_from_items(items)
        return s2 if made is not None and unify(f.left, made, s2, ag) else None
    ns = "default"
    if len(items) == 4:
        if not isinstance(items[0], Literal) or items[0].args:
            return None
        ns = items[0].functor
        items = items[1:]
    head = items[0]
    if isinstance(head, str):
        functor, neg = head, False
    elif isinstance(head, Literal):
        functor, neg = head.functor, head.neg
    else:
        return None
    args = items[1].items if len(items) > 1 and isinstance(items[1], ListTerm) else ()
    annots = items[2].items if len(items) > 2 and isinstance(items[2], ListTerm) else ()
    lit = in_ns(ns, Literal(functor, tuple(args), tuple(annots), neg=neg))
    return s2 if unify(f.left, lit, s2, ag) else None


def _plan_from_items(items: list) -> PlanTerm | None:
    """The plan term of ``[Label, {Trigger}, {Context}, {Body}]`` (Jason's
    ``Plan.newFromListOfTerms``), or None when the items do not make one."""
    label, trig_t, ctx_t, body_t = items
    if not isinstance(label, Literal) or not isinstance(trig_t, PlanTerm):
        return None
    trigger = plan_term_trigger(trig_t)
    if trigger is None:
        return None
    context: Any = ctx_t   # the formula itself, or a body term holding it
    if isinstance(ctx_t, PlanTerm):
        if ctx_t.plan is not None or len(ctx_t.body) != 1:
            return None
        context = ctx_t.body[0].term
    plan = Plan(label, trigger, context, body_t.body, in_file=False)
    return PlanTerm(plan.body, plan.as_text(), plan, braces=False)   # printed as Jason's Plan


def query_bb(ag: Agent, lit: Literal, s: dict) -> Iterator[dict]:
    """Solutions of ``lit`` against the belief base (beliefs and rules, in order)."""
    args = lit.args
    cands = ag.bb.candidates_by_first(lit.key, walk(args[0], s)) if args else ag.bb.candidates(lit.key)
    if not cands:
        return
    want_annots = bool(lit.annots) or lit.tail is not None
    for b in cands:
        if type(b) is Literal:
            s2 = dict(s)
            ok = True
            for x, y in zip(args, b.args, strict=False):
                if not unify(x, y, s2, ag):
                    ok = False
                    break
            if not ok:
                continue
            if want_annots:
                if lit.tail is None:
                    yield from annot_options(lit, b, s2, ag)
                elif unify_annots(lit, b, s2, ag):
                    yield s2
            else:
                yield s2
        elif isinstance(b, Rule):
            mapping: dict = {}
            head = rename_vars(b.head, mapping)
            body = rename_vars(b.body, mapping)
            s2 = dict(s)
            ok = True
            for x, y in zip(args, head.args, strict=False):
                if not unify(x, y, s2, ag):
                    ok = False
                    break
            if not ok:
                continue
            if want_annots and head.annots and not unify_annots(lit, head, s2, ag):
                continue
            yield from solve(ag, body, s2)


def _query_ns(ag: Agent, f: NsLit, s: dict) -> Iterator[dict]:
    """``N::b(X)`` with N free: the query in each namespace of the belief base (Jason's order),
    N bound to it; local namespaces are not taken (as in Jason). ``N::X``: every belief."""
    lit = f.lit
    if type(lit) is not Literal:
        for b in list(ag.bb):
            s2 = dict(s)
            if type(b) is Literal and unify(f, b, s2, ag):
                yield s2
        return
    for ns in ag.bb.namespaces():
        if ns.startswith(LOCAL_NS_PREFIX):
            continue
        s2 = dict(s)
        if unify(f.ns, Literal(ns), s2, ag):
            yield from query_bb(ag, in_ns(ns, lit), s2)


def _query_var(ag: Agent, v: Var | AnnotVar, s: dict) -> Iterator[dict]:
    """An unbound (maybe annotated) variable as a query: every belief and rule is a candidate
    (Jason ``DefaultBeliefBase.getCandidateBeliefs`` of a var), here in our belief-base order.

    ``X[source(A)]`` tries each way its annotations match a belief's (Jason's annotation
    backtracking in ``Literal.logicalConsequence``); X gets the belief without annotations."""
    backtrack = v if isinstance(v, AnnotVar) and v.tail is None else None
    for b in list(ag.bb):
        if type(b) is Literal:
            if backtrack is None:
                s2 = dict(s)
                if unify(v, b, s2, ag):
                    yield s2
                continue
            for s2 in annot_options(backtrack, b, s, ag):   # each way the annotations match b's
                s2 = dict(s2)
                s2[v.name] = b.no_annots()
                yield s2
        elif isinstance(b, Rule):
            mapping: dict = {}
            head = rename_vars(b.head, mapping)
            for sol in solve(ag, rename_vars(b.body, mapping), dict(s)):
                s2 = dict(sol)
                if unify(v, resolve(head, sol, ag), s2, ag):
                    yield s2


def _solve_ia(ag: Agent, f: Literal, s: dict, intention: Intention | None) -> Iterator[dict]:
    ctx = IAContext(ag, s, intention)
    try:
        r = call_ia(ctx, f)
    except Exception:
        return
    if r is True:
        yield ctx.s
    elif r is False or r is None:
        return
    elif isinstance(r, dict):
        yield r
    else:
        try:
            yield from r
        except ArithError:
            return
