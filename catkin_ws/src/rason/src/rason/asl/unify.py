"""Unification, substitution application (``capply``) and arithmetic evaluation.

A substitution (Jason's ``Unifier``) is a plain ``dict`` from variable name to term.
Functions that may fail mutate the dict they are given: callers copy it first when they
need to backtrack.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from .functions import (
    ARITH_FUNCTIONS,
    ARITH_NAMES,
    LIST_FUNCTIONS,
    USER_FUNCTIONS,
    ArithError,
    FunctionHost,
    UserFunction,
    divide,
    java_int_div,
    java_mod,
    power,
)
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
    Var,
    fresh_name,
    in_ns,
    is_constant,
    is_ground,
    merge_annots,
    sort_key,
    split_ns,
    term_str,
)

Subst = dict


def walk(t: Any, s: Subst) -> Any:
    """Follow variable bindings until a non-variable or unbound variable."""
    while isinstance(t, Var):
        b = s.get(t.name)
        if b is None:
            return t
        t = b
    return t


# ---------------------------------------------------------------- arithmetic

def _numbers_of(t: Any) -> list | None:
    """The numbers of a (resolved) list, as Jason's list functions take them; None if no list."""
    if not isinstance(t, ListTerm):
        return None
    items = list(t.items)
    rest = t.tail
    while isinstance(rest, ListTerm):
        items.extend(rest.items)
        rest = rest.tail
    return [x for x in items if type(x) is float]


def _list_len(t: Any) -> int:
    n = 0
    while isinstance(t, ListTerm):
        n += len(t.items)
        t = t.tail
    return n


def eval_arith(t: Any, s: Subst, ag: FunctionHost | None = None) -> float:
    """Evaluate ``t`` as a number; raises :class:`ArithError` if it is not numeric.

    ``ag``: the agent of ``math.random`` and ``.count`` (without it they are not numbers)."""
    tt = type(t)
    if tt is float:
        return t
    if tt is Var:
        t = walk(t, s)
        tt = type(t)
        if tt is float:
            return t
    if tt is ArithExpr:
        a = t.left
        if type(a) is Var:
            a = s.get(a.name, a)
        if type(a) is not float:
            a = eval_arith(a, s, ag)
        op = t.op
        if op == "neg":
            return -a
        b = t.right
        if type(b) is Var:
            b = s.get(b.name, b)
        if type(b) is not float:
            b = eval_arith(b, s, ag)
        if op == "+":
            return a + b
        if op == "-":
            return a - b
        if op == "*":
            return a * b
        if op == "/":
            return divide(a, b)
        if op == "**":
            return power(a, b)
        if op == "div":
            return java_int_div(a, b)
        if op == "mod":
            return java_mod(a, b)
        raise ArithError(op)
    if isinstance(t, Literal) and not t.neg:
        fn = t.functor
        if fn[0] == "." and len(t.args) == 1:
            return _agent_function(fn, t.args[0], s, ag)
        f = ARITH_FUNCTIONS.get(fn)
        if f is not None:
            if len(t.args) == 1 and type(t.args[0]) is not float:
                lf = LIST_FUNCTIONS.get(t.functor)
                if lf is not None:
                    arg = resolve(t.args[0], s, ag)
                    xs = _numbers_of(arg)
                    if xs is not None:
                        try:
                            return float(lf(xs, _list_len(arg)))
                        except TypeError as e:
                            raise ArithError(str(e)) from None
            args = [eval_arith(a, s, ag) for a in t.args]
            try:
                return float(f(*args))
            except (TypeError, ValueError, OverflowError) as e:
                raise ArithError(str(e)) from None
        uf = USER_FUNCTIONS.get(fn)
        if uf is not None and len(t.args) == uf.arity:
            return _user_function(uf, t, s, ag)
        if t.functor == "math.random" and ag is not None:
            args = [eval_arith(a, s, ag) for a in t.args]
            r = ag.random.random()
            return r * args[0] if args else r
        if t.functor == "system.time" and not t.args and ag is not None:
            return ag.clock_millis()
    raise ArithError(f"not a number: {t!r}")


def _agent_function(fn: str, arg: Any, s: Subst, ag: FunctionHost | None) -> float:
    """Jason's ``.length(L)`` (jason.functions.Length) and ``.count(Q)`` (jason.functions.Count)."""
    if fn == ".length":
        a = resolve(arg, s, ag)
        if isinstance(a, str):
            return float(len(a))
        if isinstance(a, ListTerm):
            n = 0
            while isinstance(a, ListTerm):
                n += len(a.items)
                a = a.tail
            if a is None:
                return float(n)
        raise ArithError(".length of a non-list")
    if fn == ".count" and ag is not None:
        return float(ag.count_solutions(resolve(arg, s, ag)))
    raise ArithError(f"not a function: {fn}")


#: the variable a rule-based function's query binds to its result
_RESULT = "__RuleToFunctionResult"


def _user_function(uf: UserFunction, t: Literal, s: Subst, ag: FunctionHost | None) -> float:
    """A registered function (``register_function``) applied to the arguments of ``t``."""
    args = [resolve(a, s, ag) for a in t.args]
    # Any: a rule's result may be a term that is no number (refused below), which a variable
    # typed float would refuse earlier with a TypeError in the compiled (mypyc) module
    value: Any
    if uf.compute is not None:
        try:
            value = uf.compute(ag, args)
        except (TypeError, ValueError, ArithmeticError) as e:
            raise ArithError(f"{t.functor}: {e}") from None
    else:
        if ag is None or uf.rule is None:
            raise ArithError(f"{t.functor} needs an agent")
        query = Literal(uf.rule, (*args, Var(_RESULT)))
        value = None
        for sol in ag.solve(query, {}):
            value = resolve(Var(_RESULT), sol, ag)
            break
        else:
            raise ArithError(f"No solution was found for rule {term_str(query)}")
    if type(value) is int:
        value = float(value)
    if type(value) is not float:
        raise ArithError(f"The result of {t.functor} (={term_str(value)}) is not numeric!")
    return value


def is_arith_function(t: Any) -> bool:
    return isinstance(t, Literal) and t.functor in ARITH_NAMES


# ---------------------------------------------------------------- capply

def _all_constant(annots: tuple) -> bool:
    """True when every annotation is a number, a string or a known-constant literal."""
    for a in annots:
        ta = type(a)
        if not (ta is float or ta is str or (ta is Literal and a.known_constant)):
            return False
    return True


def resolve(t: Any, s: Subst, ag: FunctionHost | None = None) -> Any:
    """Apply the substitution (Jason ``capply``); ground arithmetic is evaluated
    (``ag``: the agent of ``math.random`` and ``.count``)."""
    tt = type(t)
    if tt is float or tt is str:
        return t
    if tt is Var:
        b = s.get(t.name)
        if b is None:
            return t
        tb = type(b)
        if tb is float or tb is str:
            return b
        return resolve(b, s, ag)
    if tt is Literal:
        if t.known_constant:  # known constant (computed by the parser for program literals)
            return t
        if t.functor in ARITH_NAMES:
            try:
                return eval_arith(t, s, ag)
            except ArithError:
                pass
        args = tuple([resolve(a, s, ag) for a in t.args]) if t.args else ()
        annots = t.annots
        tail = t.tail
        if tail is None and _all_constant(annots):
            return Literal(t.functor, args, annots, None, t.neg)
        if annots or tail is not None:
            old_annots = annots
            annots = tuple([resolve(a, s, ag) for a in annots])
            if tail is None and annots == old_annots:
                return Literal(t.functor, args, old_annots, None, t.neg)
            if tail is not None:
                tv = resolve(tail, s, ag)
                if isinstance(tv, ListTerm):
                    extra = list(tv.items)
                    rest = tv.tail
                    while isinstance(rest, ListTerm):
                        extra.extend(rest.items)
                        rest = rest.tail
                    annots = merge_annots(annots, extra)
                    tail = rest
                else:
                    tail = tv
            if len(annots) > 1:
                uniq = list(dict.fromkeys(annots))
                annots = tuple(sorted(uniq, key=sort_key))
        return Literal(t.functor, args, annots, tail, t.neg)
    if tt is ArithExpr:
        try:
            return eval_arith(t, s, ag)
        except (ArithError, RecursionError):
            r = t.right
            e = ArithExpr(t.op, resolve(t.left, s, ag), None if r is None else resolve(r, s, ag))
            if is_ground(e):
                return math.nan  # Jason: a ground expression over non-numbers evaluates to NaN
            return e
    if tt is AnnotVar:
        return _resolve_annot_var(t, s, ag)
    if tt is NsLit:
        return _resolve_ns_lit(t, s, ag)
    if isinstance(t, ListTerm):
        items = [resolve(a, s, ag) for a in t.items]
        tail = t.tail
        while tail is not None:
            tail = resolve(tail, s, ag)
            if isinstance(tail, ListTerm):
                items.extend(tail.items)
                tail = tail.tail
            else:
                break
        return ListTerm(tuple(items), tail)
    if isinstance(t, RelExpr):
        return RelExpr(t.op, resolve(t.left, s, ag), resolve(t.right, s, ag))
    if isinstance(t, LogExpr):
        r = t.right
        return LogExpr(t.op, resolve(t.left, s, ag), None if r is None else resolve(r, s, ag))
    if tt is PlanTerm and s:
        return t.map_terms(lambda x: resolve(x, s, ag))
    return t


def _resolve_annot_var(t: AnnotVar, s: Subst, ag: FunctionHost | None) -> Any:
    """Jason ``VarTerm.capply`` of an annotated variable: unbound, the variable as written
    (its annotations are not applied); bound to a literal, that literal plus the variable's
    annotations (``X = p[a]``, ``X[b]`` gives ``p[a,b]``); bound to anything else, the value."""
    v = s.get(t.name)
    while type(v) is Var:
        v = s.get(v.name)
    if v is None:
        return t
    v = resolve(v, s, ag)
    if type(v) is not Literal:
        return v
    extra = [resolve(a, s, ag) for a in t.annots]
    if t.tail is not None:
        tv = resolve(t.tail, s, ag)
        if isinstance(tv, ListTerm):  # a bound tail adds its items, an unbound one nothing
            items, _ = _items_and_tail(tv.items, tv.tail, s)
            extra.extend(items)
    return v.add_annots(extra) if extra else v


def _resolve_ns_lit(t: NsLit, s: Subst, ag: FunctionHost | None) -> Any:
    """``N::b(X)``: the literal in N's namespace once N is an atom, else still an ``NsLit``."""
    ns = walk(t.ns, s)
    lit = resolve(t.lit, s, ag)
    if type(lit) in (float, str, ListTerm):   # Jason: only a literal has a namespace
        return lit
    if type(ns) is Literal and not ns.args and type(lit) is Literal:
        if "::" in lit.functor:   # a variable bound to a literal of its own namespace
            lit = split_ns(lit)[1]
        return in_ns(ns.functor, lit)
    return NsLit(ns if type(ns) in (Var, Literal) else t.ns, lit)


def _unify_ns_lit(a: Any, b: Any, s: Subst, ag: FunctionHost | None) -> bool:
    """Unify where one side (or both) is a literal of a variable namespace: the namespaces
    unify as atoms (``default`` for none; never with a local namespace's name, as in
    Jason), then the literals without them."""
    if type(a) is NsLit:
        a = _resolve_ns_lit(a, s, ag)
    if type(b) is NsLit:
        b = _resolve_ns_lit(b, s, ag)
    if type(a) is NsLit and type(b) is NsLit:
        return unify(a.ns, b.ns, s, ag) and unify(a.lit, b.lit, s, ag)
    if type(a) is NsLit or type(b) is NsLit:
        pattern, other = (a, b) if type(a) is NsLit else (b, a)
        if type(other) is not Literal:
            # a number, string or list has no namespace: ``N::X = 5`` binds X, leaves N free
            return type(pattern.lit) is Var and type(other) in (float, str, ListTerm) and unify(
                pattern.lit, other, s, ag)
        ns, bare = split_ns(other)
        if ns.startswith(LOCAL_NS_PREFIX) or not unify(pattern.ns, Literal(ns), s, ag):
            return False
        return unify(pattern.lit, bare, s, ag) if pattern is a else unify(bare, pattern.lit, s, ag)
    return unify(a, b, s, ag)


def _bind_to_ns_lit(v: Var, t: NsLit, s: Subst, ag: FunctionHost | None) -> bool:
    """A plain (free) variable against ``N::lit`` / ``N::X``: as in Jason, the variable is in the
    default namespace, so N must unify with ``default``; then the variable takes the literal."""
    r = _resolve_ns_lit(t, s, ag)
    if type(r) is not NsLit:
        return unify(v, r, s, ag)
    return unify(r.ns, _DEFAULT_NS, s, ag) and unify(v, r.lit, s, ag)


_DEFAULT_NS = Literal("default")


#: how a :class:`LiteralBuilder` makes one argument
_ARG_CONSTANT = 0     # the argument as written
_ARG_VARIABLE = 1     # the variable's value
_ARG_ARITH = 2        # ``+ - *`` of two operands, each a variable or a number

_ARITH_OPS = {"+": 0, "-": 1, "*": 2}


class Operand:
    """One side of a compiled ``L op R``: a variable's name, or a number."""

    __slots__ = ("name", "number")

    def __init__(self, x: Any) -> None:
        self.name: str | None = x.name if type(x) is Var else None
        self.number: Any = None if type(x) is Var else x

    def value(self, s: Subst) -> Any:
        """The number or the variable's binding (None when unbound)."""
        return self.number if self.name is None else s.get(self.name)


class _ArgRecipe:
    """How one argument of a compiled body literal is made (see :class:`LiteralBuilder`)."""

    __slots__ = ("kind", "left", "name", "op", "right", "term")

    def __init__(self, kind: int, term: Any) -> None:
        self.kind = kind
        self.term = term
        self.name: str = term.name if kind == _ARG_VARIABLE else ""
        arith = kind == _ARG_ARITH
        self.op: int = _ARITH_OPS[term.op] if arith else 0
        self.left: Operand | None = Operand(term.left) if arith else None
        self.right: Operand | None = Operand(term.right) if arith else None


class LiteralBuilder:
    """``resolve(t, s, ag)`` for a plan-body literal of a common shape, prepared once per plan.

    Made by :func:`compile_resolve`; numbers are computed directly and anything else (an
    unbound variable, a structure) is handed to :func:`resolve`, so both give the same term.
    """

    __slots__ = ("annots", "functor", "neg", "recipes")

    def __init__(self, t: Literal, recipes: list[_ArgRecipe]) -> None:
        self.functor = t.functor
        self.annots = t.annots
        self.neg = t.neg
        self.recipes = recipes

    def build(self, s: Subst, ag: FunctionHost | None = None) -> Literal:
        """The literal under ``s``."""
        args: list[Any] = []
        for r in self.recipes:
            kind = r.kind
            if kind == _ARG_CONSTANT:
                args.append(r.term)
            elif kind == _ARG_VARIABLE:
                v = s.get(r.name)
                if v is None:
                    v = r.term
                elif type(v) is not float and type(v) is not str:
                    v = resolve(v, s, ag)
                args.append(v)
            else:
                assert r.left is not None and r.right is not None
                x = r.left.value(s)
                y = r.right.value(s)
                if type(x) is float and type(y) is float:
                    args.append(x + y if r.op == 0 else x - y if r.op == 1 else x * y)
                else:
                    args.append(resolve(r.term, s, ag))
        return Literal(self.functor, tuple(args), self.annots, None, self.neg)


def compile_resolve(t: Any) -> LiteralBuilder | None:
    """A :class:`LiteralBuilder` for ``t``, or None when its shape is not a common one.

    The common shape: a literal without annotation variables or tail whose arguments are each
    a constant, a variable, or ``+ - *`` of two operands that are variables or numbers, e.g.
    ``value(X+1)[source(self)]``.
    """
    if (type(t) is not Literal or t.tail is not None or t.known_constant or t.functor in ARITH_NAMES
            or not _all_constant(t.annots)):
        return None
    recipes: list[_ArgRecipe] = []
    for arg in t.args:
        if is_constant(arg):
            recipes.append(_ArgRecipe(_ARG_CONSTANT, arg))
        elif type(arg) is Var:
            recipes.append(_ArgRecipe(_ARG_VARIABLE, arg))
        elif (type(arg) is ArithExpr and arg.op in _ARITH_OPS
              and all(type(x) in (Var, float) for x in (arg.left, arg.right))):
            recipes.append(_ArgRecipe(_ARG_ARITH, arg))
        else:
            return None
    return LiteralBuilder(t, recipes)


# ---------------------------------------------------------------- unification

def unify(a: Any, b: Any, s: Subst, ag: FunctionHost | None = None) -> bool:
    """Unify ``a`` (pattern: its annotations must be a subset of ``b``'s) with ``b``."""
    a = walk(a, s)
    b = walk(b, s)
    if a is b:
        return True
    if isinstance(a, Var):
        if isinstance(b, Var):
            if b.name == a.name:
                return True
        elif type(b) is AnnotVar:
            return _unify_annot_var(a, b, s, ag)
        elif type(b) is Literal:
            if "::" in b.functor and b.functor[0] != "'":
                return False   # a plain variable is in the default namespace (Jason)
        elif type(b) is NsLit:
            return _bind_to_ns_lit(a, b, s, ag)
        s[a.name] = b
        return True
    if isinstance(b, Var):
        if type(a) is AnnotVar:
            return _unify_annot_var(a, b, s, ag)
        if type(a) is Literal:
            if "::" in a.functor and a.functor[0] != "'":
                return False
        elif type(a) is NsLit:
            return _bind_to_ns_lit(b, a, s, ag)
        s[b.name] = a
        return True
    ta = type(a)
    if ta is float:
        if type(b) is float:
            return a == b
        if isinstance(b, (ArithExpr, Literal)):
            try:
                return a == eval_arith(b, s, ag)
            except ArithError:
                return False
        return type(b) is AnnotVar and _unify_annot_var(a, b, s, ag)
    if ta is str:
        if type(b) is str:
            return a == b
        return type(b) is AnnotVar and _unify_annot_var(a, b, s, ag)
    if ta is Literal:
        if type(b) is not Literal:
            if type(b) is AnnotVar:
                return _unify_annot_var(a, b, s, ag)
            if type(b) is NsLit:
                return _unify_ns_lit(a, b, s, ag)
            if type(b) is float and is_arith_function(a):
                try:
                    return eval_arith(a, s, ag) == b
                except ArithError:
                    return False
            return False
        if a.functor != b.functor or a.neg != b.neg or len(a.args) != len(b.args):
            return False
        for x, y in zip(a.args, b.args, strict=False):
            if not unify(x, y, s, ag):
                return False
        if a.annots or a.tail is not None:
            return unify_annots(a, b, s, ag)
        return True
    if ta is ListTerm:
        if type(b) is not ListTerm:
            return type(b) is AnnotVar and _unify_annot_var(a, b, s, ag)
        return _unify_lists(a, b, s, ag)
    if ta is AnnotVar or type(b) is AnnotVar:
        return _unify_annot_var(a, b, s, ag)
    if ta is NsLit or type(b) is NsLit:
        return _unify_ns_lit(a, b, s, ag)
    if ta is ArithExpr:
        try:
            va = eval_arith(a, s, ag)
        except ArithError:
            if type(b) is ArithExpr and a.op == b.op:
                return unify(a.left, b.left, s, ag) and (a.right is None or unify(a.right, b.right, s, ag))
            return False
        try:
            return va == eval_arith(b, s, ag)
        except ArithError:
            return False
    if ta in (RelExpr, LogExpr):
        if type(b) is not ta or a.op != b.op:
            return False
        if not unify(a.left, b.left, s, ag):
            return False
        if a.right is None:
            return b.right is None
        return b.right is not None and unify(a.right, b.right, s, ag)
    if ta is PlanTerm:
        if type(b) is AnnotVar:
            return _unify_annot_var(a, b, s)
        return type(b) is PlanTerm and _unify_plan_terms(a, b, s)
    return a == b


_NOLABEL = Literal("nolabel")
_TRUE = Literal("true")


def _unify_plan_terms(a: PlanTerm, b: PlanTerm, s: Subst) -> bool:
    """Plan terms unify part by part, as Jason's ``Plan`` (label, trigger, context, body),
    ``Trigger`` and ``PlanBody`` structures do; rules as their head and body."""
    if a.rule is not None or b.rule is not None:
        return (a.rule is not None and b.rule is not None and unify(a.rule.head, b.rule.head, s)
                and unify(a.rule.body, b.rule.body, s))
    pa, pb = a.plan, b.plan
    if pa is None and pb is None:
        return _unify_bodies(a.body, b.body, s)
    if pa is None or pb is None:
        return False
    ta, tb = pa.trigger, pb.trigger
    if ta.op != tb.op or ta.type != tb.type:
        return False
    ca = _TRUE if pa.context is None else pa.context
    cb = _TRUE if pb.context is None else pb.context
    return (unify(_NOLABEL if pa.label is None else pa.label, _NOLABEL if pb.label is None else pb.label, s)
            and unify(ta.literal, tb.literal, s) and unify(ca, cb, s)
            and _unify_bodies(pa.body, pb.body, s))


def _body_var(d: Any, s: Subst) -> Var | None:
    """The unbound variable a body formula is made of (``B`` in ``{ B }``), or None."""
    if d.kind != "action" or type(d.term) is not Var:
        return None
    v = walk(d.term, s)
    return v if type(v) is Var else None


def _unify_bodies(da: tuple, db: tuple, s: Subst) -> bool:
    """Jason's plan-body unification: formula by formula; a variable formula takes one
    formula, or, when it is the last one, the rest of the other body (``{ T; _ }``)."""
    while True:
        if not da or not db:
            rest = da or db
            if not rest:
                return True
            if len(rest) == 1 and _body_var(rest[0], s) is not None:
                return unify(rest[0].term, PlanTerm.of_body(()), s)
            return False
        x, y = da[0], db[0]
        vx, vy = _body_var(x, s), _body_var(y, s)
        if vx is not None and len(da) == 1:
            return unify(vx, PlanTerm.of_body(db), s)
        if vy is not None and len(db) == 1:
            return unify(vy, PlanTerm.of_body(da), s)
        if vx is not None:
            ok = unify(vx, PlanTerm.of_body((y,)), s)
        elif vy is not None:
            ok = unify(vy, PlanTerm.of_body((x,)), s)
        elif x.kind != y.kind:
            return False
        elif x.kind in ("if", "while", "for"):
            ok = str(x) == str(y)
        else:
            ok = unify(x.term, y.term, s)
        if not ok:
            return False
        da, db = da[1:], db[1:]


#: terms that are Jason ``Pred`` instances for the annotation check of annotated variables
_PRED_LIKE = (Literal, Var, AnnotVar)


def _value_of(t: AnnotVar, s: Subst) -> Any:
    """The value of an annotated variable's name, or the last (unbound) :class:`Var` it leads to."""
    v = s.get(t.name)
    if v is None:
        return Var(t.name)
    while type(v) is Var:
        nv = s.get(v.name)
        if nv is None:
            return v
        v = nv
    return v


def _unify_annot_var(a: Any, b: Any, s: Subst, ag: FunctionHost | None = None) -> bool:
    """Unification when ``a`` or ``b`` is an annotated variable (Jason ``Unifier.unifiesNoUndo``).

    Between two predicates (literals or variables), ``a``'s own annotations must be a subset of
    ``b``'s (a plain variable has none, so ``X[a] = Y`` fails while ``Y = X[a]`` binds Y to X);
    then the values are unified; then an annotated variable bound to a literal is rebound to that
    literal without annotations: ``X[a] = p[a,b]`` gives ``X = p``, ``X[a|R] = p[a,b]`` gives
    ``R = [b]``. Against a number, string or list there is no annotation check.
    """
    ta, tb = type(a), type(b)
    if (ta in _PRED_LIKE and tb in _PRED_LIKE and ta is not Var
            and (a.annots or a.tail is not None)
            and (tb is Var or not _annots_subset(a.annots, a.tail, b.annots, b.tail, s, ag))):
        return False
    va = _value_of(a, s) if ta is AnnotVar else a
    vb = _value_of(b, s) if tb is AnnotVar else b
    if not unify(va, vb, s, ag):
        return False
    for t in (a, b):
        if type(t) is AnnotVar:
            v = _value_of(t, s)
            if type(v) is Literal and (v.annots or v.tail is not None):
                # rebind the variable the name ends at (Jason: deref, then bind)
                name = t.name
                while True:
                    nv = s.get(name)
                    if type(nv) is not Var:
                        break
                    name = nv.name
                s[name] = v.no_annots()
    return True


def _list_items(t: Any, s: Subst) -> tuple[list, Any]:
    """A list's items followed through bound tails, and the tail left (None, or a variable)."""
    return _items_and_tail(t.items, t.tail, s)


def _items_and_tail(first: tuple, tail: Any, s: Subst) -> tuple[list, Any]:
    items = list(first)
    while tail is not None:
        tail = walk(tail, s)
        if isinstance(tail, ListTerm):
            items.extend(tail.items)
            tail = tail.tail
        else:
            break
    return items, tail


def _unify_lists(a: ListTerm, b: ListTerm, s: Subst, ag: FunctionHost | None = None) -> bool:
    ia, ta = _list_items(a, s)
    ib, tb = _list_items(b, s)
    n = min(len(ia), len(ib))
    for i in range(n):
        if not unify(ia[i], ib[i], s, ag):
            return False
    ra, rb = ia[n:], ib[n:]
    if ra:
        # b ran out
        if tb is None:
            return False
        return unify(tb, ListTerm(tuple(ra), ta), s, ag)
    if rb:
        if ta is None:
            return False
        return unify(ta, ListTerm(tuple(rb), tb), s, ag)
    if ta is None and tb is None:
        return True
    if ta is None:
        return unify(tb, ListTerm(), s, ag)
    if tb is None:
        return unify(ta, ListTerm(), s, ag)
    return unify(ta, tb, s, ag)


def unify_annots(a: Literal, b: Literal, s: Subst, ag: FunctionHost | None = None) -> bool:
    """Greedy subset check (Jason ``hasSubsetAnnot``); a's tail gets b's unmatched annotations."""
    return _annots_subset(a.annots, a.tail, b.annots, b.tail, s, ag)


def _annots_subset(a_annots: tuple, a_tail: Any, b_annots: tuple, b_tail: Any, s: Subst,
                   ag: FunctionHost | None = None) -> bool:
    """:func:`unify_annots` for annotation lists (also those of annotated variables)."""
    pa, tail = _items_and_tail(a_annots, a_tail, s)
    pb, btail = _items_and_tail(b_annots, b_tail, s)
    remaining = list(pb)
    missing = []
    for x in pa:
        for i, y in enumerate(remaining):
            s2 = dict(s)
            if unify(x, y, s2, ag):
                s.clear()
                s.update(s2)
                del remaining[i]
                break
        else:
            if btail is None:
                return False
            missing.append(x)
    if missing:
        # b's annotation tail receives what a has and b does not list
        if not unify(btail, ListTerm(tuple(sorted(missing, key=sort_key))), s, ag):
            return False
        btail = None
    if tail is not None:
        rest = ListTerm(tuple(sorted(remaining, key=sort_key)), btail)
        return unify(tail, rest, s, ag)
    return True


def annot_options(a: Literal | AnnotVar, b: Literal, s: Subst, ag: FunctionHost | None = None):
    """All ways a's (tail-less) annotations can match annotations of b (for belief queries)."""
    pa = list(a.annots)
    pb = list(b.annots)

    def rec(i: int, cur: Subst):
        if i == len(pa):
            yield cur
            return
        for y in pb:
            s2 = dict(cur)
            if unify(pa[i], y, s2, ag):
                yield from rec(i + 1, s2)

    yield from rec(0, s)


# ---------------------------------------------------------------- equality (==)

def term_equals(a: Any, b: Any, s: Subst, ag: FunctionHost | None = None) -> bool:
    """Jason ``==``: structural equality after applying ``s`` (annotation order ignored)."""
    ra = resolve(a, s, ag)
    rb = resolve(b, s, ag)
    return _eq(ra, rb)


def _eq(a: Any, b: Any) -> bool:
    if type(a) is not type(b):
        # Jason VarTerm.equals: variables are equal when their names are (annotations ignored)
        return (isinstance(a, (Var, AnnotVar)) and isinstance(b, (Var, AnnotVar))
                and a.name == b.name)
    if type(a) is AnnotVar:
        return a.name == b.name
    if type(a) is NsLit:
        return _eq(a.ns, b.ns) and _eq(a.lit, b.lit)
    if isinstance(a, Literal):
        if a.functor != b.functor or a.neg != b.neg or len(a.args) != len(b.args):
            return False
        if not all(_eq(x, y) for x, y in zip(a.args, b.args, strict=False)):
            return False
        if len(a.annots) != len(b.annots):
            return False
        return all(any(_eq(x, y) for y in b.annots) for x in a.annots) and a.tail == b.tail
    if isinstance(a, ListTerm):
        return (len(a.items) == len(b.items)
                and all(_eq(x, y) for x, y in zip(a.items, b.items, strict=False))
                and _eq(a.tail, b.tail))
    return a == b


# ---------------------------------------------------------------- renaming

def rename_vars(t: Any, mapping: dict, renamed: Callable[[str], bool] | None = None) -> Any:
    """Copy ``t`` with each variable replaced by a fresh one (consistent through ``mapping``);
    with ``renamed``, only the variables whose name it accepts (the others stay)."""
    if isinstance(t, (float, str)):
        return t
    if isinstance(t, Var):
        v = mapping.get(t.name)
        if v is None:
            v = mapping[t.name] = (Var(fresh_name()) if renamed is None or renamed(t.name)
                                   else t)
        return v
    if isinstance(t, Literal):
        if not t.args and not t.annots and t.tail is None:
            return t
        return Literal(t.functor, tuple(rename_vars(a, mapping, renamed) for a in t.args),
                       tuple(rename_vars(a, mapping, renamed) for a in t.annots),
                       None if t.tail is None else rename_vars(t.tail, mapping, renamed), t.neg)
    if isinstance(t, ListTerm):
        return ListTerm(tuple(rename_vars(a, mapping, renamed) for a in t.items),
                        None if t.tail is None else rename_vars(t.tail, mapping, renamed))
    if isinstance(t, AnnotVar):
        v = mapping.get(t.name)
        if v is None:
            v = mapping[t.name] = (Var(fresh_name()) if renamed is None or renamed(t.name)
                                   else Var(t.name))
        return AnnotVar(v.name, tuple(rename_vars(a, mapping, renamed) for a in t.annots),
                        None if t.tail is None else rename_vars(t.tail, mapping, renamed))
    if isinstance(t, NsLit):
        return NsLit(rename_vars(t.ns, mapping, renamed), rename_vars(t.lit, mapping, renamed))
    if isinstance(t, (ArithExpr, LogExpr)):
        return type(t)(t.op, rename_vars(t.left, mapping, renamed),
                       None if t.right is None else rename_vars(t.right, mapping, renamed))
    if isinstance(t, RelExpr):
        return RelExpr(t.op, rename_vars(t.left, mapping, renamed), rename_vars(t.right, mapping, renamed))
    if isinstance(t, PlanTerm):
        return t.map_terms(lambda x: rename_vars(x, mapping, renamed))
    return t


def compare_terms(a: Any, b: Any) -> int:
    """Three-way comparison in Jason's term order (used by ``<``, ``>``, ``.sort``)."""
    if isinstance(a, float) and isinstance(b, float):
        return (a > b) - (a < b)
    ka, kb = sort_key(a), sort_key(b)
    return (ka > kb) - (ka < kb)
