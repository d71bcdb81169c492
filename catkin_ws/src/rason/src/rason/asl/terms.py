"""AgentSpeak terms (Jason's ``jason.asSyntax``) and their Jason-exact printing.

Representation (chosen for speed):

* numbers are Python ``float`` (every Jason number is a double);
* strings are Python ``str``;
* :class:`Var`, :class:`Literal` (atoms, structures, annotations, ``~``),
  :class:`ListTerm`, :class:`ArithExpr`, :class:`RelExpr`, :class:`LogExpr`,
  :class:`PlanTerm` are small immutable classes.
"""

from __future__ import annotations

import itertools
import math
import re
from typing import Any, Union

from .functions import ARITH_NAMES

Term = Union[float, str, "Var", "AnnotVar", "Literal", "NsLit", "ListTerm", "ArithExpr", "RelExpr",
             "LogExpr", "PlanTerm"]

_fresh = itertools.count(1)


def fresh_name() -> str:
    """A new unique variable name (like Jason's ``_123``)."""
    return f"_{next(_fresh)}"


class Var:
    """A logic variable; bindings live in a substitution dict keyed by name."""

    __slots__ = ("name",)

    def __init__(self, name: str) -> None:
        self.name = name

    def __reduce__(self) -> tuple:
        return (Var, (self.name,))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Var) and other.name == self.name

    def __hash__(self) -> int:
        return hash(("V", self.name))

    def __repr__(self) -> str:
        return self.name


class AnnotVar:
    """A variable written with annotations, e.g. ``X[source(A)]`` or ``C[a|T]`` (Jason: a
    ``VarTerm`` with annotations). Kept apart from :class:`Var` so that plain variables stay
    as cheap as before; the unifier (:func:`~.unify.unify`), :func:`~.unify.resolve` and the
    queries (:func:`~.logic.solve`) know it. ``annots`` are sorted as a literal's."""

    __slots__ = ("annots", "name", "tail")

    def __init__(self, name: str, annots: tuple, tail: Any = None) -> None:
        self.name = name
        self.annots = annots
        self.tail = tail

    def __reduce__(self) -> tuple:
        return (AnnotVar, (self.name, self.annots, self.tail))

    def __eq__(self, other: object) -> bool:
        return (isinstance(other, AnnotVar) and other.name == self.name
                and other.annots == self.annots and other.tail == self.tail)

    def __hash__(self) -> int:
        return hash(("AV", self.name, self.annots))

    def __repr__(self) -> str:
        return term_str(self)


class Literal:
    """An atom or structure, possibly negated (``~``) and annotated (``[a|T]``)."""

    __slots__ = ("_h", "annots", "args", "functor", "known_constant", "known_ground", "neg", "tail")

    def __init__(self, functor: str, args: tuple = (), annots: tuple = (),
                 tail: Any = None, neg: bool = False) -> None:
        self.functor = functor
        self.args = args
        self.annots = annots
        self.tail = tail
        self.neg = neg
        self._h: int | None = None
        #: caches filled on first use by :func:`is_ground` and :func:`is_constant` (None: not
        #: yet known); the parser and plan compilation fill them for program literals
        self.known_ground: bool | None = None
        self.known_constant: bool | None = None

    def __reduce__(self) -> tuple:
        """Pickled as what it is made from (the caches are filled anew)."""
        return (Literal, (self.functor, self.args, self.annots, self.tail, self.neg))

    @property
    def arity(self) -> int:
        return len(self.args)

    @property
    def key(self) -> tuple:
        """Index key of a belief: functor, arity, negation (hot paths build it inline)."""
        return (self.functor, len(self.args), self.neg)

    def with_annots(self, annots: tuple, tail: Any = None) -> Literal:
        return Literal(self.functor, self.args, annots, tail, self.neg)

    def no_annots(self) -> Literal:
        if not self.annots and self.tail is None:
            return self
        return Literal(self.functor, self.args, (), None, self.neg)

    def add_annots(self, extra: list | tuple) -> Literal:
        """Return a copy with ``extra`` merged into the (sorted, duplicate-free) annotations."""
        return Literal(self.functor, self.args, merge_annots(self.annots, extra), self.tail, self.neg)

    def with_self_source(self) -> Literal:
        """This literal with ``source(self)`` added, unless it names a source already."""
        return self if self.has_source() else self.add_annots([SOURCE_SELF])

    def has_source(self) -> bool:
        for a in self.annots:  # noqa: SIM110 - a plain loop is faster on this hot path
            if type(a) is Literal and a.functor == "source" and len(a.args) == 1:
                return True
        return False

    def sources(self) -> list:
        return [a.args[0] for a in self.annots
                if isinstance(a, Literal) and a.functor == "source" and len(a.args) == 1]

    def __eq__(self, other: object) -> bool:
        if self is other:
            return True
        return (isinstance(other, Literal) and self.functor == other.functor
                and self.neg == other.neg and self.args == other.args
                and self.annots == other.annots and self.tail == other.tail)

    def __hash__(self) -> int:
        if self._h is None:
            self._h = hash((self.functor, self.args, self.annots, self.neg))
        return self._h

    def __repr__(self) -> str:
        return term_str(self)

    def __str__(self) -> str:
        return term_str(self)


class NsLit:
    """A literal whose namespace is a variable, ``N::b(X)`` (Jason: a literal whose namespace is
    a ``VarTerm``), or a variable in a namespace, ``N::X`` / ``ns::X``. ``lit`` is the literal
    (or variable) without namespace. Once both are known, :func:`~.unify.resolve` gives the
    plain literal in that namespace; until then it unifies with a literal of any namespace
    but a local one (:func:`split_ns`), taking its namespace and the literal without it."""

    __slots__ = ("lit", "ns")

    def __init__(self, ns: Var | Literal, lit: Literal | Var) -> None:
        self.ns = ns
        self.lit = lit

    def __reduce__(self) -> tuple:
        return (NsLit, (self.ns, self.lit))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, NsLit) and other.ns == self.ns and other.lit == self.lit

    def __hash__(self) -> int:
        return hash(("NS", self.ns, self.lit))

    def __repr__(self) -> str:
        return term_str(self)


#: the prefix of a local namespace's unique name (``{ begin namespace(ns, local) }``)
LOCAL_NS_PREFIX = "#"


def split_ns(lit: Literal) -> tuple[str, Literal]:
    """A literal's namespace (``default`` when it has none) and the literal without it."""
    ns, sep, name = lit.functor.partition("::")
    if not sep:
        return "default", lit
    return ns, Literal(name, lit.args, lit.annots, lit.tail, lit.neg)


def in_ns(ns: str, lit: Literal) -> Literal:
    """``lit`` (without namespace) in namespace ``ns`` (``default``: none)."""
    if ns == "default":
        return lit
    return Literal(f"{ns}::{lit.functor}", lit.args, lit.annots, lit.tail, lit.neg)


def is_internal_action(functor: str) -> bool:
    """Jason's rule: a literal whose (unquoted) functor has a dot is an internal action, from
    the standard library (``.print``) or a user's (``my.act``, see ``stdlib.internal_action``)."""
    return "." in functor and functor[0] != "'"


def atom(name: str) -> Literal:
    return Literal(name)


TRUE = Literal("true")
FALSE = Literal("false")
SELF = Literal("self")
PERCEPT = Literal("percept")


def source(ag: str | Literal) -> Literal:
    return Literal("source", (ag if isinstance(ag, Literal) else Literal(ag),))


SOURCE_SELF = source(SELF)
SOURCE_PERCEPT = source(PERCEPT)


class ListTerm:
    """A list ``[a, b | T]``; ``tail`` is ``None`` for a proper list."""

    __slots__ = ("items", "tail")

    def __init__(self, items: tuple = (), tail: Any = None) -> None:
        self.items = items
        self.tail = tail

    def __reduce__(self) -> tuple:
        return (ListTerm, (self.items, self.tail))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, ListTerm) and self.items == other.items and self.tail == other.tail

    def __hash__(self) -> int:
        return hash(("L", self.items, self.tail))

    def __repr__(self) -> str:
        return term_str(self)


EMPTY_LIST = ListTerm()


class _Expr:
    """An operator applied to one or two terms (shared by the expression classes)."""

    __slots__ = ("left", "op", "right")
    _tag = ""

    def __init__(self, op: str, left: Any, right: Any = None) -> None:
        self.op = op
        self.left = left
        self.right = right

    def __reduce__(self) -> tuple:
        return (type(self), (self.op, self.left, self.right))

    def __eq__(self, other: object) -> bool:
        return (type(other) is type(self) and self.op == other.op
                and self.left == other.left and self.right == other.right)

    def __hash__(self) -> int:
        return hash((self._tag, self.op, self.left, self.right))

    def __repr__(self) -> str:
        return term_str(self)


class ArithExpr(_Expr):
    """Arithmetic expression; ``op`` in ``+ - * / div mod **`` or unary ``neg``."""

    __slots__ = ()
    _tag = "A"


class RelExpr(_Expr):
    """Relational expression: ``< <= > >= == \\== = =..``."""

    __slots__ = ()
    _tag = "R"


class LogExpr(_Expr):
    """Logical expression: ``&``, ``|`` or ``not`` (``right`` is None for ``not``)."""

    __slots__ = ()
    _tag = "G"


class PlanTerm:
    """A plan/plan-body term in braces, e.g. ``{ p(1) }``, ``{+stop}`` or a whole plan
    ``{ @l +!g : c <- .print(a) }`` (then ``plan`` is the :class:`~.plans.Plan`; a plan with
    neither label, context nor body is Jason's trigger term ``{+!g}``), or a rule
    ``{ p(X) :- q(X) }`` (then ``rule`` is the :class:`Rule`).

    The plan and the deeds of ``body`` are objects of :mod:`.plans`; this class only uses
    what every one of them offers: ``map_terms(fn)`` and ``str()``.
    """

    __slots__ = ("body", "braces", "jason", "known_ground", "plan", "rule", "text")

    def __init__(self, body: tuple, text: str, plan: Any = None, rule: Any = None,
                 braces: bool = True) -> None:
        self.body = body
        #: printed in braces; a body part taken by unification (``{ A; _ }``) prints without,
        #: as Jason's PlanBody that is not a body term
        self.braces = braces
        self.text = text
        self.plan = plan
        self.rule = rule
        self.known_ground: bool | None = None   # ground (no variable inside), computed on first use
        self.jason: str | None = None   # the text Jason prints (:meth:`jason_text`), made on first use

    def __reduce__(self) -> tuple:
        return (PlanTerm, (self.body, self.text, self.plan, self.rule, self.braces))

    def same_key(self) -> str:
        """What makes two plan terms equal: as Jason's ``Plan.equals``, a plan's trigger,
        context and body, not its label."""
        p = self.plan
        if p is None:
            return self.text
        return p.as_text(label=False)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, PlanTerm) and self.same_key() == other.same_key()

    def __hash__(self) -> int:
        return hash(("P", self.same_key()))

    def __repr__(self) -> str:
        return term_str(self)

    def jason_text(self) -> str:
        """The text Jason prints inside the braces (:func:`term_str`), made once, as
        :attr:`text` is; :attr:`text` is rason's source text of the same term, read back by
        rason's parser (messages between nodes)."""
        if self.jason is None:
            if self.rule is not None or (self.plan is None and not self.body):
                self.jason = self.text
            elif self.plan is not None:
                self.jason = self.plan.as_text(jason=True)
            else:
                self.jason = "; ".join(d.jason_str() for d in self.body)
        return self.jason

    @classmethod
    def of_body(cls, deeds: tuple) -> PlanTerm:
        """A body part as a term, printed without braces (a tail taken by ``{ A; _ }``)."""
        return cls(deeds, "; ".join(str(d) for d in deeds), braces=False)

    def map_terms(self, fn: Any) -> PlanTerm:
        """This term with ``fn`` applied to every term inside (resolving, renaming); itself
        when nothing changed."""
        if self.rule is not None:
            head, body = fn(self.rule.head), fn(self.rule.body)
            if head == self.rule.head and body == self.rule.body:
                return self
            rule = Rule(head, body)
            return PlanTerm((), str(rule), rule=rule)
        if self.plan is None:
            deeds = tuple(d.map_terms(fn) for d in self.body)
            text = "; ".join(str(d) for d in deeds)
            return self if text == self.text else PlanTerm(deeds, text, braces=self.braces)
        plan = self.plan.map_terms(fn)
        text = plan.as_text()
        return self if text == self.text else PlanTerm(plan.body, text, plan, braces=self.braces)


class Rule:
    """``head :- body.``"""

    __slots__ = ("body", "head")

    def __init__(self, head: Literal, body: Any) -> None:
        self.head = head
        self.body = body

    def __reduce__(self) -> tuple:
        return (Rule, (self.head, self.body))

    def __str__(self) -> str:
        return term_str(self.head) + " :- " + term_str(self.body)

    def __repr__(self) -> str:
        return f"Rule({self.head!r}, {self.body!r})"


# ---------------------------------------------------------------- printing

_LONG_MAX = 2 ** 63


def format_number(x: float) -> str:
    """Jason's number printing: integral doubles as longs, else Java ``Double.toString``."""
    if x != x:
        return "NaN"
    if x in (math.inf, -math.inf):
        return "Infinity" if x > 0 else "-Infinity"
    # Jason prints Math.round(x) (a Java long, clamped) when it converts back to x exactly
    if x == math.floor(x):
        if -_LONG_MAX <= x < _LONG_MAX:
            return str(int(x))
        if x == float(_LONG_MAX):
            return str(_LONG_MAX - 1)
    return java_double_str(x)


def java_double_str(x: float) -> str:
    """Java's ``Double.toString``: ``5.0``, ``0.001``, ``1.0E7``, ``1.0E-4``."""
    if x != x:
        return "NaN"
    if x in (math.inf, -math.inf):
        return "Infinity" if x > 0 else "-Infinity"
    if x == 0 or 1e-3 <= abs(x) < 1e7:
        return repr(x)
    # the shortest digits that read back as x (repr's), in Java's scientific form
    mantissa, _, exp = repr(abs(x)).partition("e")
    whole, _, frac = mantissa.partition(".")
    digits = whole + frac
    point = len(whole) + (int(exp) if exp else 0)   # x = 0.digits * 10**point
    stripped = digits.lstrip("0")
    point -= len(digits) - len(stripped)
    ds = stripped.rstrip("0") or "0"
    return ("-" if x < 0 else "") + ds[0] + "." + (ds[1:] or "0") + "E" + str(point - 1)


def _annots_str(annots: tuple, tail: Any, jason: bool = True) -> str:
    if not annots and tail is None:
        return ""
    inner = ",".join(term_str(a, jason) for a in annots)
    if tail is not None:
        inner += "|" + term_str(tail, jason) if inner else term_str(tail, jason)
    return "[" + inner + "]"


#: an atom that needs no quotes (the parser's unquoted ATOM), and words the parser reads as keywords
_PLAIN_ATOM = re.compile(r"\.?[a-z][A-Za-z0-9_]*(\.[a-zA-Z][A-Za-z0-9_]*)*")
_KEYWORDS = frozenset({"not", "div", "mod"})


def atom_text(name: str) -> str:
    """A functor as exact source text: as is when the parser reads it back as that atom, else
    quoted (``'Robot'``, ``'a b'``, ``'it\\'s'``)."""
    if _PLAIN_ATOM.fullmatch(name) and name not in _KEYWORDS:
        return name
    return "'" + name.replace("\\", "\\\\").replace("'", "\\'").replace("\n", "\\n") + "'"


def string_text(s: str) -> str:
    """A string as exact source text: quoted, with ``\\``, ``\"`` and ``\\n`` escaped."""
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'


_ARITH_SYM = {"+": "+", "-": "-", "*": "*", "/": "/", "div": " div ", "mod": " mod ", "**": "**"}


def term_str(t: Any, jason: bool = True) -> str:
    """Jason's ``toString`` of a term (strings keep their quotes). Plan terms print as Jason
    prints them (``if``/``for``/``while`` as ``.if_then_else``/``.foreach``/``.loop``, the
    branches of ``|&|``/``|||`` without braces); with ``jason=False`` they print as rason's
    source text instead (:meth:`PlanTerm.text`), which rason's parser reads back."""
    if isinstance(t, float):
        return format_number(t)
    if isinstance(t, Literal):
        s = ("~" if t.neg else "") + t.functor
        if t.args:
            s += "(" + ",".join(term_str(a, jason) for a in t.args) + ")"
        if t.annots or t.tail is not None:
            s += _annots_str(t.annots, t.tail, jason)
        return s
    if isinstance(t, str):
        return '"' + t + '"'
    if isinstance(t, Var):
        return t.name
    if isinstance(t, AnnotVar):
        return t.name + _annots_str(t.annots, t.tail, jason)
    if isinstance(t, NsLit):
        return term_str(t.ns, jason) + "::" + term_str(t.lit, jason)
    if isinstance(t, ListTerm):
        inner = ",".join(term_str(a, jason) for a in t.items)
        if t.tail is not None:
            inner += "|" + term_str(t.tail, jason)
        return "[" + inner + "]"
    if isinstance(t, ArithExpr):
        if t.op == "neg":
            return "(-" + term_str(t.left, jason) + ")"
        return "(" + term_str(t.left, jason) + _ARITH_SYM[t.op] + term_str(t.right, jason) + ")"
    if isinstance(t, RelExpr):
        return "(" + term_str(t.left, jason) + " " + t.op + " " + term_str(t.right, jason) + ")"
    if isinstance(t, LogExpr):
        if t.op == "not":
            return "not (" + term_str(t.left, jason) + ")"
        return "(" + term_str(t.left, jason) + " " + t.op + " " + term_str(t.right, jason) + ")"
    if isinstance(t, PlanTerm):
        text = t.jason_text() if jason else t.text
        if t.braces:
            return "{ " + text + " }"
        # a labelled plan out of braces is Jason's Plan (made by ``=..``), printed with its dot
        return text + "." if t.plan is not None and t.plan.label is not None else text
    if isinstance(t, int):
        return format_number(float(t))
    return str(t)


def term_text(t: Any) -> str:
    """Exact source text of a data term (numbers, strings, atoms, structures, lists, variables):
    :func:`~rason.asl.parser.parse_term_text` reads it back as an equal term. It differs from
    Jason's ``toString`` (:func:`term_str`) only where that one cannot be read back: strings
    with quotes, backslashes or line breaks, functors that need quotes, a lone annotation tail.
    Non-finite numbers have no such text (they print as ``NaN``/``Infinity``)."""
    if isinstance(t, float):
        return format_number(t)
    if isinstance(t, str):
        return string_text(t)
    if isinstance(t, Literal):
        s = ("~" if t.neg else "") + atom_text(t.functor)
        if t.args:
            s += "(" + ",".join(term_text(a) for a in t.args) + ")"
        if t.annots or t.tail is not None:
            s += "[" + ",".join(term_text(a) for a in t.annots)
            s += ("|" + term_text(t.tail) if t.tail is not None else "") + "]"
        return s
    if isinstance(t, ListTerm):
        inner = ",".join(term_text(a) for a in t.items)
        if t.tail is not None:
            inner += "|" + term_text(t.tail)
        return "[" + inner + "]"
    if isinstance(t, AnnotVar):
        s = t.name + "[" + ",".join(term_text(a) for a in t.annots)
        return s + ("|" + term_text(t.tail) if t.tail is not None else "") + "]"
    wire = getattr(t, "wire", None)   # a set, map or queue (rason.asl.containers)
    if wire is not None:
        return term_text(wire())
    return term_str(t, False)


def non_finite_part(t: Any) -> str | None:
    """The first part of ``t`` that stands for a number that is not finite: a NaN or infinite
    float, or the variables Jason's text of one reads as (``NaN``, ``Infinity``); else None.
    Percepts and messages holding one are rejected: a robot must not act on them."""
    tt = type(t)
    if tt is float:
        return None if math.isfinite(t) else format_number(t)
    if tt is Var or tt is AnnotVar:
        return t.name if t.name in ("NaN", "Infinity") else None
    if tt is Literal:
        parts: Any = itertools.chain(t.args, t.annots, () if t.tail is None else (t.tail,))
    elif tt is ListTerm:
        parts = itertools.chain(t.items, () if t.tail is None else (t.tail,))
    elif tt in (ArithExpr, RelExpr, LogExpr):
        parts = (t.left,) if t.right is None else (t.left, t.right)
    else:
        return None
    for p in parts:
        bad = non_finite_part(p)
        if bad is not None:
            return bad
    return None


def to_print_str(t: Any) -> str:
    """How ``.print`` renders one argument: top-level strings lose their quotes."""
    if isinstance(t, str):
        return t
    return term_str(t)


def merge_annots(annots: tuple, extra: list | tuple) -> tuple:
    """Union of two annotation lists, sorted in Jason's term order, without duplicates."""
    if not extra:
        return annots
    if not annots and len(extra) == 1:
        return (extra[0],)
    if len(extra) == 1 and extra[0] in annots:
        return annots
    out = list(annots)
    for a in extra:
        if a not in out:
            out.append(a)
    out.sort(key=sort_key)
    return tuple(out)


def with_nested_source(t: Any, sender: Any) -> Any:
    """jason.stdlib.add_nested_source: the literal's sources go inside ``source(Sender)``:
    ``v[source(a)]`` from b is ``v[source(b)[source(a)]]`` (each literal of a list too)."""
    if isinstance(t, ListTerm):
        return ListTerm(tuple(with_nested_source(x, sender) for x in t.items), t.tail)
    if isinstance(t, Literal):
        old = [a for a in t.annots if isinstance(a, Literal) and a.functor == "source"]
        rest = tuple(a for a in t.annots if not (isinstance(a, Literal) and a.functor == "source"))
        src = Literal("source", (sender,), merge_annots((), old))
        return t.with_annots(merge_annots(rest, [src]), t.tail)
    return t


# ---------------------------------------------------------------- ordering

def sort_key(t: Any) -> tuple:
    """Jason's standard order of terms: numbers, strings, lists, literals, then variables.

    Lists compare item by item (a shorter prefix first); literals by namespace, functor, ``~``
    (plain first), then arguments one by one (so ``f(a,a) < f(z)``: arity decides only when
    one argument list is a prefix of the other), then annotations the same way. Named
    variables come before unnamed ones; other terms (expressions, plans) by their text."""
    if isinstance(t, float):
        return (0, t)
    if isinstance(t, str):
        return (1, t)
    if isinstance(t, ListTerm):
        keys = [sort_key(a) for a in t.items]
        tail = t.tail
        while isinstance(tail, ListTerm):
            keys.extend(sort_key(a) for a in tail.items)
            tail = tail.tail
        if tail is not None:
            keys.append(sort_key(tail))
        return (2, tuple(keys))
    if isinstance(t, Literal):
        ns, sep, name = t.functor.partition("::")
        if not sep:   # the default namespace (namespaces compare first)
            ns, name = "default", t.functor
        return (3, ns, name, t.neg, tuple(sort_key(a) for a in t.args),
                tuple(sort_key(a) for a in t.annots))
    if isinstance(t, (Var, AnnotVar)):
        m = _UNNAMED.fullmatch(t.name)
        return (5, 1, int(m.group(1)), "") if m else (5, 0, 0, t.name)
    return (4, term_str(t))


_UNNAMED = re.compile(r"_(\d+)")


def is_constant(t: Any) -> bool:
    """True if applying a substitution cannot change ``t`` (no variables, no arithmetic)."""
    tt = type(t)
    if tt is float or tt is str:
        return True
    if tt is Literal:
        c = t.known_constant
        if c is None:
            c = t.known_constant = (t.tail is None and t.functor not in ARITH_NAMES
                        and all(is_constant(a) for a in t.args) and all(is_constant(a) for a in t.annots))
        return c
    if tt is ListTerm:
        return t.tail is None and all(is_constant(a) for a in t.items)
    return False


def calls_code(t: Any) -> bool:
    """True when `t` holds a term that runs code when evaluated: an internal action or a
    function (``.count(...)``, ``math.abs(X)``), a plan or rule term, or a namespaced literal."""
    if type(t) is Literal:
        return ("." in t.functor or any(calls_code(a) for a in t.args)
                or any(calls_code(a) for a in t.annots))
    if type(t) is ListTerm:
        return any(calls_code(a) for a in t.items) or calls_code(t.tail)
    if isinstance(t, _Expr):
        return calls_code(t.left) or calls_code(t.right)
    return isinstance(t, (PlanTerm, NsLit))


def is_ground(t: Any) -> bool:
    """True if the term has no variables (expressions are checked recursively)."""
    if isinstance(t, (float, str)):
        return True
    if isinstance(t, Var):
        return False
    if isinstance(t, Literal):
        g = t.known_ground
        if g is None:
            g = t.known_ground = (t.tail is None and all(is_ground(a) for a in t.args)
                        and all(is_ground(a) for a in t.annots))
        return g
    if isinstance(t, ListTerm):
        return all(is_ground(a) for a in t.items) and (t.tail is None or is_ground(t.tail))
    if isinstance(t, (ArithExpr, RelExpr, LogExpr)):
        return is_ground(t.left) and (t.right is None or is_ground(t.right))
    if isinstance(t, PlanTerm):
        if t.known_ground is None:
            all_ground = True

            def note(x: Any) -> Any:
                nonlocal all_ground
                all_ground = all_ground and is_ground(x)
                return x
            t.map_terms(note)
            t.known_ground = all_ground
        return t.known_ground
    return not isinstance(t, (AnnotVar, NsLit))


def list_to_python(t: Any) -> list | None:
    """Items of a proper (resolved) list term, or None if ``t`` is not a proper list."""
    if not isinstance(t, ListTerm):
        return None
    items = list(t.items)
    while t.tail is not None:
        t = t.tail
        if not isinstance(t, ListTerm):
            return None
        items.extend(t.items)
    return items


def make_list(items: list | tuple) -> ListTerm:
    return ListTerm(tuple(items))


def java_string_hash(s: str) -> int:
    """Java's ``String.hashCode`` of ``s`` (as an unsigned 32-bit number)."""
    h = 0
    data = s.encode("utf-16-be")
    for k in range(0, len(data), 2):
        h = (31 * h + (data[k] << 8 | data[k + 1])) & 0xFFFFFFFF
    return h


def java_map_order(items: list, key: Any, capacity: int = 0) -> list:
    """The iteration order of a Java ``HashMap``/``ConcurrentHashMap<String, ...>`` holding
    ``items`` (inserted in list order): by bucket of the spread string hash, then insertion
    order. The table has 16 buckets, doubled while more than 3/4 full, unless ``capacity``
    gives its size. Jason keeps pending intentions/events (PI, PE) and unifiers in such maps."""
    n = capacity or 16
    while not capacity and len(items) > n * 3 // 4:
        n *= 2

    def bucket(it: Any) -> int:
        h = java_string_hash(key(it))
        return ((h ^ (h >> 16)) & 0x7FFFFFFF) & (n - 1)
    return sorted(items, key=bucket)


def java_unifier_text(u: dict) -> str:
    """A copy of the unifier ``u`` as Jason prints it (``Unifier.toString`` of a clone, the
    hidden argument of a running ``.loop``/``.foreach``): ``{X=0, Y=f(Z)}``, each binding as
    stored, in the order of the ``HashMap`` that ``HashMap.clone`` makes (a table sized for the
    entries it copies, filled in the order of the original)."""
    names = java_map_order([k for k in u if type(k) is str], str)
    if not names:
        return "{}"
    wanted = int(len(names) / 0.75 + 1.0)
    capacity = 1
    while capacity < wanted:
        capacity *= 2
    return "{" + ", ".join(f"{name}={term_str(u[name])}"
                           for name in java_map_order(names, str, capacity)) + "}"
