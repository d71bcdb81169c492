"""Core internal actions: printing, time, type checks, belief base, plans, findall."""

from __future__ import annotations

import copy
import re
from typing import Any

from ..ia import SUSPEND, FailGoal, IAContext, IAError, internal_action, wrong_arg
from ..parser import AslSyntaxError, parse_source, parse_term
from ..plans import ANON_LABEL, Plan, PlanTerm, Trigger, plan_term_trigger
from ..terms import (
    AnnotVar,
    ListTerm,
    Literal,
    NsLit,
    Var,
    fresh_name,
    is_ground,
    java_double_str,
    java_map_order,
    list_to_python,
    make_list,
    merge_annots,
    sort_key,
    term_str,
    to_print_str,
)
from ..unify import eval_arith, rename_vars, resolve, unify


# ---------------------------------------------------------------- console
def print_text(ctx: IAContext, args: list, first: int = 0) -> str:
    """The arguments from ``first`` on as Jason's ``.print`` joins them: strings without quotes,
    a free variable as its name (as written in the action) with ``<no-value>``."""
    written = ctx.deed.term.args if ctx.deed is not None and isinstance(ctx.deed.term, Literal) else ()
    out = []
    for k in range(first, len(args)):
        a = args[k]
        if isinstance(a, (Var, AnnotVar)):
            raw = written[k] if k < len(written) else a
            out.append(term_str(raw if isinstance(raw, (Var, AnnotVar)) else a) + "<no-value>")
        else:
            out.append(to_print_str(a))
    return "".join(out)


def info(ctx: IAContext, text: str) -> None:
    """An agent's message (Jason's logger at level info): shown unless ``verbose=0``."""
    if ctx.ag.arch.verbose >= 1:
        ctx.ag.console(text)


def _say(ctx: IAContext, text: str, newline: str) -> None:
    """What ``.print``, ``.println`` and ``.printf`` show: an agent's message, or with
    ``verbose=0`` the bare text followed by ``newline`` (Jason writes to System.out then)."""
    arch = ctx.ag.arch
    if arch.verbose >= 1:
        ctx.ag.console(text)
    else:
        arch.output(text + newline)


@internal_action(".print")
def print_(ctx: IAContext, args: list) -> bool:
    """Concatenate the arguments (strings without quotes) and print them."""
    _say(ctx, print_text(ctx, args), "")
    return True


@internal_action(".println")
def println(ctx: IAContext, args: list) -> bool:
    """``.print`` that ends its line when ``verbose=0`` too."""
    _say(ctx, print_text(ctx, args), "\n")
    return True


_PUTS_VAR = re.compile(r"#\{([A-Za-z0-9_]+)\}")


@internal_action(".puts", arity=(1, 2))
def puts(ctx: IAContext, args: list) -> bool:
    """``.puts(S[, R])`` (jason.stdlib.puts): each ``#{T}`` (T a name, number or variable) is
    replaced by T's value; the string arguments are joined; a variable last argument gets the
    text, else it is printed."""
    if not isinstance(args[0], str):
        raise wrong_arg("first argument must be a string")

    def rep(m: Any) -> str:
        try:
            t = resolve(parse_term(m.group(1)), ctx.s, ctx.ag)
        except AslSyntaxError:
            return m.group(0)
        return to_print_str(t)
    text = "".join(_PUTS_VAR.sub(rep, a) for a in args if isinstance(a, str))
    if isinstance(args[-1], Var):
        return ctx.unify(text, args[-1])
    info(ctx, text)
    return True


_JAVA_FORMAT = re.compile(r"%(\d+\$)?([-#+ 0,(]*)(\d+)?(\.\d+)?([a-zA-Z%])")


@internal_action(".printf")
def printf(ctx: IAContext, args: list) -> bool:
    """``.printf(Format, Args...)`` (jason.stdlib.printf): Java's ``String.format``; every number
    is a Double, so ``%d`` is an error."""
    if not args:
        raise IAError("The internal action 'printf' has not received the required number of "
                      "argument(s).", "wrong_arguments")
    if not isinstance(args[0], str):
        raise wrong_arg("first argument must be a string (the format)")
    values = [a.functor if isinstance(a, Literal) and not a.args and not a.annots and not a.neg
              else a for a in args[1:]]
    nxt = 0

    def conv(m: Any) -> str:
        nonlocal nxt
        index, flags, width, prec, c = m.groups()
        if c == "%":
            return "%"
        if c == "n":
            return "\n"
        if index:
            v = values[int(index[:-1]) - 1]
        else:
            if nxt >= len(values):
                raise IAError(f"Format specifier '{m.group(0)}'", "ia_failed")
            v = values[nxt]
            nxt += 1
        spec = "%" + flags + (width or "") + (prec or "")
        if c in "sS":
            text = (java_double_str(v) if isinstance(v, float) else v if isinstance(v, str)
                    else term_str(v))
            out = (spec + "s") % text
            return out.upper() if c == "S" else out
        if c in "feE" and isinstance(v, float):
            return (spec + c) % v
        java_type = "java.lang.Double" if isinstance(v, float) else "java.lang.String"
        raise IAError(f"{c} != {java_type}", "ia_failed")
    _say(ctx, _JAVA_FORMAT.sub(conv, args[0]), "\n")
    return True


# ---------------------------------------------------------------- failure
@internal_action(".fail")
def fail(ctx: IAContext, args: list) -> bool:
    """Fail the intention; the arguments become annotations of the failure event."""
    raise FailGoal(list(args))


# ---------------------------------------------------------------- identity
@internal_action(".my_name", arity=1)
def my_name(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[0], Literal(ctx.ag.name))


@internal_action(".all_names", arity=1)
def all_names(ctx: IAContext, args: list) -> bool:
    """``.all_names(L)``: the agents' names in the order Jason's local infrastructure gives
    them (that of its ``ConcurrentHashMap`` of agents by name)."""
    names = java_map_order(ctx.ag.arch.agent_names() or [ctx.ag.name], str)
    return ctx.unify(args[0], make_list([Literal(n) for n in names]))


# ---------------------------------------------------------------- time
@internal_action(".wait", arity=(1, 3))
def wait(ctx: IAContext, args: list) -> Any:
    """``.wait(ms)``, ``.wait({+b})``, ``.wait({+b}, ms)``, ``.wait(cond)``, ``.wait(cond, ms)``."""
    ag = ctx.ag
    if ctx.intention is None:
        raise IAError(".wait outside an intention")
    first = args[0]
    clock = ag.arch.clock
    # as Jason, a time is whole milliseconds (a fraction cut off) and a negative one sets no
    # timer (.wait(-1) waits for ever)
    if isinstance(first, float):
        ms = int(first)
        ag.circ.suspend_timer(ctx.intention, clock.now() + ms / 1000.0 if ms >= 0 else None, ms)
        return SUSPEND
    timeout = None
    if len(args) >= 2 and isinstance(args[1], float) and int(args[1]) >= 0:
        timeout = clock.now() + int(args[1]) / 1000.0
    # a third argument gets the time waited; then a timeout does not fail the intention
    ctx.intention.wait_elapsed = (args[2], clock.now()) if len(args) == 3 else None
    if isinstance(first, PlanTerm):
        trig = plan_term_trigger(first)
        if trig is None:
            raise IAError(f"invalid event in .wait: {term_str(first)}")
        ag.circ.suspend_event_wait(ctx.intention, trig, None, timeout)
        return SUSPEND
    if isinstance(first, str):
        try:
            t = parse_term("{" + first + "}")
        except AslSyntaxError:
            raise IAError(f"invalid event in .wait: {first}") from None
        trig = plan_term_trigger(t) if isinstance(t, PlanTerm) else None
        if trig is not None:
            ag.circ.suspend_event_wait(ctx.intention, trig, None, timeout)
            return SUSPEND
    # logical condition
    for sol in ctx.solve(first):
        ctx.s = sol
        return True
    ag.circ.suspend_event_wait(ctx.intention, None, first, timeout)
    return SUSPEND


@internal_action(".time")
def time_(ctx: IAContext, args: list) -> bool:
    """``.time(H, M, S[, MS])`` wall time; ``.time(T)``: milliseconds from the agent's clock."""
    if len(args) == 1:
        return ctx.unify(args[0], ctx.ag.clock_millis())
    import datetime  # (here: few agents ask the date, every agent starts)

    now = datetime.datetime.now()
    vals = [now.hour, now.minute, now.second, now.microsecond // 1000]
    return all(ctx.unify(a, float(v)) for a, v in zip(args, vals, strict=False))


@internal_action(".nano_time", arity=1)
def nano_time(ctx: IAContext, args: list) -> bool:
    """``.nano_time(T)``: nanoseconds from the agent's clock (for measuring short intervals)."""
    return ctx.unify(args[0], float(ctx.ag.arch.clock.now_ns()))


@internal_action(".date")
def date(ctx: IAContext, args: list) -> bool:
    import datetime

    now = datetime.date.today()
    return all(ctx.unify(a, float(v)) for a, v in zip(args, [now.year, now.month, now.day], strict=False))


@internal_action(".random", arity=(1, 3))
def random_(ctx: IAContext, args: list) -> Any:
    """``.random(R)``: R in [0,1); ``.random(R, N)``: N such numbers one after another on
    backtracking (N = 0: without end); ``.random(L, X[, N])``: a random member of list L."""
    rnd = ctx.ag.random
    if len(args) == 1:
        return ctx.unify(args[0], rnd.random())
    items = list_to_python(args[0])
    if isinstance(args[0], ListTerm):
        if not items:
            return False
        count = int(eval_arith(args[2], ctx.s)) if len(args) == 3 else 1
        target, draw = args[1], (lambda: rnd.choice(items))
    else:
        count = int(eval_arith(args[1], ctx.s))
        target, draw = args[0], rnd.random

    def gen():
        n = 0
        while n < count or count == 0:
            n += 1
            s2 = dict(ctx.s)
            if unify(target, draw(), s2):
                yield s2
    return gen()


@internal_action(".range", arity=(3, 4))
def range_(ctx: IAContext, args: list) -> Any:
    """``.range(V, Start, End[, Step])`` enumerates numbers (nothing when Start > End)."""
    start = eval_arith(args[1], ctx.s, ctx.ag)
    end = eval_arith(args[2], ctx.s, ctx.ag)
    step = eval_arith(args[3], ctx.s, ctx.ag) if len(args) == 4 else 1.0
    if step == 0:
        raise IAError("step 0 in .range")

    def gen():
        v = start
        while (v <= end) if step > 0 else (v >= end):
            s2 = dict(ctx.s)
            if unify(args[0], v, s2):
                yield s2
            v += step
    return gen()


# ---------------------------------------------------------------- type checks
def _type_check(pred):
    def fn(ctx: IAContext, args: list) -> bool:
        return pred(args[0])
    return fn


internal_action(".string", arity=1)(_type_check(lambda t: isinstance(t, str)))
internal_action(".number", arity=1)(_type_check(lambda t: isinstance(t, float)))
internal_action(".list", arity=1)(_type_check(lambda t: isinstance(t, ListTerm)))
internal_action(".atom", arity=1)(_type_check(
    lambda t: isinstance(t, Literal) and not t.args and not t.annots and not t.neg))
internal_action(".structure", arity=1)(_type_check(lambda t: isinstance(t, (Literal, ListTerm))))
internal_action(".literal", arity=1)(_type_check(lambda t: isinstance(t, Literal)))
internal_action(".ground", arity=1)(_type_check(is_ground))


@internal_action(".term2string", arity=2)
def term2string(ctx: IAContext, args: list) -> bool:
    """``.term2string(T, S)``: S is T's text, or T the term parsed from S (jason.stdlib.term2string)."""
    t, s = args
    if not isinstance(t, Var):
        return ctx.unify(s, term_str(t))
    if isinstance(s, str):
        try:
            return ctx.unify(t, parse_term(s))
        except AslSyntaxError:
            return False
    raise IAError("invalid case of term2string", "internal_action")


# ---------------------------------------------------------------- belief base
def _as_literal(t: Any) -> Literal:
    if not isinstance(t, Literal):
        raise IAError(f"not a literal: {term_str(t)}")
    return t


@internal_action(".abolish", arity=1)
def abolish(ctx: IAContext, args: list) -> bool:
    t = args[0]
    if not isinstance(t, (Literal, AnnotVar, Var, NsLit)):
        raise IAError(f"not a literal: {term_str(t)}")
    ctx.ag.abolish(t, ctx.s)
    return True


@internal_action(".asserta", arity=1)
def asserta(ctx: IAContext, args: list) -> bool:
    ctx.ag.add_belief(_as_literal(args[0]).with_self_source(), front=True)
    return True


@internal_action(".assertz", arity=1)
def assertz(ctx: IAContext, args: list) -> bool:
    ctx.ag.add_belief(_as_literal(args[0]).with_self_source(), front=False)
    return True


@internal_action(".findall", arity=3)
def findall(ctx: IAContext, args: list) -> bool:
    """``.findall(Template, Query, List)``."""
    res = [resolve(args[0], sol, ctx.ag) for sol in ctx.solve(args[1])]
    return ctx.unify(args[2], make_list(res))


@internal_action(".setof", arity=3)
def setof(ctx: IAContext, args: list) -> bool:
    res: list = []
    for sol in ctx.solve(args[1]):
        v = resolve(args[0], sol, ctx.ag)
        if v not in res:
            res.append(v)
    res.sort(key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".count", arity=2)
def count(ctx: IAContext, args: list) -> bool:
    n = sum(1 for _ in ctx.solve(args[0]))
    return ctx.unify(args[1], float(n))


@internal_action(".remove_plan", arity=(1, 2))
def remove_plan(ctx: IAContext, args: list) -> bool:
    """``.remove_plan(Label(s)[, Source])`` (jason.stdlib.remove_plan, PlanLibrary.remove): the
    source (``self`` by default) leaves the plan's label; a plan left without sources goes."""
    labels = list_to_python(args[0]) if isinstance(args[0], ListTerm) else [args[0]]
    src = args[1] if len(args) > 1 else SELF_ATOM
    pl = ctx.ag.pl
    for lab in labels or []:
        name = lab.functor if isinstance(lab, Literal) else to_print_str(lab)
        for k, p in enumerate(pl.plans):
            if p.label_name() != name:
                continue
            sources = _label_sources(p.label)
            if src in sources:
                sources.remove(src)
                if not sources:
                    pl.remove_by_label(name)
                else:
                    pl.replace(k, _with_label_sources(p, sources))
            break
    return True


SELF_ATOM = Literal("self")


def _label_sources(label: Literal | Var | None) -> list:
    """The sources of a plan's label (a label without one is the agent's own: ``self``)."""
    if not isinstance(label, Literal):
        return [SELF_ATOM]
    out = [a.args[0] for a in label.annots
           if isinstance(a, Literal) and a.functor == "source" and len(a.args) == 1]
    return out or [SELF_ATOM]


def _with_label_sources(p: Plan, sources: list) -> Plan:
    """``p`` (its goal condition and sub-plans too) with exactly these label sources; an
    unlabelled plan gets an anonymous label, named when the library adds it."""
    old = p.label if isinstance(p.label, Literal) else Literal(ANON_LABEL)
    rest = tuple(a for a in old.annots if not (isinstance(a, Literal) and a.functor == "source"))
    srcs = [Literal("source", (s,)) for s in sources]
    made = copy.copy(p)
    made.label = Literal(old.functor, old.args, merge_annots(rest, srcs))
    return made


@internal_action(".stopMAS", arity=(0, 2))
def stop_mas(ctx: IAContext, args: list) -> bool:
    """``.stopMAS``: stop every agent; ``.stopMAS(T)``: every agent gets ``+jag_shutting_down(T)``
    and the system stops T milliseconds later (on a host that can delay it, LocalMas)."""
    ms = args[0] if args else 0.0
    if not isinstance(ms, float):
        raise wrong_arg("the first argument of .stopMAS must be a number of milliseconds")
    stop_later = getattr(ctx.ag.arch, "stop_mas", None)
    if ms > 0 and stop_later is not None:
        stop_later(ms)
        return True
    ctx.ag.request_stop()
    return True


# ---------------------------------------------------------------- plans
def _to_plan(t: Any) -> Any:
    """jason.stdlib.add_plan.transform2plan: a plan term, or a string holding one plan."""
    if isinstance(t, str):
        try:
            src = parse_source(t.replace("\\", ""), "<plan>")
        except AslSyntaxError as e:
            raise IAError(str(e), "internal_action") from None
        if len(src.plans) != 1:
            raise IAError(f"not a plan: {t}", "internal_action")
        made = copy.copy(src.plans[0])
        made.in_file = False     # as Jason's: a plan read from a string names no file
        return made
    if isinstance(t, PlanTerm) and t.plan is not None:
        return t.plan
    raise wrong_arg(f"The term '{term_str(t)}' ({type(t).__name__}) can not be used as a plan for .add_plan.")


@internal_action(".add_plan", arity=(1, 3))
def add_plan(ctx: IAContext, args: list) -> bool:
    """``.add_plan(P[, Source[, begin|end]])``: P a plan term, a string or a list of them; a plan
    equal to one already in the library (same trigger, context and body) is not added again."""
    front = len(args) > 2 and term_str(args[2]) == "begin"
    items = list_to_python(args[0]) if isinstance(args[0], ListTerm) else [args[0]]
    pl = ctx.ag.pl
    src = args[1] if len(args) > 1 else SELF_ATOM
    for t in items or []:
        p = _to_plan(t)
        same = next((k for k, q in enumerate(pl.plans) if _same_plan(p, q)), None)
        if same is not None:
            # PlanLibrary.add: the plan is known, its label gets the new source
            q = pl.plans[same]
            if q.label is not None and src not in _label_sources(q.label):
                pl.replace(same, _with_label_sources(q, [*_label_sources(q.label), src]))
            continue
        if src != SELF_ATOM:
            p = _with_label_sources(p, [src])
        pl.add(p, front=front)
    return True


def _same_plan(p: Plan, q: Plan) -> bool:
    """Same trigger, context and body (labels aside): ``.add_plan`` does not add it twice."""
    def key(x: Plan) -> tuple:
        return (str(x.trigger), "" if x.context is None else term_str(x.context), x.body_text())
    return key(p) == key(q)


def _trigger_of(t: Any) -> Any:
    if isinstance(t, PlanTerm):
        trig = plan_term_trigger(t)
        if trig is not None:
            return trig
    if isinstance(t, str):
        try:
            src = parse_source(t + ".", "<trigger>")
            if len(src.plans) == 1:
                return src.plans[0].trigger
        except AslSyntaxError:
            pass
    raise wrong_arg(f"first argument '{term_str(t)}' must follow the syntax of a trigger.")


@internal_action(".relevant_plans", arity=(2, 3))
def relevant_plans(ctx: IAContext, args: list) -> bool:
    """``.relevant_plans(Trigger, Plans[, Labels])`` (jason.stdlib.relevant_plans): the plans
    whose trigger unifies with Trigger, as plan terms, labels without their sources."""
    te = _trigger_of(args[0])
    plans, labels = [], []
    lit = te.literal
    if isinstance(lit, Literal) and not lit.has_source():
        # as Jason: a trigger without source gets an anonymous one (so [source(A)] plans match)
        lit = lit.add_annots([Literal("source", (Var(fresh_name()),))])
    for p in ctx.ag.pl.relevant(te):
        if p.trigger.op != te.op or p.trigger.type != te.type or not unify(p.trigger.literal, lit, {}):
            continue
        label = p.label
        q = Plan(label, Trigger(p.trigger.op, p.trigger.type, p.trigger.literal), p.context, p.body,
                 p.line, p.src, in_file=p.in_file)
        plans.append(rename_vars(q.as_term(), {}))  # fresh variables, as Jason's clone
        labels.append(label if label is not None else Literal("nolabel"))
    if not ctx.unify(make_list(plans), args[1]):
        return False
    return len(args) < 3 or ctx.unify(make_list(labels), args[2])


@internal_action(".plan_label", arity=2)
def plan_label(ctx: IAContext, args: list) -> bool:
    """``.plan_label(P, L)``: P is the plan (as a term) whose label is L."""
    if isinstance(args[1], (Var, AnnotVar)) and isinstance(args[0], PlanTerm) and args[0].plan is not None:
        label = args[0].plan.label    # the label of the plan term as written
        return label is not None and ctx.unify(args[1], label)
    name = args[1].functor if isinstance(args[1], Literal) else to_print_str(args[1])
    for p in ctx.ag.pl.plans:
        if isinstance(p.label, Literal) and p.label.functor == name:
            # the library's labels carry their source (PlanLibrary.add), which plan_label keeps
            q = Plan(p.label.with_self_source(), p.trigger, p.context, p.body, p.line, p.src,
                     in_file=p.in_file)
            return ctx.unify(rename_vars(q.as_term(), {}), args[0])
    return False
