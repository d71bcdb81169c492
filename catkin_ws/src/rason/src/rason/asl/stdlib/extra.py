"""More of Jason 3.3's standard library: logging, types, term copies, rules and plans listing,
agents created and killed at run time, files, scheduled goals (``.at``) and odd ends."""

from __future__ import annotations

import os
import re
from typing import Any

from ..containers import MapTerm, QueueTerm, SetTerm
from ..ia import IAContext, IAError, internal_action, wrong_arg
from ..kqml import KQML_SRC
from ..plans import ACHIEVE, ADD, BELIEF, PlanTerm, Trigger, plan_term_trigger
from ..terms import (
    LOCAL_NS_PREFIX,
    AnnotVar,
    ListTerm,
    Literal,
    NsLit,
    Rule,
    Var,
    is_ground,
    java_map_order,
    make_list,
    split_ns,
    term_str,
    to_print_str,
)
from ..unify import rename_vars, resolve, unify
from .core import info, print_text

TRUE_ATOM = Literal("true")
FALSE_ATOM = Literal("false")

#: ``.log`` levels shown (Jason's default console logging shows info and above)
_SHOWN_LEVELS = {"severe", "warning", "info"}


@internal_action(".log")
def log(ctx: IAContext, args: list) -> bool:
    """``.log(Level, Args...)``: the arguments as ``.print`` joins them, logged at Level
    (severe, warning, info are shown; fine, finer, finest are not)."""
    if not args:
        raise wrong_arg("a log level is expected")
    level = to_print_str(args[0])
    if level in _SHOWN_LEVELS and (level != "info" or ctx.ag.arch.verbose >= 1):
        text = print_text(ctx, args, 1)
        ctx.ag.console(text)   # Jason's console formatter does not name the level
    return True


def type_names(t: Any) -> list[str]:
    """The types of a term, from the most primitive (Jason's ``.type`` order)."""
    out = []
    if isinstance(t, float):
        out.append("number")
    if isinstance(t, Literal) and not t.args and not t.annots and not t.neg and t.tail is None:
        out.append("atom")
    if isinstance(t, Literal):
        out.append("literal")
    if isinstance(t, str):
        out.append("string")
    if isinstance(t, ListTerm):
        out.append("list")
    if isinstance(t, SetTerm):
        out.append("set")
    if isinstance(t, MapTerm):
        out.append("map")
    if isinstance(t, (Literal, ListTerm, PlanTerm)):
        out.append("structure")
    if isinstance(t, PlanTerm) and t.rule is not None:
        out.append("rule")
    if isinstance(t, PlanTerm) and t.rule is None:
        out.append("plan")
    if isinstance(t, QueueTerm):
        out.append("queue")
    if is_ground(t) and not isinstance(t, (Var, AnnotVar)):
        out.append("ground")
    if isinstance(t, (Var, AnnotVar)):
        out.append("free")
    return out


@internal_action(".type", arity=2)
def type_(ctx: IAContext, args: list) -> Any:
    """``.type(T, Type)``: checks, or enumerates, the types of T."""
    names = type_names(args[0])
    if not isinstance(args[1], (Var, AnnotVar)):
        return isinstance(args[1], Literal) and args[1].functor in names and not args[1].args

    def gen():
        for n in names:
            s2 = dict(ctx.s)
            if unify(args[1], Literal(n), s2):
                yield s2
    return gen()


@internal_action(".eval", arity=2)
def eval_(ctx: IAContext, args: list) -> bool:
    """``.eval(R, Formula)``: R is ``true`` when the formula holds, else ``false``."""
    ok = next(iter(ctx.solve(args[1])), None) is not None
    return ctx.unify(args[0], TRUE_ATOM if ok else FALSE_ATOM)


@internal_action(".copy_term", ".rename_apart", arity=2)
def copy_term(ctx: IAContext, args: list) -> bool:
    """``.copy_term(T, C)`` / ``.rename_apart(T, C)``: C is T with new variables."""
    return ctx.unify(args[1], rename_vars(args[0], {}))


@internal_action(".set_random_seed", arity=1)
def set_random_seed(ctx: IAContext, args: list) -> bool:
    if not isinstance(args[0], float):
        raise wrong_arg("the seed must be a number")
    ctx.ag.random.seed(int(args[0]))
    return True


@internal_action(".version", arity=1)
def version(ctx: IAContext, args: list) -> bool:
    """``.version(V)``: the Jason version whose language this interpreter follows."""
    return ctx.unify(args[0], "3.3.0 (rason)")


@internal_action(".verbose", arity=1)
def verbose(ctx: IAContext, args: list) -> bool:
    """``.verbose(N)``: the agent's ``verbose`` level from now on (see ``AgentArch.verbose``)."""
    if not isinstance(args[0], float) or args[0] != int(args[0]):
        raise wrong_arg("the level must be a whole number (0, 1 or 2)")
    ctx.ag.arch.verbose = int(args[0])
    return True


@internal_action(".print_unifier")
def print_unifier(ctx: IAContext, args: list) -> bool:
    items = ", ".join(f"{k}={term_str(resolve(v, ctx.s))}" for k, v in ctx.s.items()
                      if not k.startswith("_"))
    info(ctx, "{" + items + "}")
    return True


# ---------------------------------------------------------------- rules and plans
def _rule_term(r: Rule) -> PlanTerm:
    head = r.head.with_annots(tuple(a for a in r.head.annots
                                    if not (isinstance(a, Literal) and a.functor == "source")))
    rule = Rule(head, r.body)
    return PlanTerm((), str(rule), rule=rule)


@internal_action(".relevant_rules", arity=2)
def relevant_rules(ctx: IAContext, args: list) -> bool:
    """``.relevant_rules(Head, List)``: the rules whose head unifies with Head, as terms (a
    free Head: every rule, in the belief base's order, as Jason)."""
    pat = args[0]
    out = []
    if isinstance(pat, Var):
        out = [_rule_term(r) for r in ctx.ag.bb.rules()]
    elif isinstance(pat, Literal):
        for r in ctx.ag.bb.candidates(pat.key):
            if isinstance(r, Rule) and unify(pat, r.head, dict(ctx.s)):
                out.append(_rule_term(r))
    return ctx.unify(args[1], make_list(out))


@internal_action(".list_rules")
def list_rules(ctx: IAContext, args: list) -> bool:
    """``.list_rules`` prints every rule; ``.list_rules(Head)`` those whose head unifies."""
    for r in ctx.ag.bb.rules():
        if args and not (isinstance(args[0], Literal) and unify(args[0], r.head, dict(ctx.s))):
            continue
        info(ctx, str(_rule_term(r).rule) + ".")
    return True


@internal_action(".list_plans")
def list_plans(ctx: IAContext, args: list) -> bool:
    """``.list_plans(T)`` with a goal's trigger term (``{+!g(_)}``) prints, one message each,
    the plans whose trigger unifies with it; otherwise (no argument, or any other term) one
    message with every plan grouped by the file it came from, as Jason's
    ``PlanLibrary.getAsTxt``: ``// plans from FILE`` groups in the order of Java's hash map of
    the file names, then ``// plans without file`` (added or told), the KQML plans left out."""
    trig = _trigger_term(args[0]) if args else None
    if trig is None:
        info(ctx, plans_as_text(ctx.ag.pl.plans))
        return True
    pattern = trig.literal
    if isinstance(pattern, Literal) and not pattern.has_source():
        pattern = pattern.add_annots([Literal("source", (Var("_"),))])
    for p in ctx.ag.pl.plans:
        if p.src == KQML_SRC:
            continue
        if p.trigger.op == trig.op and p.trigger.type == trig.type \
                and unify(p.trigger.literal, pattern, {}):
            info(ctx, str(p))
    return True


def _trigger_term(t: Any) -> Trigger | None:
    """The trigger of a trigger term ``{+!g}`` (a plan term of a goal's trigger alone; Jason
    reads ``{+b}`` as a body adding ``b``), else None."""
    if not isinstance(t, PlanTerm) or t.plan is None:
        return None
    p = t.plan
    if p.label is not None or p.context is not None or p.body or p.goal_condition is not None \
            or p.trigger.type == BELIEF:
        return None
    return p.trigger


def plans_as_text(plans: list) -> str:
    """Jason's ``PlanLibrary.getAsTxt(false)`` of ``plans``: see :func:`list_plans`."""
    groups: dict[str, list[str]] = {}
    for p in plans:
        if p.src == KQML_SRC:
            continue
        groups.setdefault(p.src if p.in_file else "", []).append(str(p))

    def group_text(name: str) -> str:
        head = f"// plans from {name}" if name else "// plans without file"
        return "\n\n" + head + "\n\n" + "".join(line + "\n" for line in groups[name])
    files = [name for name in java_map_order(list(groups), str) if name]
    return ("".join(group_text(name) for name in files) + "\n"
            + (group_text("") if "" in groups else ""))


@internal_action(".relevant_plan", arity=2)
def relevant_plan(ctx: IAContext, args: list) -> Any:
    """``.relevant_plan(Trigger, Plan)``: backtracks over the plans relevant for Trigger."""
    trig = plan_term_trigger(args[0]) if isinstance(args[0], PlanTerm) else None
    if trig is None:
        raise wrong_arg("first argument must be a trigger term")

    def gen():
        for p in ctx.ag.pl.relevant(trig):
            if p.trigger.op != trig.op or p.trigger.type != trig.type:
                continue
            if not unify(p.trigger.literal, trig.literal, {}):
                continue
            s2 = dict(ctx.s)
            if unify(args[1], rename_vars(p.as_term(), {}), s2):
                yield s2
    return gen()


@internal_action(".get_src_info", arity=2)
def get_src_info(ctx: IAContext, args: list) -> bool:
    """``.get_src_info(Plan|Label, Info)``: ``[code_src(File), code_line(Line)]``."""
    p = None
    if isinstance(args[0], PlanTerm) and args[0].plan is not None:
        p = args[0].plan
    elif isinstance(args[0], Literal):
        p = next((q for q in ctx.ag.pl.plans if q.label_name() == args[0].functor), None)
    if p is None:
        return False
    info = [Literal("code_src", (p.src,)), Literal("code_line", (float(p.line),))]
    return ctx.unify(args[1], make_list(info))


# ---------------------------------------------------------------- events
@internal_action(".drop_event", arity=1)
def drop_event(ctx: IAContext, args: list) -> bool:
    """``.drop_event(G)``: removes the ``+!G`` events waiting to be handled."""
    pattern = args[0]
    ag = ctx.ag
    keep = [ev for ev in ag.circ.events if not (ev.trigger.op == ADD and ev.trigger.type == ACHIEVE
                                          and unify(pattern, ev.trigger.literal, dict(ctx.s)))]
    ag.circ.events.clear()
    ag.circ.events.extend(keep)
    return True


@internal_action(".perceive")
def perceive(ctx: IAContext, args: list) -> bool:
    """``.perceive``: perceive now (the next cycle perceives anyway)."""
    percepts = ctx.ag.arch.perceive()
    if percepts is not None:
        ctx.ag.update_percepts(percepts)
    return True


# ---------------------------------------------------------------- agents
def _runtime(ctx: IAContext) -> Any:
    rt = getattr(ctx.ag.arch, "create_agent", None)
    if rt is None:
        raise IAError("this agent's host cannot create or kill agents", "internal_action")
    return ctx.ag.arch


@internal_action(".create_agent", arity=(1, 3))
def create_agent(ctx: IAContext, args: list) -> bool:
    """``.create_agent(Name, Source[, Options])``: a new agent in the same host; a free Name
    gets the name the host chose."""
    arch = _runtime(ctx)
    name = args[0]
    wanted = None if isinstance(name, (Var, AnnotVar)) else to_print_str(name)
    source = to_print_str(args[1]) if len(args) > 1 else None
    try:
        made = arch.create_agent(ctx.ag, wanted, source)
    except (OSError, ValueError) as e:
        raise IAError(f"cannot create agent {wanted}: {e}", "internal_action") from None
    return ctx.unify(name, Literal(made)) if wanted is None else True


@internal_action(".kill_agent", arity=1)
def kill_agent(ctx: IAContext, args: list) -> bool:
    """``.kill_agent(Name)``: the agent stops and leaves the host."""
    return bool(_runtime(ctx).kill_agent(to_print_str(args[0])))


@internal_action(".clone", arity=1)
def clone(ctx: IAContext, args: list) -> bool:
    """``.clone(Name)``: a new agent with this agent's beliefs, plans and pending events (a host
    that cannot copy a mind starts the agent's program anew)."""
    arch = _runtime(ctx)
    try:
        if hasattr(arch, "clone_agent"):   # a copy of the mind, as Jason (LocalMas)
            arch.clone_agent(ctx.ag, to_print_str(args[0]))
            return True
        arch.create_agent(ctx.ag, to_print_str(args[0]), ctx.ag.filename)
    except (OSError, ValueError) as e:
        raise IAError(f"cannot clone to {to_print_str(args[0])}: {e}", "internal_action") from None
    return True


@internal_action(".save_agent", ".mind_inspector")
def not_here(ctx: IAContext, args: list) -> bool:
    raise IAError("not available in rason: the agent's state lives in the node "
                  "(see rosservice .../mind)", "internal_action")


# ---------------------------------------------------------------- files
@internal_action(".list_files", arity=(2, 3))
def list_files(ctx: IAContext, args: list) -> bool:
    """``.list_files(Folder, Pattern, Files)`` / ``.list_files(Folder, Files)``: the files under
    Folder (recursively) whose path matches the regular expression."""
    folder = to_print_str(args[0])
    pattern = to_print_str(args[1]) if len(args) == 3 else ".*"
    try:
        rx = re.compile(pattern)
    except re.error as e:
        raise wrong_arg(f"bad pattern {pattern}: {e}") from None
    found = []
    for root, dirs, files in os.walk(folder):
        dirs.sort()
        for f in sorted(files):
            path = os.path.join(root, f)
            if rx.fullmatch(f) or rx.fullmatch(path):
                found.append(path)
    return ctx.unify(args[-1], make_list(found))


# ---------------------------------------------------------------- .at
_AT_UNITS = {"ms": 1.0, "milliseconds": 1.0, "millisecond": 1.0, "s": 1000.0, "second": 1000.0,
             "seconds": 1000.0, "m": 60000.0, "minute": 60000.0, "minutes": 60000.0,
             "h": 3600000.0, "hour": 3600000.0, "hours": 3600000.0, "d": 86400000.0,
             "day": 86400000.0, "days": 86400000.0}
_AT_RX = re.compile(r"\s*now\s*\+\s*([0-9]+(?:\.[0-9]+)?)\s*([a-z]*)\s*$")


@internal_action(".at", arity=2)
def at(ctx: IAContext, args: list) -> bool:
    """``.at("now +N unit", {+!g})``: the event happens once, N units from now."""
    m = _AT_RX.match(to_print_str(args[0]))
    if m is None or (m.group(2) and m.group(2) not in _AT_UNITS):
        raise wrong_arg(f"'{to_print_str(args[0])}' is not a time like \"now +3 s\"")
    delay_ms = float(m.group(1)) * _AT_UNITS.get(m.group(2) or "ms", 1.0)
    trig = plan_term_trigger(args[1]) if isinstance(args[1], PlanTerm) else None
    if trig is None or not isinstance(trig.literal, Literal):
        raise wrong_arg("the second argument must be an event such as {+!g}")
    lit = trig.literal
    if trig.type == ACHIEVE or trig.type == BELIEF:
        lit = lit.with_self_source()
    ctx.ag.circ.schedule_event(Trigger(trig.op, trig.type, lit), delay_ms / 1000.0)
    return True


# ---------------------------------------------------------------- namespaces
@internal_action(".namespace", arity=1)
def namespace(ctx: IAContext, args: list) -> Any:
    """``.namespace(NS)``: NS is a namespace of this agent (enumerates them when free)."""

    def gen():
        for ns in ctx.ag.bb.namespaces():
            if ns.startswith(LOCAL_NS_PREFIX):   # a variable never takes a local namespace
                continue
            s2 = dict(ctx.s)
            if unify(args[0], Literal(ns), s2):
                yield s2
    return gen()


def _ns_props(ag: Any, ns: Any) -> dict:
    """The properties of a namespace (``.namespace_set_prop``), kept per agent."""
    return ag.namespace_props.setdefault(term_str(ns), {})


@internal_action(".namespace_set_prop", arity=3)
def namespace_set_prop(ctx: IAContext, args: list) -> bool:
    """``.namespace_set_prop(NS, Key, Value)``."""
    props = _ns_props(ctx.ag, args[0])
    props[term_str(args[1])] = (args[1], args[2])
    return True


@internal_action(".namespace_get_prop", arity=(2, 4))
def namespace_get_prop(ctx: IAContext, args: list) -> Any:
    """``.namespace_get_prop(NS, Key[, Value[, Default]])``: a free Key enumerates the keys
    (in the order of Jason's hash map of properties); a missing Key gives Default, and without
    one the action succeeds with Value left free (as Jason 3.3)."""
    props = _ns_props(ctx.ag, args[0])
    key = args[1]
    if not isinstance(key, (Var, AnnotVar)):
        entry = props.get(term_str(key))
        if entry is None:   # as Jason: a missing key takes the default, else succeeds as it is
            return len(args) < 4 or ctx.unify(args[2], args[3])
        return len(args) == 2 or ctx.unify(args[2], entry[1])

    def gen():
        for name in java_map_order(list(props), lambda k: k):
            k, v = props[name]
            s2 = dict(ctx.s)
            if unify(key, k, s2) and (len(args) == 2 or unify(args[2], v, s2)):
                yield s2
    return gen()


@internal_action(".belief", arity=1)
def belief(ctx: IAContext, args: list) -> Any:
    """``.belief(B)``: backtracks over the beliefs stored in the belief base that unify with B
    (rules are not used, except those whose body is ``true``)."""
    pattern = args[0]
    bb = ctx.ag.bb
    if isinstance(pattern, Literal):
        cands: Any = bb.candidates(pattern.key)
    elif isinstance(pattern, (Var, AnnotVar)):
        cands = list(bb)
    elif isinstance(pattern, NsLit):   # namespace by namespace, in Jason's order
        order = {ns: k for k, ns in enumerate(bb.namespaces())}
        cands = sorted(bb, key=lambda b: order.get(
            split_ns(b.head if isinstance(b, Rule) else b)[0], len(order)))
    else:
        raise wrong_arg("first argument must be a literal")

    def gen():
        for b in cands:
            if isinstance(b, Rule):
                if not (isinstance(b.body, Literal) and b.body.functor == "true" and not b.body.args):
                    continue
                if isinstance(pattern, Literal):
                    b = b.head
            s2 = dict(ctx.s)
            if unify(pattern, b, s2):
                yield s2
    return gen()


# ---------------------------------------------------------------- directory facilitator
def _directory(ctx: IAContext) -> Any:
    df = ctx.ag.arch.service_directory()
    if df is None:
        raise IAError("this agent's host has no directory facilitator", "internal_action")
    return df


def _service(args: list) -> str:
    """The service named by the first argument: a string's text, else the term's text."""
    if isinstance(args[0], (Var, AnnotVar)):
        raise wrong_arg("first argument must be a service (a string or a ground term)")
    return to_print_str(args[0])


@internal_action(".df_register", arity=(1, 2))
def df_register(ctx: IAContext, args: list) -> bool:
    """``.df_register(S[, Type])``: this agent provides service S (Type is not used to match,
    as in Jason's local infrastructure)."""
    _directory(ctx).register(ctx.ag.name, _service(args))
    return True


@internal_action(".df_deregister", arity=(1, 2))
def df_deregister(ctx: IAContext, args: list) -> bool:
    _directory(ctx).deregister(ctx.ag.name, _service(args))
    return True


@internal_action(".df_search", arity=(2, 3))
def df_search(ctx: IAContext, args: list) -> bool:
    """``.df_search(S[, Type], L)``: L lists the agents providing S."""
    names = _directory(ctx).search(_service(args), ctx.ag.arch.service_alive)
    return ctx.unify(args[-1], make_list([Literal(n) for n in names]))


@internal_action(".df_subscribe", arity=(1, 2))
def df_subscribe(ctx: IAContext, args: list) -> bool:
    """``.df_subscribe(S[, Type])``: ``df`` tells this agent ``provider(Agent, "S")`` for each
    provider of S, now and later."""
    _directory(ctx).subscribe(ctx.ag.name, _service(args))
    return True
