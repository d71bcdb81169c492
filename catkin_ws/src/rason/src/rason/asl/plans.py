"""Plans, plan bodies and the plan library (Jason's ``Plan``, ``PlanBody``, ``PlanLibrary``)."""

from __future__ import annotations

import copy
import itertools
from collections.abc import Iterator
from typing import TYPE_CHECKING, Any

from .terms import (
    SOURCE_SELF,
    AnnotVar,
    Literal,
    LogExpr,
    NsLit,
    PlanTerm,
    Var,
    calls_code,
    is_constant,
    is_internal_action,
    java_unifier_text,
    term_str,
)
from .unify import compile_resolve

if TYPE_CHECKING:  # pragma: no cover
    from .logic import BeliefContext

# triggering event operators and types
ADD, DEL = "+", "-"
GOAL_STATE = "^"   # goal-state meta events: ^!g[state(S)]
#: the functor of an anonymous label (``@[atomic]``) until the plan library names the plan
ANON_LABEL = "undefined"
ACHIEVE, TEST, BELIEF = "!", "?", ""

# body formula kinds (Jason's BodyType)
K_ACHIEVE = "achieve"          # !g
K_ACHIEVE_NEW = "achieveNF"    # !!g
K_TEST = "test"                # ?g
K_ADD_BEL = "addBel"           # +b
K_DEL_BEL = "delBel"           # -b
K_DEL_ADD_BEL = "delAddBel"    # -+b
K_ADD_BEL_NEW = "addBelNewFocus"  # ++b (its event is external)
K_DEL_BEL_NEW = "delBelNewFocus"  # --b (its event is external)
K_ACTION = "action"            # env action
K_INTERNAL = "internalAction"  # .ia(...)
K_CONSTRAINT = "constraint"    # X > 3, X = Y, ...
K_IF = "if"
K_WHILE = "while"
K_FOR = "for"
K_LOOP = "loop"                # internal: next iteration of while/for


class Trigger:
    """A triggering event ``+!g``, ``-b``, ``+?g``..."""

    __slots__ = ("is_goal", "key", "literal", "op", "type")

    def __init__(self, op: str, type: str, literal: Any) -> None:
        self.op = op
        self.type = type
        self.literal = literal
        self.is_goal = type != BELIEF
        if isinstance(literal, Literal):
            self.key: tuple[str, str, str | None, int, bool] = (
                op, type, literal.functor, len(literal.args), literal.neg)
        else:
            self.key = (op, type, None, 0, False)

    def __reduce__(self) -> tuple:
        return (Trigger, (self.op, self.type, self.literal))

    def __str__(self) -> str:
        return self.op + self.type + term_str(self.literal)

    def __repr__(self) -> str:
        return str(self)

    @property
    def is_achieve(self) -> bool:
        return self.type == ACHIEVE


#: Deeds whose literal gets ``source(self)`` when it has no source (goals and belief changes).
_SELF_SOURCED = (K_ACHIEVE, K_ACHIEVE_NEW, K_ADD_BEL, K_DEL_BEL, K_DEL_ADD_BEL, K_ADD_BEL_NEW,
                 K_DEL_BEL_NEW)


#: deeds that run no internal action or rule of their own (their terms may still call some)
_PLAIN_KINDS = frozenset({K_ACHIEVE, K_ACHIEVE_NEW, K_ADD_BEL, K_DEL_BEL, K_DEL_ADD_BEL,
                          K_ADD_BEL_NEW, K_DEL_BEL_NEW, K_ACTION})


def is_update(t: Trigger) -> bool:
    """Is ``t`` a belief event, ``+b`` or ``-b`` (Jason's ``Trigger.isUpdate``)?"""
    return t.type == BELIEF and (t.op == ADD or t.op == DEL)


class Deed:
    """One formula of a plan body, with the source line it came from.

    ``self_term`` is ``term`` with ``source(self)`` already added, computed once here, when
    that cannot depend on the unifier (the annotations hold no variable and no tail); the
    reasoning cycle then only applies the unifier. None means: add the source at run time.
    """

    __slots__ = ("builder", "extra", "kind", "line", "plain", "self_term", "self_trigger", "term")

    def __init__(self, kind: str, term: Any, line: int, extra: Any = None) -> None:
        self.kind = kind
        self.term = term
        self.line = line
        self.extra = extra
        self.self_term = _with_self_source(term) if kind in _SELF_SOURCED else None
        # resolve(self_term, u) prepared for the common shapes (unify.LiteralBuilder), else None
        self.builder = compile_resolve(self.self_term) if self.self_term is not None else None
        # ``!!g`` of a constant goal posts the same trigger every time
        self.self_trigger = (Trigger(ADD, ACHIEVE, self.self_term)
                             if kind == K_ACHIEVE_NEW and self.self_term is not None
                             and self.self_term.known_constant else None)
        #: running it cannot look at the agent's circumstance (a goal, a belief change or an
        #: environment action whose term calls no internal action, function or rule)
        self.plain = kind in _PLAIN_KINDS and not calls_code(term)

    def __repr__(self) -> str:
        return deed_str(self)

    def jason_str(self) -> str:
        """This deed as Jason prints it (:func:`deed_str`)."""
        return deed_str(self, True)

    def __reduce__(self) -> tuple:
        """Pickled as what it is made from (its ``builder`` is made anew)."""
        return (Deed, (self.kind, self.term, self.line, self.extra))

    def map_terms(self, fn: Any) -> Deed:
        """This deed with ``fn`` applied to every term in it (blocks included), the deed's
        own term first (a statement's condition before its block, as Jason renames them)."""
        term = fn(self.term)
        extra: Any
        if self.kind == K_IF:
            branches, els = self.extra
            extra = ([(fn(c), map_deeds(b, fn)) for c, b in branches],
                     None if els is None else map_deeds(els, fn))
        elif self.kind in (K_WHILE, K_FOR):
            extra = map_deeds(self.extra, fn)
        elif self.kind == K_LOOP:
            r: LoopRound = self.extra
            extra = LoopRound(r.kind, r.loop.map_terms(fn), r.base, r.solutions, r.braced)
        else:
            extra = self.extra
        return Deed(self.kind, term, self.line, extra)


class LoopRound:
    """What the deed of a running ``while``/``for``'s next round (:data:`K_LOOP`, put back
    after the block at each pass) holds: the loop's deed, the unifier before the loop
    (restored after it), for a ``for`` the solutions not taken yet; ``braced`` when the loop
    was started by ``.loop``/``.foreach`` called as actions (their block is a term in braces).
    Jason's ``.loop``/``.foreach`` deed at that place carries these as hidden arguments."""

    __slots__ = ("base", "braced", "kind", "loop", "solutions")

    def __init__(self, kind: str, loop: Deed, base: dict, solutions: Any = None,
                 braced: bool = False) -> None:
        self.kind = kind            # K_WHILE or K_FOR
        self.loop = loop
        self.base = base
        self.solutions = solutions
        self.braced = braced

    def jason_str(self) -> str:
        """Jason's deed of the next round: ``.loop(C,B,{U})``, ``.foreach(C,B,It,{U})``, with
        the unifier before the loop as ``Unifier.toString`` of its copy prints it and, for a
        ``for``, Jason's iterator of the condition's solutions as Java prints an object
        (its class, ``@``, a number that stands for Java's identity hash)."""
        loop = self.loop
        block = body_str(loop.extra, True)
        if self.braced:
            block = "{ " + block + " }"
        if self.kind == K_WHILE:
            return ".loop(" + term_str(loop.term) + "," + block + "," + java_unifier_text(self.base) + ")"
        number = (id(self.solutions) >> 4) & 0x7FFFFFFF
        return (".foreach(" + term_str(loop.term) + "," + block + "," + _java_iterator_class(loop.term)
                + "@" + format(number, "x") + "," + java_unifier_text(self.base) + ")")


#: the internal actions of Jason 3.3 that answer with an iterator of their own (an anonymous
#: class ``jason.stdlib.NAME$1``); the others answer true or false
_ITERATOR_ACTIONS = frozenset({
    ".belief", ".desire", ".intend", ".intention", ".member", ".namespace", ".namespace_get_prop",
    ".nth", ".plan_label", ".prefix", ".random", ".range", ".relevant_plan", ".sublist",
    ".substring", ".suffix", ".type"})


def _java_iterator_class(cond: Any) -> str:
    """The class of the iterator Jason's ``logicalConsequence`` gives for the condition
    ``cond`` (checked against Jason 3.3): a belief or rule query ``Literal$1``, a conjunction
    ``LogExpr$1``, a disjunction ``LogExpr$2``, an internal action with solutions of its own
    its class, anything else (``not``, a relation, ``true``, an action answering true) the one
    of a single solution, ``LogExpr$3``."""
    if type(cond) is LogExpr and cond.op in ("&", "|"):
        return "jason.asSyntax.LogExpr$" + ("1" if cond.op == "&" else "2")
    if type(cond) is Literal and cond.functor != "true":
        if cond.functor in _ITERATOR_ACTIONS:
            return "jason.stdlib." + cond.functor[1:] + "$1"
        if not is_internal_action(cond.functor):
            return "jason.asSyntax.Literal$1"
    return "jason.asSyntax.LogExpr$3"


def _with_self_source(term: Any) -> Literal | None:
    if type(term) is not Literal or term.tail is not None:
        return None
    if not all(is_constant(a) for a in term.annots):
        return None
    lit = term.with_self_source()
    is_constant(lit)   # cached on the literal: resolving a constant is free
    return lit


def body_str(body: tuple | list, jason: bool = False) -> str:
    """The deeds of a body as rason's source text (read back by rason's parser), or with
    `jason` as Jason prints them (see :func:`deed_str`)."""
    return "; ".join(deed_str(d, jason) for d in body)


def deed_str(d: Deed, jason: bool = False) -> str:
    """One deed as rason's source text, or with `jason` as Jason prints it: the statements
    as the internal actions Jason's parser makes of them (``.if_then_else(C,T,E)``, an
    ``elif`` a nested one, ``.foreach(C,B)``, ``.loop(C,B)``, blocks without braces) and the
    branches of ``|&|``/``|||`` without braces. The source text keeps the statements and
    puts every ``.fork`` branch in braces, so that rason reads it back."""
    k = d.kind
    t = d.term
    if k == K_ACHIEVE:
        return "!" + term_str(t, jason)
    if k == K_ACHIEVE_NEW:
        return "!!" + term_str(t, jason)
    if k == K_TEST:
        return "?" + term_str(t, jason)
    if k == K_ADD_BEL:
        return "+" + term_str(t, jason)
    if k == K_DEL_BEL:
        return "-" + term_str(t, jason)
    if k == K_DEL_ADD_BEL:
        return "-+" + term_str(t, jason)
    if k == K_ADD_BEL_NEW:
        return "++" + term_str(t, jason)
    if k == K_DEL_BEL_NEW:
        return "--" + term_str(t, jason)
    if k == K_IF:
        if jason:
            return _jason_if(d.extra[0], d.extra[1])
        parts = []
        for i, (cond, body) in enumerate(d.extra[0]):
            kw = "if" if i == 0 else "elif"
            parts.append(kw + " (" + term_str(cond, False) + ") { " + body_str(body) + " }")
        if d.extra[1] is not None:
            parts.append("else { " + body_str(d.extra[1]) + " }")
        return " ".join(parts)
    if k == K_WHILE:
        return _loop_str("while", t, d.extra, jason)
    if k == K_FOR:
        return _loop_str("for", t, d.extra, jason)
    if k == K_LOOP:
        # the next round of a while/for: Jason's ``.loop``/``.foreach`` deed put back after
        # the block, with its hidden arguments
        return d.extra.jason_str() if jason else "{ loop }"
    if not jason and k == K_INTERNAL and type(t) is Literal and t.functor == ".fork":
        return _fork_source(t)
    return term_str(t, jason)


def _fork_source(t: Literal) -> str:
    """A ``.fork`` deed as source text: a fork made by ``|&|``/``|||`` (branches not in
    braces) as those operators, so that it reads back the same; another with every body in
    braces (rason's parser reads no bare body as an argument)."""
    ops = _operator_fork(t)
    if ops is not None:
        return ops
    if t.annots:
        return term_str(t, False)
    return ".fork(" + ",".join("{ " + a.text + " }" if type(a) is PlanTerm and a.plan is None
                               and a.rule is None else term_str(a, False)
                               for a in t.args) + ")"


def _operator_fork(t: Literal) -> str | None:
    """``A |&| B`` / ``A ||| B`` for a fork whose branches are bodies out of braces (as the
    operators make them), else None. A branch that is such a fork goes in parentheses, one
    of several deeds or a statement in braces (a plan-body term, run in place)."""
    branches = t.args[1:]
    op = {"and": " |&| ", "or": " ||| "}.get(term_str(t.args[0])) if t.args else None
    if op is None or t.annots or len(branches) < 2 or not all(
            type(a) is PlanTerm and not a.braces and a.plan is None and a.rule is None
            for a in branches):
        return None
    parts = []
    for a in branches:
        body = a.body
        if len(body) != 1 or body[0].kind in (K_IF, K_WHILE, K_FOR, K_LOOP):
            parts.append("{ " + body_str(body) + " }")
            continue
        inner = _operator_fork(body[0].term) if (
            body[0].kind == K_INTERNAL and type(body[0].term) is Literal
            and body[0].term.functor == ".fork") else None
        parts.append("(" + inner + ")" if inner is not None else deed_str(body[0]))
    return op.join(parts)


def _jason_if(branches: list, els: tuple | None) -> str:
    """``if``/``elif``/``else`` as Jason prints it: ``.if_then_else(C,T[,E])``, each ``elif``
    the else part of the one before."""
    cond, body = branches[0]
    s = ".if_then_else(" + term_str(cond) + "," + body_str(body, True)
    if len(branches) > 1:
        s += "," + _jason_if(branches[1:], els)
    elif els:    # an empty else is no else part in Jason (an empty then part prints empty)
        s += "," + body_str(els, True)
    return s + ")"


def _loop_str(kind: str, cond: Any, block: tuple, jason: bool) -> str:
    """``while``/``for`` as source text, or as Jason's ``.loop``/``.foreach``."""
    if jason:
        return (".loop(" if kind == "while" else ".foreach(") + term_str(cond) + "," + \
            body_str(block, True) + ")"
    return kind + " (" + term_str(cond, False) + ") { " + body_str(block) + " }"


#: the fields of a :class:`Plan` it is made from (by name: a pickled plan keeps no position)
_PLAN_MADE_FROM = ("label", "trigger", "context", "body", "line", "src", "atomic", "in_file",
                   "goal_condition", "sub_plans")


def _remake_plan(made_from: dict) -> Plan:
    """A plan from its pickled fields (see :meth:`Plan.__reduce__`)."""
    return Plan(**made_from)


class Plan:
    """``@label trigger : context <- body.`` (compared by identity).

    A plain class with the ``__init__`` and ``__repr__`` ``@dataclass(eq=False)`` would make:
    every agent imports this module at start-up, where ``dataclasses`` costs ~3.5 ms."""

    def __init__(self, label: Literal | Var | None, trigger: Trigger, context: Any, body: tuple,
                 line: int = 0, src: str = "", atomic: bool = False, in_file: bool = True,
                 goal_condition: Any = None, sub_plans: tuple = ()) -> None:
        #: a variable in a plan term that unifies part by part
        self.label: Literal | Var | None = label
        self.trigger = trigger
        self.context: Any = context
        self.body = body
        self.line = line
        self.src = src
        self.atomic = atomic
        #: body stored reversed, ready to be used as an intention stack (set by _derive)
        self.rev_body: tuple = ()
        #: the context prepared on first use (see reasoning.sel_appl), when it has a common shape
        self.compiled_context: BeliefContext | None = None
        self.context_checked = False
        #: a plan of a source file (its label gets ``url(File)``), not one made from a plan term
        self.in_file = in_file
        #: ``+!g : c <: gc <- b`` (Jason 3's goal condition): once gc holds the goal is
        #: achieved, whether the body is done or not; a body done before waits for it
        self.goal_condition: Any = goal_condition
        #: the trigger literal's arguments when only they decide whether it unifies with an
        #: event of its key (no annotations, no tail), else None (set by _derive)
        self.trigger_args: tuple | None = None
        #: ``+!g <- b. { +!s <- c. }`` (Jason 3.3's sub-plans): plans relevant only for the
        #: events of an intention that runs this plan or one of them, seeing the variables
        #: this plan had when it was chosen; held in ``scope_library`` once in a library
        self.sub_plans = sub_plans
        #: the library of the sub-plans (made by :meth:`PlanLibrary.add`; None without them)
        self.sub_library: PlanLibrary | None = None
        #: for a sub-plan: the library that holds it (None for a plan of the agent's own library)
        self.scope: PlanLibrary | None = None
        self._derive()

    def __repr__(self) -> str:
        return (f"Plan(label={self.label!r}, trigger={self.trigger!r}, context={self.context!r}, "
                f"body={self.body!r}, line={self.line!r}, src={self.src!r}, "
                f"atomic={self.atomic!r}, in_file={self.in_file!r}, "
                f"goal_condition={self.goal_condition!r}, sub_plans={self.sub_plans!r})")

    def _derive(self) -> None:
        """What the plan's fields imply (its reversed body, trigger arguments, atomicity)."""
        if type(self.context) is Literal and self.context.functor == "true" and not self.context.args:
            self.context = None   # as Jason's Plan.setContext: a 'true' context is no context
        self.rev_body = tuple(reversed(self.body))
        pattern = self.trigger.literal
        self.trigger_args = (pattern.args if type(pattern) is Literal and not pattern.annots
                             and pattern.tail is None else None)
        if isinstance(self.label, Literal):
            self.atomic = any(isinstance(a, Literal) and a.functor == "atomic" for a in self.label.annots)

    def __reduce__(self) -> tuple:
        """Pickled as what it is made from (what ``_derive`` derives, and the context
        prepared on use, are made anew)."""
        return (_remake_plan, ({name: getattr(self, name) for name in _PLAN_MADE_FROM},))

    def label_name(self) -> str | None:
        if not isinstance(self.label, Literal):
            return None
        return self.label.functor

    def __str__(self) -> str:
        """The plan as Jason prints it (``.list_plans``)."""
        text = self.as_text(jason=True)
        return text if self.sub_plans else text + "."

    def as_term(self) -> PlanTerm:
        """This plan as a term (Jason's ``Plan.setAsPlanTerm``): ``{ @l +!g : c <- b }``."""
        return PlanTerm(self.body, self.as_text(), self)

    def body_text(self) -> str:
        return body_str(self.body)

    def map_terms(self, fn: Any) -> Plan:
        """A copy of this plan with ``fn`` applied to every term in it."""
        label = self.label if self.label is None else fn(self.label)
        trigger = Trigger(self.trigger.op, self.trigger.type, fn(self.trigger.literal))
        context = self.context if self.context is None else fn(self.context)
        cond = self.goal_condition if self.goal_condition is None else fn(self.goal_condition)
        return Plan(label, trigger, context, map_deeds(self.body, fn), self.line, self.src,
                    in_file=self.in_file, goal_condition=cond,
                    sub_plans=tuple(p.map_terms(fn) for p in self.sub_plans))

    def with_sub_plans(self, sub_plans: tuple) -> Plan:
        """This plan with ``sub_plans`` after those it has."""
        made = copy.copy(self)
        made.sub_plans = self.sub_plans + sub_plans
        return made

    def as_text(self, label: bool = True, jason: bool = False) -> str:
        """The plan's text without its dot: rason's source text (read back by rason's
        parser), or with `jason` as Jason prints it (see :func:`deed_str`)."""
        s = ""
        if self.label is not None and label:
            s += "@" + term_str(self.label, jason) + " "
        s += str(self.trigger)
        if self.context is not None:
            s += " : " + term_str(self.context, jason)
        if self.goal_condition is not None:
            s += " <: " + term_str(self.goal_condition, jason)
        if self.sub_plans:
            # as Jason's Plan.toASString: the body and each sub-plan on a line of their own
            s += " {"
            if self.body:
                s += "\n   <- " + body_str(self.body, jason) + "."
            for p in (self.sub_library.plans if self.sub_library is not None else self.sub_plans):
                s += "\n   " + p.as_text(jason=jason) + ("" if p.sub_plans else ".")
            return s + "\n}"
        if self.body:
            s += " <- " + body_str(self.body, jason)
        return s


def map_deeds(body: tuple, fn: Any) -> tuple:
    """The deeds of a body with ``fn`` applied to every term (blocks included)."""
    return tuple(d.map_terms(fn) for d in body)


def body_deeds(body: tuple) -> Iterator[Deed]:
    """Every deed of a plan body, those inside ``if``/``while``/``for`` blocks included."""
    for d in body:
        yield d
        if d.kind == K_IF:
            for _cond, block in d.extra[0]:
                yield from body_deeds(block)
            if d.extra[1] is not None:
                yield from body_deeds(d.extra[1])
        elif d.kind in (K_WHILE, K_FOR):
            yield from body_deeds(d.extra)


_plan_numbers = itertools.count(1)


def named_plan(plan: Plan) -> Plan:
    """The plan as Jason's ``PlanLibrary.add`` keeps it: a plan without a label (or with an
    anonymous one, ``@[atomic]``) is named ``p__N`` (annotations kept), and the label carries
    ``source(self)`` when it names no source and ``url(File)`` of the file it came from."""
    label = plan.label
    if isinstance(label, Literal) and label.functor != ANON_LABEL and label.has_source() \
            and (not plan.src or not plan.in_file
                 or any(isinstance(a, Literal) and a.functor == "url" for a in label.annots)):
        return plan
    if not isinstance(label, Literal) or label.functor == ANON_LABEL:
        annots = label.annots if isinstance(label, Literal) else ()
        label = Literal(f"p__{next(_plan_numbers)}", (), annots)
    extra = [] if label.has_source() else [SOURCE_SELF]
    if plan.src and plan.in_file and not any(isinstance(a, Literal) and a.functor == "url"
                                             for a in label.annots):
        extra.append(Literal("url", (plan.src,)))
    named = copy.copy(plan)
    named.label = label.add_annots(extra) if extra else label
    return named


def _for_update(plan: Plan) -> bool:
    """Is ``plan`` for a belief event of a given literal (not ``+X``)? Those make a library
    ``update_plans`` (Jason counts no plan with a variable trigger there)."""
    return is_update(plan.trigger) and not isinstance(plan.trigger.literal, (Var, AnnotVar, NsLit))


class PlanLibrary:
    """Plans indexed by trigger (operator, type, functor, arity) in source order."""

    def __init__(self, father: PlanLibrary | None = None) -> None:
        #: the library whose plans come next in the search (Jason's ``getFather``): for the
        #: sub-plans of a plan, the library that holds that plan; None for the agent's own
        self.father = father
        self.plans: list[Plan] = []
        #: the plans of each trigger key (operator, type, functor, arity, negation), in order
        #: (read directly by the reasoning cycle's inlined RelPl; changed only here)
        self.by_key: dict[tuple, list[Plan]] = {}
        #: plans whose trigger literal is a variable (``+!_``): relevant for every key
        self.var_plans: list[Plan] = []
        #: some plan handles goal-state meta events (``^!g[state(S)]``)
        self.goal_state_plans = False
        #: some plan has a goal condition (``<:``): intentions are checked every cycle
        self.goal_condition_plans = False
        #: some plan of this library is for a belief event (``+b``/``-b``, not a variable):
        #: for sub-plans, an intention running their parent is interested in external belief
        #: events (Jason's ``hasPlansForUpdateEvents``)
        self.update_plans = False
        #: in the agent's own library: the trigger keys of the sub-plans for belief events, at
        #: any depth (``(op, BELIEF, None, 0, False)`` for one whose trigger is a variable,
        #: ``+X``); see :meth:`may_branch`
        self.branch_keys: set[tuple] = set()

    def add(self, plan: Plan, front: bool = False) -> None:
        scoped = self.father is not None or plan.sub_plans
        plan = self._scoped(plan) if scoped else named_plan(plan)
        if _for_update(plan):
            self.update_plans = True
        if plan.sub_library is not None and self.father is None:
            plan.sub_library.collect_update_keys(self.branch_keys)
        if front:
            self.plans.insert(0, plan)
            self._rebuild()
            return
        self.plans.append(plan)     # at the end: the index grows in place (loading stays linear)
        if isinstance(plan.trigger.literal, (Var, AnnotVar, NsLit)):
            self.var_plans.append(plan)
        else:
            self.by_key.setdefault(plan.trigger.key, []).append(plan)
        if plan.trigger.op == GOAL_STATE:
            self.goal_state_plans = True
        if plan.goal_condition is not None:
            self.goal_condition_plans = True

    def _scoped(self, plan: Plan) -> Plan:
        """The plan as this library keeps it, as Jason's parser and ``PlanLibrary`` make it:
        its sub-plans are named first, in a library of their own whose father is this one; a
        sub-plan knows the library it is in and its label gets no ``url``."""
        sub_library = None
        if plan.sub_plans:
            sub_library = PlanLibrary(self)
            for p in plan.sub_plans:
                sub_library.add(p)
        if self.father is not None:
            plan = copy.copy(plan)
            plan.in_file = False
        plan = copy.copy(named_plan(plan))
        plan.sub_library = sub_library
        plan.scope = self if self.father is not None else None
        return plan

    def collect_update_keys(self, keys: set[tuple]) -> None:
        """Add to ``keys`` the trigger keys of this library's plans for belief events (``+b``,
        ``-b``, ``+X``) and of those of every library inside it."""
        for p in self.plans:
            if is_update(p.trigger):
                keys.add(p.trigger.key)
            if p.sub_library is not None:
                p.sub_library.collect_update_keys(keys)

    def replace(self, k: int, plan: Plan) -> None:
        """Put ``plan`` in place of the ``k``-th plan (same position)."""
        self.plans[k] = plan
        self._rebuild()

    def remove_by_label(self, name: str) -> bool:
        n = len(self.plans)
        self.plans = [p for p in self.plans if p.label_name() != name]
        self._rebuild()
        return len(self.plans) != n

    def _rebuild(self) -> None:
        self.by_key = {}
        self.var_plans = []
        self.goal_state_plans = any(p.trigger.op == GOAL_STATE for p in self.plans)
        self.goal_condition_plans = any(p.goal_condition is not None for p in self.plans)
        self.update_plans = any(_for_update(p) for p in self.plans)
        self.branch_keys = set()
        if self.father is None:
            for p in self.plans:
                if p.sub_library is not None:
                    p.sub_library.collect_update_keys(self.branch_keys)
        for p in self.plans:
            if isinstance(p.trigger.literal, (Var, AnnotVar, NsLit)):
                self.var_plans.append(p)
            else:
                self.by_key.setdefault(p.trigger.key, []).append(p)

    def relevant(self, trigger: Trigger) -> list[Plan]:
        """Candidate plans for a trigger (Jason ``getCandidatePlans``); for a variable
        (``+!_``), every plan of the same operator and type."""
        if trigger.key[2] is None:
            return [p for p in self.plans if p.trigger.op == trigger.op and p.trigger.type == trigger.type]
        lst = self.by_key.get(trigger.key)
        if self.var_plans:
            extra = [p for p in self.var_plans
                     if p.trigger.op == trigger.op and p.trigger.type == trigger.type]
            if extra:
                return sorted((lst or []) + extra, key=self.plans.index)
        return lst or []

    def has_key(self, key: tuple) -> bool:
        """True if some plan may be relevant for a trigger with this key (a sub-plan too)."""
        return key in self.by_key or bool(self.var_plans) or self.may_branch(key)

    def may_branch(self, key: tuple) -> bool:
        """May an intention branch for an external belief event with this trigger key: is
        some sub-plan, at any depth, for that key or for any belief event (``+X``, which Jason
        tries for every such event once the intention has some other sub-plan for belief
        events)?  Such an event is kept even when no plan of the agent's own is relevant for
        it (see ``reasoning.branch_for_update``)."""
        bk = self.branch_keys
        return bool(bk) and (key in bk or (key[1] == BELIEF and key[2] is not None
                                           and (key[0], BELIEF, None, 0, False) in bk))

    def has_candidate(self, op: str, type_: str, lit: Any) -> bool:
        return bool(self.relevant(Trigger(op, type_, lit)))


def plan_term_trigger(t: PlanTerm) -> Trigger | None:
    """Interpret ``{+b}`` / ``{-b}`` / ``{+!g}`` plan terms (used by ``.wait``)."""
    if t.plan is not None:
        return t.plan.trigger
    if len(t.body) != 1:
        return None
    d = t.body[0]
    if d.kind == K_ADD_BEL:
        return Trigger(ADD, BELIEF, d.term)
    if d.kind == K_DEL_BEL:
        return Trigger(DEL, BELIEF, d.term)
    if isinstance(d.extra, Trigger):
        return d.extra
    return None


#: the plan Jason(ER) puts under the sub-plan that handles a belief event in a branch of an
#: intention (``reasoning.branch_for_update``): when that sub-plan ends, its first deed goes
#: as the deed of a finished subgoal does, and the second drops the branch
BRANCH_JOIN = Plan(None, Trigger(ADD, BELIEF, Literal("artificial_plan")), None,
                   (Deed(K_INTERNAL, Literal(".print", (Literal("dropwhenreturntohere"),)), 0),
                    Deed(K_INTERNAL, Literal(".drop_intention"), 0)), in_file=False)
