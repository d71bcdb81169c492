"""The reasoning cycle (Jason's ``TransitionSystem``), one function per step.

``reasoning_cycle`` = sense (perceive, mail, action feedback, timers)
-> deliberate (SelEv, RelPl, ApplPl, SelAppl, AddIM for every pending event)
-> act (SelInt, ExecInt, ClrInt for one intention, one deed).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from .ia import SUSPEND, FailGoal, IAContext, IAError, call_ia
from .intentions import Event, IntendedMeans, Intention, Suspension, unifier_term
from .logic import compile_context, eval_rel, first_solution, query_bb, solve
from .plans import (
    ACHIEVE,
    ADD,
    BRANCH_JOIN,
    DEL,
    GOAL_STATE,
    K_ACHIEVE,
    K_ACHIEVE_NEW,
    K_ACTION,
    K_ADD_BEL,
    K_ADD_BEL_NEW,
    K_CONSTRAINT,
    K_DEL_ADD_BEL,
    K_DEL_BEL,
    K_DEL_BEL_NEW,
    K_FOR,
    K_IF,
    K_INTERNAL,
    K_LOOP,
    K_TEST,
    K_WHILE,
    TEST,
    Deed,
    LoopRound,
    Plan,
    PlanLibrary,
    Trigger,
)
from .selection import Option
from .terms import (
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
    fresh_name,
    is_ground,
    is_internal_action,
    term_str,
)
from .unify import ArithError, rename_vars, resolve, unify, walk

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent


# ====================================================================== helpers

def error_annots(ag: Agent, im: IntendedMeans | None, deed: Deed | None, kind: str, msg: str,
                 code: Any = None, extra: list | None = None) -> list:
    """Jason's failure annotations: error, error_msg, code, code_src, code_line (+ extra).

    As in ``TransitionSystem.setDefaultFailureAnnots``, ``code``, ``code_src`` and ``code_line``
    are only added when ``extra`` has no annotation of that name.
    """
    extra = list(extra or [])
    given = {a.functor for a in extra if isinstance(a, Literal)} if extra else ()
    out: list = [Literal("error", (Literal(kind),)), Literal("error_msg", (msg,))]
    if "code" not in given:
        if code is None and deed is not None:
            code = deed.term if im is None else resolve(deed.term, im.u, ag)
        if code is not None and not isinstance(code, (Literal, float, str)):
            code = Literal(term_str(code))
        if code is not None:
            out.append(Literal("code", (code,)))
    if im is not None and "code_src" not in given:
        out.append(Literal("code_src", (im.plan.src,)))
    if deed is not None and "code_line" not in given:
        out.append(Literal("code_line", (float(deed.line),)))
    return out + extra


def _fail_annots(args: list) -> tuple[str, list]:
    """``.fail(A...)`` (jason.stdlib.fail): the message is the first ``error_msg(M)`` argument
    (``"fail"`` without one) and every other argument becomes an annotation."""
    msg, smsg = "fail", None
    for a in args:
        if isinstance(a, Literal) and a.functor == "error_msg" and len(a.args) == 1:
            smsg = a
            m = a.args[0]
            msg = m if isinstance(m, str) else term_str(m)
            break
    return msg, [a for a in args if a is not smsg]


def _self_sourced(ag: Agent, d: Deed, u: dict, error: str) -> Literal:
    """The deed's literal under ``u``, with ``source(self)`` when it has no source.

    Raises IAError with ``error`` (``{}`` = the term) when the deed's term is not a literal.
    """
    st = d.self_term
    if st is not None:
        builder = d.builder
        lit = builder.build(u, ag) if builder is not None else resolve(st, u, ag)
        if type(lit) is Literal:
            return lit
    lit = resolve(d.term, u, ag)
    if not isinstance(lit, Literal):
        raise IAError(error.format(term_str(lit)))
    return lit.with_self_source()


def _goal_literal(ag: Agent, d: Deed, u: dict) -> Any:
    """The goal of a ``!g``/``!!g`` deed under ``u`` (with ``source(self)``); a goal whose
    namespace is a free variable (``!N::g``) is posted as it is, as Jason does."""
    if type(d.term) is NsLit:
        t = resolve(d.term, u, ag)
        if type(t) is NsLit and type(t.lit) is Literal:
            return NsLit(t.ns, t.lit.with_self_source())
    return _self_sourced(ag, d, u, "invalid goal {}")


# ====================================================================== deliberate

def deliberate(ag: Agent) -> bool:
    """Handle one pending event (SelEv -> RelPl -> ApplPl -> SelAppl -> AddIM).

    External events nobody has a plan for are dropped before they are queued
    (:meth:`.Circumstance.add_event`), so they never use up a cycle, as in Jason.
    """
    did = False
    c = ag.circ
    c.selected_event = None
    if c.goal_state_events:
        c.post_goal_states()
    while c.events:
        # SelEv: the first event, unless an atomic intention or the agent's own selection
        # function may have a say
        ev = sel_ev(ag) if c.atomic_used or ag.selection.event is not None else c.events.popleft()
        if ev is None:
            break
        c.selected_event = ev
        did = True
        if handle_event(ag, ev):
            break
    return did


def sel_ev(ag: Agent) -> Event | None:
    """SelEv: the first event (FIFO), with Jason's rules for atomic intentions: no event is
    selected while an atomic intention runs, and an event of an atomic intention (its subgoal)
    goes before every other event (``TransitionSystem.applySelEv``); then the agent's own
    ``selection.event`` function, when it has one."""
    c = ag.circ
    if c.atomic_used:
        if c.atomic_running():
            return None
        for k, ev in enumerate(c.events):
            if ev.intention is not None and ev.intention.is_atomic:
                del c.events[k]
                return ev
    choose = ag.selection.event
    if choose is None:
        return c.events.popleft()
    chosen = choose(ag, list(c.events))
    if chosen is None:
        return None
    _take(c.events, chosen, "event")
    return chosen


def _take(queue: Any, chosen: Any, what: str) -> None:
    """Remove ``chosen`` (the very object) from ``queue``; a selection function must return
    one of the members it was given."""
    for k, x in enumerate(queue):
        if x is chosen:
            del queue[k]
            return
    raise _not_a_candidate(what, chosen)


def _not_a_candidate(what: str, chosen: Any) -> ValueError:
    return ValueError(f"the {what} selection function returned {chosen!r}, which is not one of "
                      "the candidates it was given")


def rel_pl(ag: Agent, ev: Event) -> list[Plan]:
    """RelPl: candidate plans for the event's trigger."""
    return ag.pl.relevant(ev.trigger)


def sel_appl(ag: Agent, lit: Any, relevant: list[Plan], ev: Event | None = None) -> tuple[Plan, dict] | None:
    """ApplPl + SelAppl: the first applicable plan in source order and its unifier.

    Plans are checked one by one and the search stops at the first applicable one (Jason's
    default ``selectOption``), so later contexts are never evaluated. An agent with its own
    ``selection.option`` function gets every applicable plan (ApplPl) and picks one; an agent
    whose belief base has a ``select__option/4`` rule (or fact) gets the first option that it
    accepts (:func:`_sel_option_bb`).
    """
    i = ev.intention if ev is not None else None
    if ag.selection.option is not None:
        return _sel_option(ag, lit, relevant, i)
    if SELECT_OPTION_KEY in ag.bb.by_key:
        return _sel_option_bb(ag, lit, relevant, ev)
    for plan in relevant:
        sol = _applicable(ag, lit, plan, i)
        if sol is not None:
            return plan, sol
    return None


def _applicable(ag: Agent, lit: Any, plan: Plan, i: Intention | None = None) -> dict | None:
    """ApplPl for one relevant plan: the unifier under which its trigger matches ``lit`` and
    its context holds, or None (``i``: the event's intention, for a sub-plan)."""
    u = _relevant_unifier(ag, lit, plan, i)
    if u is None:
        return None
    return _context_holds(ag, plan, u)


def _context_holds(ag: Agent, plan: Plan, u: dict) -> dict | None:
    """The first solution of the plan's context extending ``u``, or None."""
    ctx = plan.context
    if ctx is None:
        return u
    compiled = plan.compiled_context
    if compiled is None and not plan.context_checked:
        compiled = plan.compiled_context = compile_context(ctx)
        plan.context_checked = True
    try:
        return compiled.solve(ag, u) if compiled is not None else first_solution(ag, ctx, u)
    except (ArithError, RecursionError):
        return None


def _relevant_unifier(ag: Agent, lit: Any, plan: Plan, i: Intention | None = None,
                      start: dict | None = None) -> dict | None:
    """The unifier under which the plan's trigger matches the event's literal, or None; it
    extends ``start`` when given, else a sub-plan starts from the unifier its parent plan's
    means in ``i`` started with."""
    u: dict = start if start is not None else (
        {} if plan.scope is None or i is None else _scope_unifier(plan, i))
    args = plan.trigger_args
    if args is not None and type(lit) is Literal:
        # same key as the event (RelPl): only the arguments remain to unify
        if args and not _unify_args(args, lit.args, u, ag):
            return None
    elif not unify(plan.trigger.literal, lit, u, ag):
        return None
    return u


def _scope_unifier(plan: Plan, i: Intention) -> dict:
    """A copy of the unifier that the means of ``i`` running the parent of sub-plan ``plan``
    started with (the topmost such means; none: empty), as Jason's ``getOption``."""
    for im in reversed(i.ims):
        if im.scope_u is not None and im.plan.sub_library is plan.scope:
            return dict(im.scope_u)
    return {}


def _scope_library(i: Intention | None) -> PlanLibrary | None:
    """Where the search for the plans of an event of ``i`` starts when its top means runs a
    plan with sub-plans or a sub-plan (Jason's ``getPLForIM``); None: the agent's own."""
    if i is None or not i.ims:
        return None
    top = i.ims[-1].plan
    return top.sub_library if top.sub_library is not None else top.scope


def scoped_relevant(ag: Agent, i: Intention | None, trig: Trigger) -> list[Plan] | None:
    """RelPl for an event of intention ``i`` in a scope (:func:`_scope_library`): the
    relevant plans of that scope, then of each scope around it, the agent's own plans last;
    None for any other event (the agent's own only)."""
    lib = _scope_library(i)
    if lib is None:
        return None
    found: list[Plan] = []
    while lib is not None:
        found.extend(lib.relevant(trig))
        lib = lib.father
    return found


def _has_fail_plan(ag: Agent, i: Intention, type_: str, lit: Any) -> bool:
    """Is some ``-!g`` plan relevant for goal ``lit`` of intention ``i``, in the scope of its
    top means and those around it (Jason's ``findEventForFailure``, which looks for the
    goal with a failure plan scope by scope), or among the agent's own plans?"""
    lib = _scope_library(i)
    if lib is None:
        return ag.pl.has_candidate(DEL, type_, lit)
    while lib is not None:
        if lib.has_candidate(DEL, type_, lit):
            return True
        lib = lib.father
    return False


def _sel_option(ag: Agent, lit: Any, relevant: list[Plan], i: Intention | None) -> tuple[Plan, dict] | None:
    """ApplPl for every relevant plan, then the agent's ``selection.option`` function."""
    choose = ag.selection.option
    assert choose is not None
    options = []
    for plan in relevant:
        sol = _applicable(ag, lit, plan, i)
        if sol is not None:
            options.append(Option(plan, sol))
    if not options:
        return None
    chosen = choose(ag, options)
    if chosen is None:
        return None
    if not any(o is chosen for o in options):
        raise _not_a_candidate("option", chosen)
    return chosen.plan, chosen.unifier


#: the key of Jason's option-selection rule ``select__option(Event, Intention, Plan, Unifier)``
SELECT_OPTION_KEY = ("select__option", 4, False)


def _sel_option_bb(ag: Agent, lit: Any, relevant: list[Plan], ev: Event | None) -> tuple[Plan, dict] | None:
    """SelAppl through the belief base, as Jason 3.3's ``Agent.selectOptionBB``: every
    solution of every relevant plan's context is an option (as for a plan annotated
    ``all_unifs``), in source order; the first one for which
    ``select__option(Trigger, IntentionId, Plan, Unifier)`` follows from the belief base is
    chosen. ``Trigger`` is the event's trigger term, ``IntentionId`` its intention's number
    (-1 for an external event), ``Plan`` the plan term under the option's unifier and
    ``Unifier`` that unifier as ``[map(_N, Value), ...]`` (:func:`unifier_term`). None when
    the rule accepts none (Jason 3.3 then throws an ``IndexOutOfBoundsException``)."""
    int_id = float(ev.intention.id) if ev is not None and ev.intention is not None else -1.0
    for plan in relevant:
        u = _relevant_unifier(ag, lit, plan, ev.intention if ev is not None else None)
        if u is None:
            continue
        solutions = [u] if plan.context is None else _context_solutions(ag, plan, u)
        for sol in solutions:
            # printed as Jason prints a Trigger and a Plan that are not terms: no braces
            trig = ev.trigger if ev is not None else plan.trigger
            trig_term = PlanTerm((), str(trig), Plan(None, trig, None, (), in_file=False),
                                 braces=False)
            applied = plan.map_terms(lambda t, s=sol: resolve(t, s, ag))
            plan_term = PlanTerm(applied.body, applied.as_text(), applied, braces=False)
            query = Literal(SELECT_OPTION_KEY[0],
                            (trig_term, int_id, plan_term, unifier_term(sol, ag)))
            if first_solution(ag, query, dict(sol)) is not None:
                return plan, sol
    return None


def _context_solutions(ag: Agent, plan: Plan, u: dict) -> list[dict]:
    """Every solution of the plan's context extending ``u`` (an arithmetic error: none)."""
    try:
        return list(solve(ag, plan.context, u))
    except (ArithError, RecursionError):
        return []


def branch_for_update(ag: Agent, ev: Event) -> None:
    """Jason(ER)'s branches (``TransitionSystem.applySelEv``): for an external belief event,
    each intention with a means whose plan has a sub-plan applicable for it (the means tried
    from the top of the stack, the sub-plan's context under the means' unifier as it is now)
    gets a branch: a new intention with the same stack, ``BRANCH_JOIN`` above it and the
    event, its plan chosen already, queued last. The intention itself goes on as before;
    ``.done`` in the branch ends the intention's goal (``stdlib.goals.done``)."""
    trig = ev.trigger
    lit = trig.literal
    if not ((type(lit) is Literal and lit.known_ground) or is_ground(lit)):
        lit = rename_vars(lit, {})
        trig = Trigger(trig.op, trig.type, lit)
    for _place, i in ag.circ.places():
        if i.branch_of is not None or not any(im.plan.sub_library is not None
                                              and im.plan.sub_library.update_plans for im in i.ims):
            continue
        found = _branch_option(ag, i, lit, trig)
        if found is None:
            continue
        branch = Intention(next(ag.circ.intention_ids))
        branch.ims = list(i.ims)   # the same means (Jason's Intention.copyTo)
        branch.atomic_count = i.atomic_count
        branch.branch_of = i
        branch.push(IntendedMeans(BRANCH_JOIN, trig, dict(i.ims[-1].u)))
        branch.suspended = Suspension.EVENT
        ag.circ.events.append(Event(trig, branch, option=found))


def _branch_option(ag: Agent, i: Intention, lit: Any, trig: Trigger) -> tuple[Plan, dict] | None:
    """The first sub-plan of a means of ``i`` (from the top) applicable for the belief event
    ``trig`` under that means' unifier, with its unifier; None when there is none."""
    for im in reversed(i.ims):
        lib = im.plan.sub_library
        if lib is None:
            continue
        for plan in lib.relevant(trig):
            u = _relevant_unifier(ag, lit, plan, None, dict(im.u))
            sol = None if u is None else _context_holds(ag, plan, u)
            if sol is not None:
                return plan, sol
    return None


def handle_event(ag: Agent, ev: Event) -> bool:
    """Find a plan for the event and create/extend an intention.

    Returns False when an external non-goal event was discarded (Jason then selects the
    next event in the same cycle)."""
    trig = ev.trigger
    pl = ag.pl
    key = trig.key
    if ev.option is not None:   # the event of a branch: its plan is chosen
        return _intend(ag, ev, ev.option[0], ev.option[1], True)
    if pl.branch_keys and ev.intention is None and pl.may_branch(key):
        branch_for_update(ag, ev)
    # RelPl (rel_pl, inlined): the plans of the trigger's key, unless some plan has a
    # variable trigger (or the trigger is a variable)
    i = ev.intention
    relevant = pl.by_key.get(key) if not pl.var_plans and key[2] is not None else pl.relevant(trig)
    if i is not None and i.ims and (i.ims[-1].plan.sub_library is not None
                                    or i.ims[-1].plan.scope is not None):
        relevant = scoped_relevant(ag, i, trig)   # in a plan with sub-plans or a sub-plan
    if not relevant:
        if i is not None and not trig.is_goal:
            _resume_after_belief_event(ag, i)       # the common case: +b of a plan body
            return True
        return _no_plan(ag, trig, i, "relevant")
    lit = trig.literal
    ground = (type(lit) is Literal and lit.known_ground) or is_ground(lit)
    if not ground and ev.fail_target is None:
        # an external event keeps the names of the variables inside its plan and rule terms
        # (a told rule prints as it was written, as in Jason); a -!g event keeps those of the
        # failed goal's means, as Jason's does: what its failure plan binds shows there
        # (stdlib.goals.intention_term)
        lit = rename_vars(lit, {}, None if i is not None else _names_outside_code(lit).__contains__)
        ev = Event(Trigger(trig.op, trig.type, lit), i, ev.fail_target, ev.reply)
    opt = sel_appl(ag, lit, relevant, ev)
    if opt is None:
        return _no_plan(ag, trig, i, "applicable")
    return _intend(ag, ev, opt[0], opt[1], ground)


def _intend(ag: Agent, ev: Event, plan: Plan, u: dict, ground: bool) -> bool:
    """AddIM: the means of ``plan`` under ``u`` for the event, on top of the event's
    intention or in a new one; the intention runs."""
    trig = ev.trigger
    i = ev.intention
    if ag.pl.goal_state_plans and trig.op == ADD and trig.type == ACHIEVE:
        ag.circ.goal_state(trig, "executing")   # Jason's applyAddIM
    im = IntendedMeans(plan, ev.trigger, u, ev.fail_target, not ground)
    if i is None:
        i = Intention(next(ag.circ.intention_ids), ev.reply)
    elif trig.op == ADD and i.ims:
        if ag.options.tro:
            _tail_call(ag, i, im)
        if len(i.ims) >= ag.options.max_intention_depth:
            _too_deep(ag, i, trig)
            return True
    if plan.atomic:
        ag.circ.atomic_used = True
        i.push(im)
    else:
        i.ims.append(im)   # (Intention.push: only an atomic plan changes more)
    i.suspended = None
    ag.circ.running.append(i)
    return True


def _names_outside_code(t: Any, out: set[str] | None = None) -> set[str]:
    """The names of the variables of ``t`` that are not inside a plan or rule term."""
    if out is None:
        out = set()
    tt = type(t)
    if tt is Var or tt is AnnotVar:
        out.add(t.name)
        if tt is AnnotVar:
            for a in t.annots:
                _names_outside_code(a, out)
    elif tt is Literal:
        for a in t.args:
            _names_outside_code(a, out)
        for a in t.annots:
            _names_outside_code(a, out)
        if t.tail is not None:
            _names_outside_code(t.tail, out)
    elif tt is ListTerm:
        for a in t.items:
            _names_outside_code(a, out)
        if t.tail is not None:
            _names_outside_code(t.tail, out)
    elif tt is NsLit:
        _names_outside_code(t.ns, out)
        _names_outside_code(t.lit, out)
    elif tt is RelExpr or tt is ArithExpr or tt is LogExpr:
        _names_outside_code(t.left, out)
        if t.right is not None:
            _names_outside_code(t.right, out)
    return out


def _tail_call(ag: Agent, i: Intention, im: IntendedMeans) -> None:
    """Tail-recursion optimisation (Jason's TRO in AddIM): when the top means of ``i`` is a goal
    whose last deed posted this goal again (same functor and arity), it is finished: ``im``
    replaces it, so looping by recursion keeps the intention's depth constant. What the
    replaced means would have passed to its caller is kept in ``im.result``."""
    top = i.ims[-1]
    tt, nt = top.trigger, im.trigger
    if not (tt.op == ADD and tt.is_goal and nt.is_goal and len(top.stack) == 1):
        return
    tl, nl = tt.literal, nt.literal
    if not (type(tl) is Literal and type(nl) is Literal and tl.functor == nl.functor
            and len(tl.args) == len(nl.args)):
        return
    call = top.stack[-1]
    if call.kind not in (K_ACHIEVE, K_TEST):
        return
    i.pop()
    if top.result is None and not top.open_call and (i.ims or i.reply is None):
        return   # top's caller asked a ground goal (and no question waits for the answer)
    answer, asked = _renamed_pair(resolve(tl, top.u, ag), resolve(call.term, top.u, ag))
    if top.result is not None:   # compose with what top itself owed its caller
        s: dict = {}
        prev_answer, prev_call = top.result
        unified = unify(prev_call, answer, s, ag)
        answer = resolve(prev_answer, s, ag)
        if unified:
            asked = resolve(asked, s, ag)
    im.result = (answer, asked)


def _renamed_pair(a: Any, b: Any) -> tuple[Any, Any]:
    """``a`` and ``b`` with their variables renamed apart from every other term (one mapping)."""
    if (type(a) is Literal and a.known_ground) or is_ground(a):
        return a, b
    mapping: dict = {}
    return rename_vars(a, mapping), rename_vars(b, mapping)


def _too_deep(ag: Agent, i: Intention, trig: Trigger) -> None:
    """The intention reached the depth limit: it fails with ``error(intention_too_deep)``."""
    limit = ag.options.max_intention_depth
    msg = (f"intention {i.id} reached the depth limit of {limit} intended means at {trig} "
           "(recursion that is not a tail call?)")
    ag.warn(f"warning: {msg}")
    fail_intention(ag, i, annots=error_annots(ag, i.top(), None, "intention_too_deep", msg,
                                              code=trig.literal))


def _no_plan(ag: Agent, trig: Trigger, i: Intention | None, what: str) -> bool:
    """No ``what`` (relevant/applicable) plan for the event: Jason's Rel2/Appl2 rules.

    A belief event of an intention lets that intention go on; a goal of an intention fails
    it (``-!g`` failure handling); a failed ``-!g`` drops it; an external goal posts its own
    ``-!g`` when some plan could handle that. Returns False for a discarded external belief
    event (the next event is selected in the same cycle).
    """
    if i is not None and not trig.is_goal:
        _resume_after_belief_event(ag, i)
        return True
    if trig.op == GOAL_STATE:
        return False   # a goal-state meta event nobody handles now is dropped silently
    if i is not None:
        msg = f"Found a goal for which there is no {what} plan: {trig}"
        if trig.op == DEL:
            # generateGoalDeletionFromEvent on a -!g event: the intention is given up, unless
            # it runs on (.fail_goal from its own intention left it in the running queue)
            ag.warn("Could not finish intention:\n" + i.dump())
            ag.warn(msg)
            if i.suspended is not None:
                ag.circ.remove_intention(i)
            return True
        fail_intention(ag, i, "no_" + what, msg, code=trig.literal, from_event=trig)
    elif trig.is_goal:
        _external_goal_failed(ag, trig, what)
    else:
        return False
    return True


def _unify_args(xs: tuple, ys: tuple, u: dict, ag: Agent) -> bool:
    for x, y in zip(xs, ys, strict=False):  # noqa: SIM110 - hot path, no generator
        if not unify(x, y, u, ag):
            return False
    return True


def _resume_after_belief_event(ag: Agent, i: Intention) -> None:
    """An internal +b/-b event had no plan: the intention just goes on after the belief deed."""
    ims = i.ims
    if ims:
        stack = ims[-1].stack
        if stack:
            stack.pop()
    i.suspended = None
    if ims and not i.dropped:
        ag.circ.running.append(i)


def _external_goal_failed(ag: Agent, trig: Trigger, what: str) -> None:
    """A goal without intention (``!!g``, a message) has no relevant/applicable plan."""
    msg = f"Found a goal for which there is no {what} plan: {trig}"
    lit = trig.literal
    if trig.op == ADD and isinstance(lit, Literal) and ag.pl.has_candidate(DEL, trig.type, lit):
        annots = [Literal("error", (Literal("no_" + what),)), Literal("error_msg", (msg,)),
                  Literal("code", (lit,))]
        ag.circ.events.append(Event(Trigger(DEL, trig.type, lit.add_annots(annots))))
        return
    if trig.op == ADD:
        ag.warn(f"No fail event was generated for {trig}")
    ag.warn(msg)


# ====================================================================== act

def act(ag: Agent) -> bool:
    """ProcAct (one action feedback) + SelInt + ExecInt + ClrInt on one intention."""
    did = False
    c = ag.circ
    if ag.pl.goal_condition_plans:
        ag.goals.clear_satisfied_goals()
    if c.action_results:
        ag.process_feedback(c.action_results.popleft())
        did = True
    running = c.running
    if not running:
        return did
    # SelInt: round robin (the first one) unless an atomic intention or the agent's own
    # selection function may have a say
    i = sel_int(ag) if c.atomic_used or ag.selection.intention is not None else running.popleft()
    if i is None:
        return did
    exec_int(ag, i)
    return True


def sel_int(ag: Agent) -> Intention | None:
    """SelInt: round robin; an atomic intention is always selected first; then the agent's own
    ``selection.intention`` function, when it has one."""
    c = ag.circ
    running = c.running
    if not running:
        return None
    if c.atomic_used and c.atomic_running():
        for i in list(running):
            if i.is_atomic:
                running.remove(i)
                return i
        return None   # the atomic intention waits: nothing else runs meanwhile (as in Jason)
    choose = ag.selection.intention
    if choose is None:
        return running.popleft()
    chosen = choose(ag, list(running))
    if chosen is None:
        return None
    _take(running, chosen, "intention")
    return chosen


def exec_int(ag: Agent, i: Intention) -> None:
    """ExecInt: execute the next deed of the top intended means."""
    if not i.ims:   # queued twice (a -!g of .fail_goal on a running intention) and finished
        return
    im = i.ims[-1]
    stack = im.stack
    if not stack:  # a plan with an empty body: just ClrInt
        clr_int(ag, i)
        if i.ims and i.suspended is None and not i.dropped:
            ag.circ.running.append(i)
        return
    d = stack[-1]
    im.current = d
    ag.circ.current = i
    try:
        ok = _EXEC_DEED[d.kind](ag, i, im, d)
    except FailGoal as fg:
        if fg.annots:
            msg, extra = _fail_annots(fg.annots)
            annots = error_annots(ag, im, d, "internal_action", msg, extra=extra)
        else:
            annots = error_annots(ag, im, d, "ia_failed", "")
        fail_intention(ag, i, annots=annots)
        ok = False
    except IAError as e:
        fail_intention(ag, i, annots=error_annots(ag, im, d, e.kind, e.message, extra=e.annots))
        if i.dropped:   # no failure plan took it: Jason logs the internal action's error too
            ag.warn(f"Error in internal action '{term_str(d.term)}' ({im.plan.src}:{d.line}): {e.message}")
        ok = False
    except ArithError as e:
        fail_intention(ag, i, annots=error_annots(ag, im, d, "ia_failed", f"arithmetic error: {e}"))
        ok = False
    except RecursionError:
        fail_intention(ag, i, annots=error_annots(ag, im, d, "ia_failed", "term nested too deeply"))
        ok = False
    except Exception as e:
        fail_intention(ag, i, annots=error_annots(ag, im, d, "ia_failed", f"{type(e).__name__}: {e}"))
        ok = False
    finally:
        ag.circ.current = None
    if not ok or i.suspended is not None or i.dropped:   # waits, or failed (handled)
        return
    ims = i.ims
    if not ims:
        return
    if not ims[-1].stack:   # ClrInt only when the top means is finished
        clr_int(ag, i)
        if not ims or i.waits():
            return
    ag.circ.running.append(i)


def _fail(ag: Agent, i: Intention, im: IntendedMeans, d: Deed, kind: str, msg: str, code: Any = None) -> bool:
    fail_intention(ag, i, annots=error_annots(ag, im, d, kind, msg, code=code))
    return False


def _await_own_event(i: Intention, im: IntendedMeans, d: Deed, posted: bool) -> bool:
    """After a belief change in a body: Jason's default ``intBels=sameFocus`` makes its event
    belong to this intention, which waits for it (a plan for it runs on top of the intention;
    without one the intention goes on). The deed stays current until then."""
    if not posted:
        return True
    im.stack.append(d)
    i.suspended = Suspension.EVENT
    return False


# ExecInt, one function per kind of deed. Each returns True when the intention goes on, False
# when it waits (subgoal, event, action, suspension) or failed (already handled).

def _exec_internal_action(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``.ia(...)``: an internal action (may suspend the intention)."""
    u = im.u
    im.stack.pop()
    ctx = IAContext(ag, u, i, im, d)
    r = call_ia(ctx, d.term)
    if r is True:
        im.u = ctx.s
        return True
    if r is SUSPEND:
        im.u = ctx.s
        if not i.dropped:
            i.suspended = i.suspended or Suspension.IA
        return False
    if r is False or r is None:
        return _fail(ag, i, im, d, "ia_failed", "")
    if isinstance(r, dict):
        im.u = r
        return True
    for sol in r:
        im.u = sol
        return True
    return _fail(ag, i, im, d, "ia_failed", "")


def _exec_add_belief(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``+b``: add a belief; its event belongs to this intention."""
    u = im.u
    im.stack.pop()
    if type(d.term) is PlanTerm or (type(d.term) in (Var, AnnotVar) and _holds_rule(d.term, u)):
        return _change_rule(ag, im, d, ADD)
    lit = _self_sourced(ag, d, u, "cannot add {} as a belief")
    return _await_own_event(i, im, d, ag.add_belief(lit, front=True, focus=i))


def _exec_add_belief_new_focus(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``++b``: add a belief; its event is external (a new intention), this one goes on."""
    im.stack.pop()
    ag.add_belief(_self_sourced(ag, d, im.u, "cannot add {} as a belief"), front=True)
    return True


def _exec_remove_belief_new_focus(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``--b``: remove a belief; its event is external, this intention goes on."""
    im.stack.pop()
    if isinstance(resolve(d.term, im.u, ag), ListTerm):
        return True  # a list is a Literal in Jason: no such belief, nothing removed (untell [..])
    lit = _belief_to_remove(ag, im, d)
    if lit is not None:
        ag.remove_belief(lit)
    return True


def _exec_achieve(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``!g``: post the subgoal's event; the intention waits for it."""
    u = im.u
    lit = _goal_literal(ag, d, u)
    if not (type(lit) is Literal and lit.known_ground) and not is_ground(lit):
        lit = rename_vars(lit, {})
    i.suspended = Suspension.SUBGOAL
    trig = Trigger(ADD, ACHIEVE, lit)
    ag.circ.events.append(Event(trig, i))
    if type(lit) is Literal and len(lit.annots) > 1:
        _check_hard_deadline(ag, trig, i)
    if ag.pl.goal_state_plans:
        ag.circ.goal_state(trig, "pending")
    return False


def _exec_achieve_new_focus(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``!!g``: post the goal as a new intention's event."""
    u = im.u
    im.stack.pop()
    trig = d.self_trigger
    if trig is None:
        trig = Trigger(ADD, ACHIEVE, _goal_literal(ag, d, u))
    if type(trig.literal) is Literal and len(trig.literal.annots) > 1:
        _check_hard_deadline(ag, trig, None)
    if ag.circ.event_waits or ag.pl.goal_state_plans:
        ag.circ.add_event(Event(trig))   # (its goal-state event "pending" is posted there)
    else:
        ag.circ.events.append(Event(trig))   # (add_event inlined: a goal's event is always kept)
    return True


def _check_hard_deadline(ag: Agent, trig: Trigger, i: Intention | None) -> None:
    """A goal annotated ``hard_deadline(ms)`` (Jason's checkHardDeadline): ``ms`` from now it
    fails with ``deadline_reached`` if it is still pursued."""
    for a in trig.literal.annots:
        if type(a) is Literal and a.functor == "hard_deadline" and len(a.args) == 1 \
                and type(a.args[0]) is float:
            ag.goals.schedule_deadline(trig, i, a.args[0] / 1000.0)
            return


def _exec_constraint(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``X > 3``, ``X = f(Y)``: a condition in the body."""
    u = im.u
    im.stack.pop()
    f = d.term
    if type(f) is RelExpr:
        r = eval_rel(f, u, ag)
        if r is None:
            return _fail(ag, i, im, d, "constraint_failed",
                         f"Constraint {term_str(resolve(f, u, ag))} was not satisfied.")
        im.u = r
        return True
    for sol in solve(ag, f, u, i):
        im.u = sol
        return True
    return _fail(ag, i, im, d, "constraint_failed",
                 f"Constraint {term_str(resolve(f, u, ag))} was not satisfied.")


def _exec_replace_belief(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``-+b``: remove the first ``b(...)[source(self)]``, then add ``b``."""
    im.stack.pop()
    builder = d.builder
    lit = builder.build(im.u, ag) if builder is not None else None
    if type(lit) is not Literal:
        lit = _self_sourced(ag, d, im.u, "cannot add {} as a belief")
    # remove the first belief matching b(_,...)[source(self)] (external event), then add
    posted, removed = ag.replace_belief(lit, i)
    if removed is not None and removed.args:
        # as Jason, which looks the old belief up with a fresh variable for each argument in
        # the means' unifier: those bindings stay there (.intention lists them)
        u = dict(im.u)
        for arg in removed.args:
            u[fresh_name()] = arg
        im.u = u
    if posted:   # (_await_own_event inlined)
        im.stack.append(d)
        i.suspended = Suspension.EVENT
        return False
    return True


def _exec_remove_belief(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``-b``: remove a belief; its event belongs to this intention."""
    im.stack.pop()
    if type(d.term) is PlanTerm or (type(d.term) in (Var, AnnotVar) and _holds_rule(d.term, im.u)):
        return _change_rule(ag, im, d, DEL)
    lit = _belief_to_remove(ag, im, d)
    if lit is None:
        return True
    return _await_own_event(i, im, d, ag.remove_belief(lit, focus=i))


def _holds_rule(v: Var | AnnotVar, u: dict) -> bool:
    """``+R`` / ``+R[source(A)]`` where R is bound to a rule term."""
    return type(walk(Var(v.name), u)) is PlanTerm


def _change_rule(ag: Agent, im: IntendedMeans, d: Deed, op: str) -> bool:
    """``+{ h :- b }`` adds a rule at the beginning of the rules for ``h``; ``-{ h :- b }``
    removes the first rule that unifies with it (also through a variable, ``+R[a]``: the
    annotations go to the head)."""
    term: Any = d.term
    extra: tuple = ()
    if isinstance(term, AnnotVar):
        extra = tuple(resolve(a, im.u) for a in term.annots)
        term = Var(term.name)
    t = resolve(term, im.u)
    rule = t.rule if type(t) is PlanTerm else None
    if rule is None or not isinstance(rule.head, Literal):
        raise IAError(f"cannot add {term_str(t)} as a belief")
    if op == ADD:
        # Jason's belief base keeps an added rule with fresh variables
        mapping: dict = {}
        head = rename_vars(rule.head.add_annots(extra) if extra else rule.head, mapping)
        ag.bb.add_rule(Rule(head.with_self_source(), rename_vars(rule.body, mapping)), front=True)
        return True
    for r in list(ag.bb.candidates(rule.head.key)):
        if isinstance(r, Rule):
            s2 = dict(im.u)
            if unify(r.head.no_annots(), rule.head.no_annots(), s2) and unify(r.body, rule.body, s2):
                ag.bb.remove_rule(r)
                im.u = s2
                break
    return True


def _belief_to_remove(ag: Agent, im: IntendedMeans, d: Deed) -> Literal | None:
    """The belief a ``-b``/``--b`` deed removes: the literal itself when ground, else the first
    belief it unifies with (its bindings kept in ``im.u``); None when there is none."""
    lit = _self_sourced(ag, d, im.u, "cannot remove {}")
    if lit.known_ground or is_ground(lit):
        return lit
    for sol in query_bb(ag, lit, im.u):
        im.u = sol
        return resolve(lit, sol, ag)
    return None


def _exec_test_goal(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``?g``: query the beliefs, else post a ``+?g`` event."""
    u = im.u
    stack = im.stack
    f = d.term
    for sol in solve(ag, f, u, i):
        stack.pop()
        im.u = sol
        return True
    lit = resolve(f, u, ag)
    if (isinstance(lit, Literal) and not is_internal_action(lit.functor)
            and ag.pl.has_candidate(ADD, TEST, lit)):
        lit = lit.with_self_source()
        if not is_ground(lit):
            lit = rename_vars(lit, {})
        i.suspended = Suspension.SUBGOAL
        ag.circ.events.append(Event(Trigger(ADD, TEST, lit), i))
        return False
    stack.pop()
    # the message shows the test as written (TransitionSystem: "Failed to test '"+bTerm+"'")
    return _fail(ag, i, im, d, "test_goal_failed", f"Failed to test '{term_str(f)}'", code=lit)


def _exec_action(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """An environment action: the intention waits for its feedback (a plan body in a
    variable runs in its place)."""
    u = im.u
    im.stack.pop()
    lit = resolve(d.term, u, ag)
    if isinstance(lit, Literal) and lit.functor == "true" and not lit.args:
        return True
    if type(lit) is PlanTerm and lit.plan is None and lit.rule is None:
        # a variable holding a plan body (``H`` with ``H = {?b(X); .print(X)}``): its deeds
        # take its place in this means and the first runs in this very step, as in Jason
        deeds = lit.body
        if not deeds:
            return True
        im.stack.extend(reversed(deeds))
        first = deeds[0]
        im.current = first
        return _EXEC_DEED[first.kind](ag, i, im, first)
    if not isinstance(lit, Literal):
        return _fail(ag, i, im, d, "action_failed", f"invalid action {term_str(lit)}")
    ag.start_action(i, im, d, lit)
    return False


def _exec_if(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``if (c) {...} elif (c) {...} else {...}``."""
    u = im.u
    stack = im.stack
    stack.pop()
    branches, els = d.extra
    for cond, body in branches:
        for sol in solve(ag, cond, u, i):
            im.u = sol
            stack.extend(reversed(body))
            return True
    if els is not None:
        stack.extend(reversed(els))
    return True


def _exec_while(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``while (c) {...}``."""
    im.stack.pop()
    _start_while(ag, i, im, d, False)
    return True


def _start_while(ag: Agent, i: Intention, im: IntendedMeans, d: Deed, braced: bool) -> None:
    """The first pass of the ``while`` deed ``d`` (``braced``: started by ``.loop``)."""
    base = im.u
    _while_pass(ag, i, im, Deed(K_LOOP, d.term, d.line, LoopRound(K_WHILE, d, base, None, braced)),
                base)


def _while_pass(ag: Agent, i: Intention, im: IntendedMeans, next_round: Deed, s: dict) -> bool:
    """Start the next pass of a ``while`` (``next_round``: its :class:`LoopRound` deed, put
    back after the block) if its condition holds under ``s``."""
    loop = next_round.extra.loop
    for sol in solve(ag, loop.term, s, i):
        im.u = sol
        im.stack.append(next_round)
        im.stack.extend(reversed(loop.extra))
        return True
    return False


def _exec_for(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """``for (c) {...}``: one iteration per solution of ``c``."""
    im.stack.pop()
    _start_for(ag, i, im, d, False)
    return True


def _start_for(ag: Agent, i: Intention, im: IntendedMeans, d: Deed, braced: bool) -> None:
    """The first pass of the ``for`` deed ``d`` (``braced``: started by ``.foreach``)."""
    base = im.u
    sols = solve(ag, d.term, base, i)   # lazy, as Jason: each solution after the last pass
    _for_next(im, Deed(K_LOOP, d.term, d.line, LoopRound(K_FOR, d, base, sols, braced)))


def _exec_loop_next(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> bool:
    """The next iteration of a ``while`` or ``for``."""
    im.stack.pop()
    r: LoopRound = d.extra
    if r.kind == K_WHILE:
        s = dict(r.base)   # the loop's variables unbound again
        if not _while_pass(ag, i, im, d, s):
            im.u = s
        return True
    _for_next(im, d)
    return True


def _for_next(im: IntendedMeans, next_round: Deed) -> None:
    """The next pass of a ``for`` (``next_round``: its :class:`LoopRound` deed, put back
    after the block), or its end: the unifier as before the loop."""
    r: LoopRound = next_round.extra
    for sol in r.solutions:
        im.u = sol
        im.stack.append(next_round)
        im.stack.extend(reversed(r.loop.extra))
        return
    im.u = dict(r.base)


def run_statement(ag: Agent, i: Intention, im: IntendedMeans, d: Deed) -> None:
    """Run the ``if``/``while``/``for`` deed ``d`` at once, as the top of ``im``'s stack, for
    the internal actions ``.if_then_else``/``.loop``/``.foreach``: as in Jason, the action
    tests the condition and puts the block in place in the step that calls it."""
    if d.kind == K_IF:
        im.stack.append(d)          # (taken off by _exec_if)
        _exec_if(ag, i, im, d)
    elif d.kind == K_WHILE:
        _start_while(ag, i, im, d, True)
    else:
        _start_for(ag, i, im, d, True)


#: ExecInt's handler for each kind of deed.
_EXEC_DEED = {
    K_INTERNAL: _exec_internal_action,
    K_ADD_BEL: _exec_add_belief,
    K_ACHIEVE: _exec_achieve,
    K_ACHIEVE_NEW: _exec_achieve_new_focus,
    K_CONSTRAINT: _exec_constraint,
    K_DEL_ADD_BEL: _exec_replace_belief,
    K_DEL_BEL: _exec_remove_belief,
    K_ADD_BEL_NEW: _exec_add_belief_new_focus,
    K_DEL_BEL_NEW: _exec_remove_belief_new_focus,
    K_TEST: _exec_test_goal,
    K_ACTION: _exec_action,
    K_IF: _exec_if,
    K_WHILE: _exec_while,
    K_FOR: _exec_for,
    K_LOOP: _exec_loop_next,
}


def means_answer(ag: Agent, im: IntendedMeans) -> Any:
    """The finished means' goal as its caller gets it: its trigger under its unifier, or, when
    tail-recursion optimisation made it replace other means, what those owed their caller."""
    res = resolve(im.trigger.literal, im.u, ag)
    if im.result is None:
        return res
    answer, asked = im.result
    s: dict = {}
    return resolve(answer, s, ag) if unify(asked, res, s, ag) else answer


def clr_int(ag: Agent, i: Intention) -> None:
    """ClrInt: pop finished intended means, passing results back to the caller's goal."""
    ims = i.ims
    while ims and not ims[-1].stack:
        if ims[-1].trigger_u is not None:
            # Jason 3's goal condition: the goal (or belief event) is achieved when it holds,
            # not when the plan is done; until then the intention waits
            # (see GoalOps.clear_satisfied_goals)
            ag.circ.suspend(i, Suspension.GOAL_CONDITION)
            i.pi_key = str(i.id)   # pending (Jason's PI), under the intention's number
            return
        im = ims.pop()   # (Intention.pop inlined)
        if im.plan.atomic:
            i.atomic_count -= 1
        if ag.pl.goal_state_plans and im.trigger.is_goal and im.trigger.op != GOAL_STATE:
            # a -!g plan that finishes achieves g too (Jason: the goal of the top means)
            ag.circ.goal_state(im.trigger, "achieved")
            ag.circ.goal_state(im.trigger, "finished")
        if not ims:
            if i.reply is not None:
                ag.comm.intention_finished(i, im)
            return
        if im.fail_target == DROPPED_FIRST:
            if _clr_after_dropped_goal(ag, i, im):
                continue
            return
        if im.fail_target is not None:
            i.truncate(im.fail_target)
            if not ims:
                ag.comm.intention_finished(i, im)
                return
            caller = ims[-1]
            if caller.stack and caller.stack[-1] is caller.current:
                d = caller.stack.pop()   # the deed that failed (an internal action is gone already)
                if d.kind == K_ACHIEVE:
                    # as Jason, the failure plan's goal answers the caller's !g(X) (X bound)
                    _answer_caller(ag, caller, d, im)
            continue
        caller = ims[-1]
        if caller.stack:
            d = caller.stack.pop()
            if d.kind in (K_ACHIEVE, K_TEST):
                _answer_caller(ag, caller, d, im)


#: ``fail_target`` of a ``-!g`` posted by ``.fail_goal`` from the goal's own intention: Jason
#: has popped the goal's means already and the intention ran on, so when the failure plan ends
#: its ClrInt looks for the goal in the stack (:func:`_clr_after_dropped_goal`)
DROPPED_FIRST = -1


def _achieves(ag: Agent, m: IntendedMeans, lit: Any) -> bool:
    """Is the next deed of ``m`` a ``!g`` that unifies with ``lit`` (``m`` keeps the bindings)?"""
    if not m.stack:
        return False
    d = m.stack[-1]
    if d.kind != K_ACHIEVE or type(d.term) in (Var, AnnotVar):
        return False
    s2 = dict(m.u)
    if unify(resolve(d.term, m.u, ag), lit, s2, ag):
        m.u = s2
        return True
    return False


def _clr_after_dropped_goal(ag: Agent, i: Intention, done: IntendedMeans) -> bool:
    """Jason's ClrInt after a failure plan ``done`` (popped already) whose goal ``.fail_goal``
    removed from its own intention: means are popped until one that is (or calls) the goal
    has gone, then the caller goes on after its next deed. As the caller already went on past
    the goal when ``.fail_goal`` returned, this gives up its means too, unless its next deed
    posts the same goal again. Returns whether the intention has means left."""
    lit = done.trigger.literal
    ims = i.ims
    m = ims[-1]
    if not _achieves(ag, m, lit):
        m = i.pop()
    while ims and not (m.trigger.is_goal and unify(m.trigger.literal, lit, dict(m.u), ag)) \
            and not _achieves(ag, m, lit):
        m = i.pop()
    if not ims:
        if i.reply is not None:
            ag.comm.intention_finished(i, done)
        return False
    caller = ims[-1]
    if caller.stack:
        d = caller.stack.pop()
        if d.kind == K_ACHIEVE:
            _answer_caller(ag, caller, d, done)
    return True


def _answer_caller(ag: Agent, caller: IntendedMeans, d: Deed, im: IntendedMeans) -> None:
    """Unify the caller's goal deed ``d`` with what the finished means ``im`` achieved."""
    res = means_answer(ag, im)
    goal = resolve(d.term, caller.u, ag)
    s2 = dict(caller.u)
    if unify(goal, res, s2, ag):
        caller.u = s2


# ====================================================================== failure

def fail_intention(ag: Agent, i: Intention, kind: str | None = None, msg: str = "",
                   code: Any = None, annots: list | None = None, from_event: Trigger | None = None) -> None:
    """generateGoalDeletion (Jason's Intention.findEventForFailure): walking down the stack
    from the top means, post ``-!g`` for the first goal with a failure plan, else drop.

    When a failure plan itself failed, the walk starts below the goal it handled. A failure
    plan met further down (a subgoal of ``-!g`` failed without a plan of its own) is tried
    again: its ``-!g`` is posted anew, and when that finishes the goal's means goes on after
    the deed that failed, as Jason does."""
    if annots is None:
        im = i.top()
        d = im.stack[-1] if im is not None and im.stack else None
        annots = error_annots(ag, im, d, kind or "ia_failed", msg, code=code)
    ims = i.ims
    if (from_event is not None and from_event.op == ADD and from_event.is_goal
            and _has_fail_plan(ag, i, from_event.type, from_event.literal)):
        # findEventForFailure starts with the goal of the event itself (it has no means yet):
        # its -!g runs on top of the intention, then the caller goes on after the subgoal
        _post_failure_of(ag, i, from_event, annots, len(ims), from_event)
        return
    idx = len(ims) - 1
    target = ims[idx].fail_target if from_event is None and idx >= 0 else None
    if target == DROPPED_FIRST:
        target = idx   # the goal's means is gone: the walk starts at the failure plan's caller
    if target is not None:
        if target == 0:
            # the goal has no caller: its failure plan is tried again
            tgt = ims[0]
            i.truncate(1)
            _post_failure(ag, i, tgt, annots, 0)
            return
        idx = target - 1
    while idx >= 0:
        im = ims[idx]
        t = im.trigger
        if _has_fail_plan(ag, i, t.type, t.literal):
            if t.is_goal and t.op != GOAL_STATE:
                if i.fork is not None and idx < i.fork.point and not _end_fork(ag, i):
                    break
                _post_failure(ag, i, im, annots, idx, from_event)
                return
            break
        idx -= 1
    if i.fork is not None:
        _end_fork(ag, i)
    top = i.top()
    trig = top.trigger if top is not None else None
    if trig is not None:
        shown = Trigger(trig.op, trig.type, trig.literal.add_annots(annots)
                        if isinstance(trig.literal, Literal) else trig.literal)
    else:
        shown = None
    c = ag.circ
    if from_event is not None:
        ag.warn_drop(i, f"No fail event was generated for {from_event}", shown, relevant_msg=msg)
        se = c.selected_event
        if se is not None and se.intention is i:
            # Jason leaves the event selected, its intention whole, until the next
            # deliberation: .intend, .desire and .intention of this cycle's act still see it
            kept = Intention(i.id)
            kept.ims = list(i.ims)
            c.selected_event = Event(se.trigger, kept)
    else:
        ag.warn_drop(i, f"No failure event was generated for {shown}", shown)
    c.remove_intention(i)


_HAS_FAILURE_PLAN = Literal("has_failure_plan")


def _end_fork(ag: Agent, i: Intention) -> bool:
    """A branch of a ``.fork`` failed below its fork point: an ``and`` fork drops its other
    branches (True: the failure goes on below); an ``or`` fork leaves them running and the
    failed branch just ends (False)."""
    assert i.fork is not None, "only a branch of a fork ends one"
    fk = i.fork.fork
    if not fk.is_and:
        return False
    for other in fk.branches:
        if other is not i:
            ag.circ.remove_intention(other)
    fk.branches = [i]
    i.fork = None
    return True


def _post_failure(ag: Agent, i: Intention, im: IntendedMeans, annots: list, idx: int,
                  failed: Trigger | None = None) -> None:
    """Post ``-!g`` for the goal of ``im``; ``failed`` is the goal whose failure started it
    (default: the top means'), whose state becomes ``failed`` (reason: the error) and then
    ``executing`` (reason: ``has_failure_plan``), as Jason's goal listener posts them."""
    _post_failure_of(ag, i, im.trigger, annots, idx, failed)


def _post_failure_of(ag: Agent, i: Intention, t: Trigger, annots: list, idx: int,
                     failed: Trigger | None = None) -> None:
    """Post ``-!g`` for the goal of trigger ``t`` (see :func:`_post_failure`); when it is
    handled, the means from ``idx`` up are given up and the caller goes on after its deed."""
    if ag.pl.goal_state_plans:
        top = i.top()
        ft = failed or (top.trigger if top is not None else t)
        reason = next((a.args[0] for a in annots if isinstance(a, Literal) and a.functor == "error"
                       and len(a.args) == 1), "")
        ag.circ.goal_state(ft, "failed", reason)
        ag.circ.goal_state(ft, "executing", _HAS_FAILURE_PLAN)
    lit = t.literal.add_annots(annots) if isinstance(t.literal, Literal) else t.literal
    ag.circ.detach(i)
    i.suspended = Suspension.FAILURE
    ag.circ.events.append(Event(Trigger(DEL, t.type, lit), i, fail_target=idx))


def fail_goal_above(ag: Agent, i: Intention, idx: int, lit: Any, annots: tuple = ()) -> None:
    """``.fail_goal`` of the goal of ``i.ims[idx]`` with ``idx > 0`` (``lit``: the goal as the
    action's argument, bound). As Jason's: the goal's means and those above go at once; then
    ``-!g`` (no annotations but ``annots``) is posted for the goal, or for the first means below
    with a failure plan. From another intention, that intention waits for the event (none:
    it goes, silently). From the goal's own intention, the caller goes on after its ``!g``
    meanwhile (see :func:`_clr_after_dropped_goal`)."""
    c = ag.circ
    own = i is c.current
    t = i.ims[idx].trigger
    if ag.pl.goal_state_plans:
        c.goal_state(t, "failed")
    i.truncate(idx)
    ims = i.ims
    ev_lit: Any = None
    j = idx
    if _has_fail_plan(ag, i, ACHIEVE, lit):
        ev_lit = lit
    else:
        for j in range(idx - 1, -1, -1):
            tj = ims[j].trigger
            if _has_fail_plan(ag, i, tj.type, tj.literal):
                if tj.op == ADD and tj.is_goal:
                    ev_lit = tj.literal
                break
    if ev_lit is not None and annots and isinstance(ev_lit, Literal):
        ev_lit = ev_lit.add_annots(annots)
    if own:
        top = ims[-1]
        if top.stack:
            top.stack.pop()   # Jason's ExecInt: the step of the means now on top is done
        top.current = None
        if ev_lit is not None:
            c.events.append(Event(Trigger(DEL, ACHIEVE, ev_lit), i, fail_target=DROPPED_FIRST))
        return
    if ev_lit is None:
        c.remove_intention(i)
        return
    c.detach(i)
    i.suspended = Suspension.FAILURE
    c.events.append(Event(Trigger(DEL, ACHIEVE, ev_lit), i, fail_target=j))


def fail_goal_at(ag: Agent, i: Intention, idx: int, annots: tuple = ()) -> None:
    """``.fail_goal``: fail the goal of ``i.ims[idx]`` (its ``-!g`` event has no annotations
    but ``annots``)."""
    ims = i.ims
    j = idx
    while j >= 0:
        im = ims[j]
        t = im.trigger
        if _has_fail_plan(ag, i, t.type, t.literal):
            if t.op == ADD and t.is_goal:
                if ag.pl.goal_state_plans:
                    ag.circ.goal_state(t, "failed")
                lit = t.literal.no_annots() if isinstance(t.literal, Literal) else t.literal
                if annots and isinstance(lit, Literal):
                    lit = lit.add_annots(annots)
                ag.circ.detach(i)
                i.suspended = Suspension.FAILURE
                ag.circ.events.append(Event(Trigger(DEL, t.type, lit), i, fail_target=j))
                return
            break
        j -= 1
    # no failure plan: Jason's fail_goal drops the intention without a warning (logged at
    # level fine only), in 3.2.2 and 3.3 alike
    ag.circ.remove_intention(i)

