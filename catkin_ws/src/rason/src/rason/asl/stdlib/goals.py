"""Goal internal actions: ``.desire .intend .drop_desire .drop_intention .succeed_goal .fail_goal``."""

from __future__ import annotations

from typing import Any

from ..ia import SUSPEND, IAContext, IAError, internal_action, wrong_arg
from ..intentions import (
    Fork,
    ForkBranch,
    IntendedMeans,
    Intention,
    Suspension,
    has_goal,
    unifier_term,
)
from ..plans import ACHIEVE, ADD, BRANCH_JOIN, K_INTERNAL, Deed, Plan, Trigger, deed_str, map_deeds
from ..terms import Literal, PlanTerm, Var, java_map_order, make_list, term_str
from ..unify import rename_vars, resolve, unify


def im_term(im: Any, through: dict | None = None) -> Literal:
    """``im(Label, {Trigger}, {Body}, [map(Var, Value), ...])`` (Jason's IntendedMeans.getAsTerm):
    the label with ``code_src``/``code_line`` of the plan, the trigger as a trigger term, the
    deeds still to run as a plan-body term, the unifier as :func:`unifier_term` gives it."""
    plan = im.plan
    label = plan.label if isinstance(plan.label, Literal) else Literal("nolabel")
    label = label.add_annots([Literal("code_src", (plan.src,)), Literal("code_line", (float(plan.line),))])
    deeds = list(reversed(im.stack))
    if im.current is not None and (not deeds or deeds[0] is not im.current):
        deeds.insert(0, im.current)
    # Jason's makeVarsAnnon: the body's variables are fresh ones (the deed running this very
    # action may hold the variable the stack is unified with)
    mapping: dict = {}
    deeds = list(map_deeds(tuple(deeds), lambda t: rename_vars(t, mapping)))
    body = PlanTerm(tuple(deeds), "; ".join(deed_str(d) for d in deeds))
    trigger = im.trigger
    if through:
        trigger = Trigger(trigger.op, trigger.type, resolve(trigger.literal, through))
    trig = Plan(None, trigger, None, ()).as_term()
    return Literal("im", (label, trig, body, unifier_term(im.u, through=through)))


def intention_term(i: Any) -> Literal:
    """``intention(Id, [im(...) top first ...])`` (Jason's Intention.getAsTerm). The means of
    a goal that a failure plan above handles shows what that plan has bound so far in its
    goal's variables (the ``-!g`` event keeps them), as Jason's does."""
    ims = i.ims
    handling: dict[int, dict] = {}
    for im in ims:
        if im.fail_target is not None and im.is_failure_plan:
            handling.setdefault(im.fail_target, im.u)
    return Literal("intention", (float(i.id), make_list(
        [im_term(im, handling.get(k)) for k, im in reversed(list(enumerate(ims)))])))


def _intend_solutions(ctx: IAContext, pattern: Any, int_id: Any, with_suspended: bool):
    """jason.stdlib.intend.allIntentions: one solution per ``+!G`` intended means of each
    visited intention, top of its stack first (``int_id``: unified with the intention's
    number). An intention held by ``.suspend`` counts for ``.desire`` but not for ``.intend``."""
    for _place, i in ctx.ag.circ.places():
        if i.sus_ia and not with_suspended:
            continue
        for im in reversed(i.ims):
            t = im.trigger
            if t.op != ADD or t.type != ACHIEVE:
                continue
            s2 = dict(ctx.s)
            if unify(pattern, t.literal, s2) and (int_id is None or unify(int_id, float(i.id), s2)):
                yield s2


@internal_action(".intend", arity=(1, 2))
def intend(ctx: IAContext, args: list) -> Any:
    return _intend_solutions(ctx, args[0], args[1] if len(args) == 2 else None, False)


@internal_action(".desire", arity=(1, 2))
def desire(ctx: IAContext, args: list) -> Any:
    """jason.stdlib.desire: the selected event, the queued events (``+!g`` triggers), then
    every solution of ``.intend``."""
    pattern = args[0]
    ag = ctx.ag

    int_id = args[1] if len(args) == 2 else None

    def gen():
        evs = [ag.circ.selected_event] if ag.circ.selected_event is not None else []
        held = [ev for _, ev in java_map_order(ag.circ.pending_events, lambda kv: kv[0])]
        for ev in evs + list(ag.circ.events) + held:
            t = ev.trigger
            if t.op == ADD and t.type == ACHIEVE:
                s2 = dict(ctx.s)
                # (desire.testEvent: an event without intention answers whatever int_id is)
                if unify(pattern, t.literal, s2) and (
                        int_id is None or ev.intention is None or unify(int_id, float(ev.intention.id), s2)):
                    yield s2
        yield from _intend_solutions(ctx, pattern, int_id, True)
    return gen()


_STATE = {"SE": "running", "SI": "running", "E": "running", "I": "running",
          "PE": "suspended", "PA": "waiting"}


def _state_term(ag: Any, place: str, i: Intention, state: str) -> Literal:
    """An intention's state as Jason's ``.intention`` gives it: ``waiting`` carries what it
    waits for, ``[action(A)]`` (an environment action) or ``[reason(R)]`` (as ``.suspended``)."""
    if state != "waiting":
        return Literal(state)
    if place == "PA":
        act = next((pa.action for pa in ag.circ.pending_actions.values() if pa.intention is i), None)
        return Literal(state, (), (Literal("action", (act,)),)) if act is not None else Literal(state)
    return Literal(state, (), (Literal("reason", (_waiting_reason(i),)),))


def _waiting_reason(i: Intention) -> Any:
    """Why an intention pending in PI waits (Jason's suspended reason)."""
    if i.wait_reason is not None and i.suspended in (Suspension.WAIT, Suspension.EVENT_WAIT):
        return i.wait_reason
    if i.sus_ia and (i.pi_key or "").startswith("suspended-"):
        return Literal("suspend_ia")
    return Literal(i.suspended.value if i.suspended is not None else "no_reason")


@internal_action(".intention", arity=(2, 4))
def intention(ctx: IAContext, args: list) -> Any:
    """``.intention(Id, State[, Stack[, current]])`` (jason.stdlib.intention): states as
    ``Intention.getStateBasedOnPlace`` (running, waiting, suspended)."""
    ag = ctx.ag
    if len(args) == 4 and term_str(args[3]) == "current":
        i = ag.circ.current
        if i is None and ag.circ.selected_event is not None:
            i = ag.circ.selected_event.intention
        if i is None:
            return False
        s2 = dict(ctx.s)
        ok = (unify(args[0], float(i.id), s2) and unify(args[1], Literal("running"), s2)
              and unify(args[2], intention_term(i).args[1], s2))
        return s2 if ok else False

    def gen():
        for place, i in ag.circ.places():
            state = ("suspended" if i.sus_ia else "waiting") if place == "PI" else _STATE[place]
            s2 = dict(ctx.s)
            if not (unify(args[0], float(i.id), s2) and unify(args[1], _state_term(ag, place, i, state), s2)):
                continue
            if len(args) >= 3 and not unify(args[2], intention_term(i).args[1], s2):
                continue
            yield s2
    return gen()


@internal_action(".current_intention", arity=1)
def current_intention(ctx: IAContext, args: list) -> bool:
    """``.current_intention(I)``: ``intention(Id, [im(...)...])`` of the running intention;
    deprecated in Jason 3, which warns at every call, as here."""
    ctx.ag.warn(".current_intention( intention(I,S) ) was replaced by .intention(I,_,S,current)")
    i = ctx.intention
    if i is None:
        return False
    return ctx.unify(args[0], intention_term(i))


@internal_action(".drop_desire", arity=1)
def drop_desire(ctx: IAContext, args: list) -> bool:
    ctx.ag.goals.drop_goal(args[0], ctx.s, drop_events=True)
    return True


@internal_action(".drop_intention", arity=(0, 1))
def drop_intention(ctx: IAContext, args: list) -> bool:
    if not args:
        if ctx.intention is not None:
            ctx.ag.circ.remove_intention(ctx.intention)
        return True
    ctx.ag.goals.drop_goal(args[0], ctx.s, drop_events=False)
    return True


@internal_action(".drop_all_desires", arity=0)
def drop_all_desires(ctx: IAContext, args: list) -> bool:
    """Drop every event and intention but the current one (jason.stdlib.drop_all_desires)."""
    ctx.ag.goals.drop_all(events=True, keep=ctx.intention)
    return True


@internal_action(".drop_all_intentions", arity=0)
def drop_all_intentions(ctx: IAContext, args: list) -> bool:
    """Drop every intention (and its events) but the current one (jason.stdlib.drop_all_intentions)."""
    ctx.ag.goals.drop_all(events=False, keep=ctx.intention)
    return True


@internal_action(".drop_all_events")
def drop_all_events(ctx: IAContext, args: list) -> bool:
    ctx.ag.circ.events.clear()
    return True


@internal_action(".suspend", arity=(0, 1))
def suspend(ctx: IAContext, args: list) -> Any:
    """``.suspend(G)`` / ``.suspend`` (the current intention), jason.stdlib.suspend."""
    ag = ctx.ag
    if not args:
        i = ctx.intention
        if i is None:
            return False
        ag.circ.suspend(i, Suspension.SUSPENDED)
        i.sus_ia = True
        i.pi_key = f"suspended-self-{i.id}"
        return SUSPEND
    if not isinstance(args[0], Literal):
        raise wrong_arg("first argument must be a literal")
    own, ctx.s = ag.goals.suspend_goal(args[0], ctx.s, ctx.intention)
    return SUSPEND if own else True


@internal_action(".resume", arity=1)
def resume(ctx: IAContext, args: list) -> bool:
    """``.resume(G)``, jason.stdlib.resume."""
    if not isinstance(args[0], Literal):
        raise wrong_arg("first argument must be a literal")
    ctx.s = ctx.ag.goals.resume_goal(args[0], ctx.s)
    return True


@internal_action(".suspended", arity=2)
def suspended(ctx: IAContext, args: list) -> Any:
    """``.suspended(G, R)`` (jason.stdlib.suspended): G is a goal of an intention waiting for
    an action (R = ``act``) or pending in PI (R = its reason: ``suspend_ia`` for ``.suspend``)."""
    if not isinstance(args[0], Literal):
        raise wrong_arg("first argument must be a literal")
    for place, i in ctx.ag.circ.places():
        if place not in ("PA", "PI"):
            continue
        s2 = has_goal(i, args[0], ctx.s)
        if s2 is None:
            continue
        reason = Literal("act") if place == "PA" else _waiting_reason(i)
        return s2 if unify(args[1], reason, s2) else False
    return False


@internal_action(".succeed_goal", arity=1)
def succeed_goal(ctx: IAContext, args: list) -> bool:
    ctx.ag.goals.succeed_goal(args[0], ctx.s)
    return True


@internal_action(".fail_goal", arity=1)
def fail_goal(ctx: IAContext, args: list) -> bool:
    ctx.ag.goals.fail_goal(args[0], ctx.s)
    return True


@internal_action(".fork", arity=(2, None))
def fork(ctx: IAContext, args: list) -> Any:
    """``.fork(and|or, {Body1}, {Body2}, ...)`` (what Jason's ``|&|``/``|||`` become): each body
    runs in an intention of its own that carries on with the rest of the current plan after a
    ``.join``; the current intention stops here. ``and`` goes on when every branch has joined
    (with the last one's bindings), ``or`` with the first one (the others are dropped)."""
    kind = args[0]
    if not (isinstance(kind, Literal) and not kind.args and kind.functor in ("and", "or")):
        raise wrong_arg("first argument must be 'and' or 'or'.")
    bodies = []
    for b in args[1:]:
        if not (isinstance(b, PlanTerm) and b.plan is None and b.rule is None):
            raise wrong_arg("the branches must be plan bodies ({ ... })")
        bodies.append(b)
    ag, cur, im = ctx.ag, ctx.intention, ctx.im
    if cur is None or im is None:
        raise IAError("'.fork' runs only in a plan body")
    fk = Fork(kind.functor == "and")
    point = len(cur.ims)
    for body in bodies:
        i = Intention(next(ag.circ.intention_ids))
        i.reply = cur.reply
        i.ims = list(cur.ims[:-1])        # the means below are shared, as in Jason
        top = IntendedMeans(im.plan, im.trigger, dict(ctx.s), im.fail_target)
        top.result, top.open_call = im.result, im.open_call
        top.stack = list(im.stack)
        top.stack.append(Deed(K_INTERNAL, Literal(".join", (ForkTerm(fk),)), ctx.deed.line))
        top.stack.extend(reversed(body.body))
        i.ims.append(top)
        i.atomic_count = cur.atomic_count
        i.fork = ForkBranch(fk, point)
        fk.branches.append(i)
        fk.to_finish += 1
        ag.circ.running.append(i)
    cur.ims.clear()        # the forked intention itself ends: its branches go on for it
    return SUSPEND


@internal_action(".join")
def join(ctx: IAContext, args: list) -> Any:
    """Put by ``.fork`` after each branch: ``and`` waits for every branch, ``or`` goes on with
    the first branch and drops the others."""
    if len(args) != 1 or not isinstance(args[0], ForkTerm):
        raise wrong_arg("'.join' only closes the branches of a '.fork'")
    fk = args[0].fork
    fk.to_finish -= 1
    if fk.is_and:
        return True if fk.to_finish <= 0 else SUSPEND
    for other in fk.branches:
        if other is not ctx.intention:
            ctx.ag.circ.remove_intention(other)
    fk.branches = [ctx.intention]
    return True


class ForkTerm:
    """The argument of the ``.join`` put by ``.fork`` (Jason's ObjectTerm of its fork data)."""

    __slots__ = ("fork",)

    def __init__(self, fork: Fork) -> None:
        self.fork = fork

    def __str__(self) -> str:
        return str(self.fork)


@internal_action(".done", arity=(0, 1))
def done(ctx: IAContext, args: list) -> Any:
    """``.done`` / ``.done(G)`` (Jason 3.3): the goal of the current means (or of the event
    whose plan it runs), or the goal G, is achieved now: its means and those above it go and
    its caller goes on after it; the branches of the intention (``reasoning.branch_for_update``)
    go too. In a branch, ``.done`` means the goal of the means under the branch's join and
    ends it in the intention the branch copies, which goes on; the branch ends. As in Jason,
    when the current intention has no such goal, it stays suspended."""
    if args and not isinstance(args[0], (Literal, Var)):
        raise wrong_arg("first argument must be a literal")
    ag, i, im = ctx.ag, ctx.intention, ctx.im
    if i is None or im is None:
        raise IAError("'.done' runs only in a plan body")
    if args:
        goal = Trigger(ADD, ACHIEVE, args[0])
    elif i.branch_of is not None:
        goal = _under_join(i).trigger
    else:
        goal = im.trigger
    idx = _means_of(ag, i, goal, ctx.s)
    if idx is None:
        return SUSPEND
    if i.branch_of is not None:
        ag.circ.remove_intention(i)
        copied = i.branch_of
        at = None if copied.dropped else _means_of(ag, copied, goal, ctx.s)
        if at is not None:
            ag.goals.succeed_at(copied, at)
        return True
    if ag.pl.goal_state_plans:
        ag.circ.goal_state(i.ims[idx].trigger, "achieved")
        ag.circ.goal_state(i.ims[idx].trigger, "finished")
    i.truncate(idx)
    if i.ims and i.ims[-1].stack:
        i.ims[-1].stack.pop()     # the deed that posted the goal
    ag.goals.drop_branches(i)
    return True


def _under_join(branch: Intention) -> IntendedMeans:
    """The means of a branch just under its join (the top of the intention it copies)."""
    for k in range(len(branch.ims) - 1, 0, -1):
        if branch.ims[k].plan is BRANCH_JOIN:
            return branch.ims[k - 1]
    raise IAError("a branch without its join")


def _means_of(ag: Any, i: Intention, goal: Trigger, s: dict) -> int | None:
    """The index of the topmost means of ``i`` whose trigger ``goal`` unifies with, or None."""
    for idx in range(len(i.ims) - 1, -1, -1):
        t = i.ims[idx].trigger
        if t.op == goal.op and t.type == goal.type and unify(goal.literal, t.literal, dict(s), ag):
            return idx
    return None
