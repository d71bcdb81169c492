"""AgentSpeak (Jason 3 dialect) parser: a lark LALR grammar, compiled ahead of time into
:mod:`rason.asl.asl_tables` and run by :mod:`rason.asl.lalr` (no lark at run time).

Every error is raised as :class:`AslSyntaxError` (``file:line:col: message``).
"""

from __future__ import annotations

import builtins
import itertools
import os
import posixpath
import sys
import threading
from collections.abc import Callable
from typing import Any, NamedTuple

from . import asl_tables
from .containers import from_wire
from .functions import register_function
from .lalr import (
    LalrParser,
    NestedTooDeep,
    Token,
    UnexpectedCharacters,
    UnexpectedInput,
    UnexpectedToken,
)
from .limits import (
    MAX_PARSE_STACK,
    MAX_SOURCE_CHARS,
    MAX_TERM_CHARS,
    MAX_TERM_DEPTH,
    deeper_than,
    too_deep,
    too_long,
)
from .plain import read_plain_term
from .plans import (
    ACHIEVE,
    ADD,
    ANON_LABEL,
    BELIEF,
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
    K_TEST,
    K_WHILE,
    TEST,
    Deed,
    Plan,
    Trigger,
    body_str,
)
from .terms import (
    LOCAL_NS_PREFIX,
    TRUE,
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
    is_constant,
    is_internal_action,
    merge_annots,
    term_str,
)


class AslSyntaxError(Exception):
    """A syntax error in AgentSpeak source; ``str()`` is ``file:line:col: message``."""

    def __init__(self, file: str, line: int, col: int, message: str) -> None:
        self.file = file
        self.line = line
        self.col = col
        self.message = message
        super().__init__(f"{file}:{line}:{col}: {message}")


#: The lexical rules that Jason's ``.asl`` and ``.mas2j`` languages share: numbers, strings,
#: comments and white space (appended to both grammars).
LEXICON = r"""
NUMBER: /[0-9]+(\.[0-9]+)?([eE][+-]?[0-9]+)?/
STRING: /"(\\.|[^"\\])*"/
COMMENT: /\/\/[^\n]*/
BLOCK_COMMENT: /\/\*(.|\n)*?\*\//
%import common.WS
%ignore WS
%ignore COMMENT
%ignore BLOCK_COMMENT
"""

GRAMMAR = r"""
start: item*
?item: belief | rule | init_goal | plan | directive | sub_plans
sub_plans: "{" sub_item* "}"
?sub_item: plan | sub_plans
belief: literal "."
rule: literal ":-" log_expr "."
init_goal: "!" literal "."
plan: [label] trigger [context] [goal_condition] [plan_body] "."
goal_condition: "<:" log_expr
directive: "{" literal "}"
         | "{" ATOM literal "}"    -> directive_block
label: "@" literal              -> label
     | "@" annots               -> label_anon
     | "@" var                  -> label_var
context: ":" log_expr
plan_body: BODY_ARROW stmt_list
BODY_ARROW: "<-"
trigger: top [goaltype] literal_or_var
!top: "+" | "-" | "^"
!goaltype: "!" | "?"

stmt_list: par
         | par ";"
         | par ";" stmt_list
         | ctrl
         | ctrl ";"
         | ctrl stmt_list
         | ctrl ";" stmt_list

?par: par_and
    | par_and "|||" par        -> s_fork_or
?par_and: simple
        | simple "|&|" par_and -> s_fork_and

simple: "!" literal_or_var     -> s_achieve
      | "!!" literal_or_var    -> s_achieve_new
      | "?" log_expr_nor       -> s_test
      | "-+" literal_or_var    -> s_del_add
      | "++" literal_or_var    -> s_add_new
      | "--" literal_or_var    -> s_del_new
      | log_expr               -> s_expr
      | "(" fork ")"           -> s_group
?fork: par_and "|||" par       -> s_fork_or
     | simple "|&|" par_and    -> s_fork_and

ctrl: "if" "(" log_expr ")" block elif_part* [else_part]  -> s_if
    | "while" "(" log_expr ")" block                      -> s_while
    | "for" "(" log_expr ")" block                        -> s_for
elif_part: "elif" "(" log_expr ")" block
else_part: "else" block
block: "{" [stmt_list] "}"

?log_expr: log_and
         | log_and "|" log_expr   -> or_
?log_expr_nor: log_and
?log_and: log_not
        | log_not "&" log_and     -> and_
?log_not: rel_expr
        | "not" log_not           -> not_
?rel_expr: arith
         | arith relop arith      -> rel
!relop: "<=" | ">=" | "<" | ">" | "==" | "\\==" | "=.." | "="
?arith: term_
      | arith addop term_        -> arith_bin
!addop: "+" | "-"
?term_: power
      | term_ mulop power        -> arith_bin
!mulop: "*" | "/" | "div" | "mod"
?power: unary
      | unary "**" power         -> pow_
?unary: primary
      | "-" unary                -> neg
      | "+" unary                -> pos
?primary: NUMBER                 -> number
        | STRING                 -> string
        | literal_or_var
        | list
        | "(" log_expr ")"
        | "{" [stmt_list] "}"     -> plan_term
        | "{" stmt_list ":-" log_expr "}"                    -> rule_term
        | "{" stmt_list context [plan_body] "}"              -> plan_term_belief
        | "{" stmt_list plan_body "}"                        -> plan_term_belief_noctx
        | "{" "+" goaltype literal_or_var [context] [plan_body] "}"  -> plan_term_add_goal
        | "{" "-" goaltype literal_or_var [context] [plan_body] "}"  -> plan_term_del_goal
        | "{" "^" goaltype literal_or_var [context] [plan_body] "}"  -> plan_term_state_goal
        | "{" label trigger [context] [plan_body] "}"               -> plan_term_labelled

?literal_or_var: literal | var
var: VAR [annots]
literal: [NEG] [NS] ATOM [args] [annots]
       | VNS [NEG] ATOM [args] [annots]   -> ns_var_literal
       | (NS | VNS) VAR                   -> ns_var
NS.2: /([a-z][A-Za-z0-9_]*)?::/
VNS.2: /[A-Z_][A-Za-z0-9_]*::/
NEG: "~"
args: "(" log_expr ("," log_expr)* ")"
annots: "[" [elems] "]"
      | "[" "|" log_and "]"       -> annots_tail
list: "[" [elems] "]"
elems: log_and ("," log_and)* ["|" log_and]

ATOM: /\.?[a-z][A-Za-z0-9_]*(\.[a-zA-Z][A-Za-z0-9_]*)*/ | /'(\\.|[^'\\\n])*'/
VAR: /[A-Z_][A-Za-z0-9_]*/
""" + LEXICON

_parser: LalrParser | None = None


def user_cache_folder() -> str | None:
    """The folder where what is costly to make is kept between runs (``$XDG_CACHE_HOME/rason``,
    else ``~/.cache/rason``), or None when it cannot be made."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    folder = os.path.join(base, "rason")
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError:
        return None
    return folder


def grammar_cache_path(grammar: str) -> str | None:
    """Where the LALR tables built from ``grammar`` are kept between runs (None: nowhere).
    Lark checks the grammar's digest stored inside, so a stale file is rebuilt."""
    import hashlib  # here: only the .mas2j reader needs it, and its import costs an agent's start

    folder = user_cache_folder()
    if folder is None:
        return None
    digest = hashlib.sha256(grammar.encode("utf-8")).hexdigest()[:16]
    return os.path.join(folder, f"lark-{digest}-py{sys.version_info[0]}{sys.version_info[1]}.cache")


def cached_lark(grammar: str, transformer: Any = None) -> Any:
    """A lark LALR parser for ``grammar`` (placeholders for ``[x]``), its tables loaded from
    :func:`grammar_cache_path` when an earlier run built them (about 10x faster than building
    them). Without ``transformer`` it makes trees with positions; with one, the transformer's
    methods build the result while the parser reduces (no tree). The ``.mas2j`` reader uses it;
    lark is imported on the first call (an agent's start does without it)."""
    from lark import Lark  # here: importing lark costs a third of an agent's start

    path = grammar_cache_path(grammar)
    return Lark(grammar, parser="lalr", propagate_positions=transformer is None, maybe_placeholders=True,
                cache=path if path is not None else False, transformer=transformer)


def _get_parser() -> LalrParser:
    """The agent language's parser (made once; its tables must be those of ``GRAMMAR``)."""
    global _parser
    if _parser is None:
        if asl_tables.GRAMMAR != GRAMMAR:
            raise RuntimeError("rason.asl.asl_tables is stale: regenerate it with "
                               "python -m rason.asl.lalr_gen (see rason/asl/lalr_gen.py)")
        _parser = LalrParser(asl_tables, _BUILDER, max_stack=MAX_PARSE_STACK)
    return _parser


def _unescape(raw: str, exact: bool = False) -> str:
    """The text of a quoted string (or atom). As Jason, ``\\n`` and the escaped quote (``\\"``
    or ``\\'``) are translated and every other backslash stays; ``exact`` (text written by
    :func:`~rason.asl.terms.term_text`) also translates ``\\\\``."""
    quote = raw[0]
    body = raw[1:-1]
    out = []
    i = 0
    n = len(body)
    while i < n:
        c = body[i]
        if c == "\\" and i + 1 < n:
            nx = body[i + 1]
            if nx == "n":
                out.append("\n")
            elif nx == quote or (exact and nx == "\\"):
                out.append(nx)
            else:
                out.append(c + nx)
            i += 2
            continue
        out.append(c)
        i += 1
    return "".join(out)


class AgentSource:
    """The parsed content of one ``.asl`` file (a plain class: see :class:`.arch.Message`)."""

    def __init__(self, beliefs: list[Literal | Rule] | None = None,
                 goals: list[Literal] | None = None, plans: list[Plan] | None = None,
                 filename: str = "<string>") -> None:
        self.beliefs: list[Literal | Rule] = beliefs if beliefs is not None else []
        self.goals: list[Literal] = goals if goals is not None else []
        self.plans: list[Plan] = plans if plans is not None else []
        self.filename = filename

    def __eq__(self, other: object) -> bool:
        if other.__class__ is not self.__class__:
            return NotImplemented
        return ((self.beliefs, self.goals, self.plans, self.filename)
                == (other.beliefs, other.goals, other.plans, other.filename))

    __hash__ = None  # type: ignore[assignment]  # mutable and compared by value

    def __repr__(self) -> str:
        return (f"AgentSource(beliefs={self.beliefs!r}, goals={self.goals!r}, "
                f"plans={self.plans!r}, filename={self.filename!r})")


class _Anon:
    def __init__(self) -> None:
        self.counter = itertools.count(1)


class _Meta(NamedTuple):
    """Where a grammar rule's text starts (its first token's line and column; 0 if unknown)."""

    line: int = 0
    column: int = 0


_NO_POSITION = _Meta()


class _ToAst:
    """The rules of the grammar as the objects they make; every method receives where the
    rule's text starts and its children (see :class:`_ReduceBuilder`)."""

    def __init__(self, filename: str, exact: bool = False) -> None:
        self.filename = filename
        self.src = filename
        self.exact = exact
        #: the text has ``::lit`` or ``this_ns``, filled in with the namespace in effect once the
        #: items are known (see :func:`_fill_namespace`)
        self.abstract_ns = False
        #: the line of the ``:`` / ``<:`` / ``<-`` that starts a context, goal condition or
        #: body, by the id of the object made from it (a plan's ``code_line``, see :meth:`plan`)
        self.opened_at: dict[int, int] = {}

    # ---------------- terms
    def number(self, meta: Any, c: builtins.list) -> float:
        return float(c[0])

    def string(self, meta: Any, c: builtins.list) -> str:
        return _unescape(str(c[0]), self.exact)

    def var(self, meta: Any, c: builtins.list) -> Any:
        name = str(c[0])
        v = Var(fresh_name()) if name == "_" else Var(name)
        annots = c[1]
        if annots is not None and (annots[0] or annots[1] is not None):
            # Jason's as2j ``var``: a variable may carry annotations, X[source(A)]
            return AnnotVar(v.name, merge_annots((), annots[0]), annots[1])
        return v

    def args(self, meta: Any, c: builtins.list) -> tuple:
        return tuple(c)

    def elems(self, meta: Any, c: builtins.list) -> tuple:
        # last element is the tail (maybe None)
        return (tuple(c[:-1]), c[-1])

    def annots(self, meta: Any, c: builtins.list) -> tuple:
        if c[0] is None:
            return ((), None)
        return c[0]

    def annots_tail(self, meta: Any, c: builtins.list) -> tuple:
        """``p[|T]``: no annotations but a tail (how such a literal prints)."""
        return ((), c[0])

    def list(self, meta: Any, c: builtins.list) -> ListTerm:
        if c[0] is None:
            return ListTerm()
        items, tail = c[0]
        return ListTerm(items, tail)

    def literal(self, meta: Any, c: builtins.list) -> Literal:
        neg, ns, atom, args, annots = c
        # a namespace is kept as a prefix of the functor; ``::lit`` is the current namespace (the
        # block's, as a literal without one; outside blocks the default one, as ``default::``)
        if ns is not None and str(ns) not in ("default::", "::"):
            atom = str(ns) + str(atom)
        elif ns is not None and str(ns) == "::":
            atom = "::" + str(atom)   # the namespace in effect, filled in by _fill_namespace
            self.abstract_ns = True
        elif not args and annots is None and str(atom) == "this_ns":
            self.abstract_ns = True
        annots_t: tuple = ()
        tail = None
        if annots is not None:
            annots_t, tail = annots
            annots_t = merge_annots((), annots_t)
        name = str(atom)
        if self.exact and name[0] == "'":   # Jason keeps the quotes in the functor
            name = _unescape(name, exact=True)
        lit = Literal(name, args or (), annots_t, tail, neg is not None)
        is_constant(lit)  # cache: resolving a constant literal is free
        return lit

    def ns_var_literal(self, meta: Any, c: builtins.list) -> NsLit:
        """``N::b(X)``: a literal whose namespace is the variable N."""
        vns, neg, atom, args, annots = c
        name = str(vns)[:-2]
        lit = self.literal(meta, [neg, None, atom, args, annots])
        return NsLit(Var(fresh_name()) if name == "_" else Var(name), lit)

    def ns_var(self, meta: Any, c: builtins.list) -> Any:
        """``N::X`` / ``ns::X``: a variable in a namespace (plain ``X`` in the default one)."""
        ns_text, var = str(c[0])[:-2], str(c[1])
        v = Var(fresh_name()) if var == "_" else Var(var)
        if ns_text in ("", "default"):
            return v
        ns = Var(ns_text) if ns_text[0].isupper() or ns_text[0] == "_" else Literal(ns_text)
        return NsLit(ns, v)

    def or_(self, meta: Any, c: builtins.list) -> LogExpr:
        return LogExpr("|", c[0], c[1])

    def and_(self, meta: Any, c: builtins.list) -> LogExpr:
        return LogExpr("&", c[0], c[1])

    def not_(self, meta: Any, c: builtins.list) -> LogExpr:
        return LogExpr("not", c[0])

    def relop(self, meta: Any, c: builtins.list) -> str:
        return str(c[0])

    addop = relop
    mulop = relop

    def top(self, meta: Any, c: builtins.list) -> Token:
        """The token itself (it has its own position; its readers take ``str()``)."""
        return c[0]

    goaltype = top

    def rel(self, meta: Any, c: builtins.list) -> RelExpr:
        return RelExpr(str(c[1]), c[0], c[2])

    def arith_bin(self, meta: Any, c: builtins.list) -> ArithExpr:
        return ArithExpr(str(c[1]), c[0], c[2])

    def pow_(self, meta: Any, c: builtins.list) -> ArithExpr:
        return ArithExpr("**", c[0], c[1])

    def neg(self, meta: Any, c: builtins.list) -> Any:
        x = c[0]
        if isinstance(x, float):
            return -x
        return ArithExpr("neg", x)

    def pos(self, meta: Any, c: builtins.list) -> Any:
        return ("+pos", c[0])

    def plan_term(self, meta: Any, c: builtins.list) -> PlanTerm:
        body = tuple(c[0]) if c and c[0] is not None else ()
        return PlanTerm(body, body_str(body))

    def _plan_term(self, meta: Any, label: Any, trigger: Trigger, context: Any, body: Any) -> PlanTerm:
        plan = Plan(label, trigger, context, tuple(body or ()), meta.line, self.src, in_file=False)
        return plan.as_term()

    def _goal_plan_term(self, meta: Any, op: str, c: builtins.list) -> PlanTerm:
        """``{+!g : c <- b}`` / ``{-?g ...}``: an unlabelled goal plan as a term."""
        gt = ACHIEVE if str(c[0]) == "!" else TEST
        return self._plan_term(meta, None, Trigger(op, gt, _fix(c[1])), c[2], c[3])

    def plan_term_add_goal(self, meta: Any, c: builtins.list) -> PlanTerm:
        return self._goal_plan_term(meta, ADD, c)

    def plan_term_state_goal(self, meta: Any, c: builtins.list) -> PlanTerm:
        return self._goal_plan_term(meta, GOAL_STATE, c)

    def rule_term(self, meta: Any, c: builtins.list) -> PlanTerm:
        """``{ head :- body }``: a rule as a term (for ``+``, ``.add_plan``, ``.relevant_rules``)."""
        body, cond = c
        if (len(body) != 1 or body[0].kind not in (K_ACTION, K_INTERNAL)
                or not isinstance(body[0].term, Literal)):
            raise _SemErr(meta, "wrong place for a rule")
        rule = Rule(body[0].term, _fix(cond))
        return PlanTerm((), str(rule), rule=rule)

    def _belief_plan_term(self, meta: Any, body: builtins.list, context: Any, plan_body: Any) -> PlanTerm:
        """``{ +b : c <- body }`` / ``{ -b <- body }``: a plan whose trigger is a belief."""
        if len(body) != 1 or body[0].kind not in (K_ADD_BEL, K_DEL_BEL):
            raise _SemErr(meta, "a plan term needs a trigger (+b, -b, +!g...)")
        op = ADD if body[0].kind == K_ADD_BEL else DEL
        return self._plan_term(meta, None, Trigger(op, BELIEF, body[0].term), context, plan_body)

    def plan_term_belief(self, meta: Any, c: builtins.list) -> PlanTerm:
        return self._belief_plan_term(meta, c[0], c[1], c[2])

    def plan_term_belief_noctx(self, meta: Any, c: builtins.list) -> PlanTerm:
        return self._belief_plan_term(meta, c[0], None, c[1])

    def plan_term_del_goal(self, meta: Any, c: builtins.list) -> PlanTerm:
        return self._goal_plan_term(meta, DEL, c)

    def plan_term_labelled(self, meta: Any, c: builtins.list) -> PlanTerm:
        return self._plan_term(meta, *c)

    # ---------------- body
    def stmt_list(self, meta: Any, c: builtins.list) -> builtins.list:
        out: builtins.list = []
        for x in c:
            if isinstance(x, list):
                out.extend(x)
            elif x is not None:
                out.append(x)
        return out

    def s_fork_and(self, meta: Any, c: builtins.list) -> Deed:
        return _fork_deed("and", c[0], c[1], meta.line)

    def s_fork_or(self, meta: Any, c: builtins.list) -> Deed:
        return _fork_deed("or", c[0], c[1], meta.line)

    def s_group(self, meta: Any, c: builtins.list) -> Deed:
        """``( a ||| b )``: a fork in parentheses, a deed of the body around it."""
        return c[0]

    def s_achieve(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_ACHIEVE, c[0], meta.line)

    def s_achieve_new(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_ACHIEVE_NEW, c[0], meta.line)

    def s_test(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_TEST, _fix(c[0]), meta.line)

    def s_del_add(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_DEL_ADD_BEL, c[0], meta.line)

    def s_add_new(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_ADD_BEL_NEW, c[0], meta.line)

    def s_del_new(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_DEL_BEL_NEW, c[0], meta.line)

    def s_expr(self, meta: Any, c: builtins.list) -> Deed | builtins.list:
        t = c[0]
        if isinstance(t, tuple) and t and t[0] == "+pos" and isinstance(t[1], PlanTerm):
            return _plan_term_deed(t[1], ADD, meta.line)
        if isinstance(t, ArithExpr) and t.op == "neg" and isinstance(t.left, PlanTerm):
            return _plan_term_deed(t.left, DEL, meta.line)
        if isinstance(t, tuple) and t and t[0] == "+pos" and isinstance(t[1], _BELIEF_TERMS):
            return Deed(K_ADD_BEL, t[1], meta.line)
        if isinstance(t, ArithExpr) and t.op == "neg" and isinstance(t.left, _BELIEF_TERMS):
            return Deed(K_DEL_BEL, t.left, meta.line)
        if type(t) is PlanTerm and t.plan is None and t.rule is None:
            return builtins.list(t.body)    # ``{a; b}`` as a deed: its deeds in place (Jason)
        t = _fix(t)
        if isinstance(t, Literal):
            if is_internal_action(t.functor):
                return Deed(K_INTERNAL, t, meta.line)
            return Deed(K_ACTION, t, meta.line)
        if isinstance(t, (Var, AnnotVar, NsLit)):
            return Deed(K_ACTION, t, meta.line)
        if isinstance(t, (RelExpr, LogExpr)):
            return Deed(K_CONSTRAINT, t, meta.line)
        raise _SemErr(meta, "invalid body formula")

    def block(self, meta: Any, c: builtins.list) -> tuple:
        return tuple(c[0]) if c and c[0] is not None else ()

    def elif_part(self, meta: Any, c: builtins.list) -> tuple:
        return ("elif", _fix(c[0]), c[1])

    def else_part(self, meta: Any, c: builtins.list) -> tuple:
        return c[0]

    def s_if(self, meta: Any, c: builtins.list) -> Deed:
        branches = [(_fix(c[0]), c[1])]
        els = None
        for x in c[2:]:
            if x is None:
                continue
            if isinstance(x, tuple) and len(x) == 3 and x[0] == "elif":
                branches.append((x[1], x[2]))
            else:
                els = x
        return Deed(K_IF, branches[0][0], meta.line, (branches, els))

    def s_while(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_WHILE, _fix(c[0]), meta.line, c[1])

    def s_for(self, meta: Any, c: builtins.list) -> Deed:
        return Deed(K_FOR, _fix(c[0]), meta.line, c[1])

    # ---------------- top level
    def belief(self, meta: Any, c: builtins.list) -> tuple:
        return ("belief", _fix(c[0]), meta)

    def rule(self, meta: Any, c: builtins.list) -> tuple:
        return ("rule", Rule(_fix(c[0]), _fix(c[1])), meta)

    def init_goal(self, meta: Any, c: builtins.list) -> tuple:
        return ("goal", _fix(c[0]), meta)

    def label(self, meta: Any, c: builtins.list) -> Literal:
        return c[0]

    def label_anon(self, meta: Any, c: builtins.list) -> Literal:
        """``@[atomic]``: a label without a name (the plan library gives it one)."""
        annots, _tail = c[0]
        return Literal(ANON_LABEL, (), merge_annots((), annots))

    def label_var(self, meta: Any, c: builtins.list) -> Any:
        return c[0]

    def directive(self, meta: Any, c: builtins.list) -> tuple:
        d = _fix(c[0])
        if isinstance(d, Literal) and d.functor == "register_function":
            # at once, as Jason's parser does: the literals after it are read as the function
            _register_function(d, meta, self.filename)
        return ("directive", d, meta)

    def directive_block(self, meta: Any, c: builtins.list) -> tuple:
        """``{ begin namespace(ns) }`` (Jason: a directive opening a block closed by ``{ end }``)."""
        if str(c[0]) != "begin":
            raise _SemErr(meta, f"unexpected '{c[0]}' in a directive")
        return ("block", _fix(c[1]), meta)

    def context(self, meta: Any, c: builtins.list) -> Any:
        made = _fix(c[0])
        self.opened_at[id(made)] = meta.line
        return made

    def plan_body(self, meta: Any, c: builtins.list) -> tuple:
        made = tuple(c[1])   # (c[0]: the arrow, a token of its own so that meta is its line)
        self.opened_at[id(made)] = meta.line
        return made

    def trigger(self, meta: Any, c: builtins.list) -> Trigger:
        op = {"+": ADD, "-": DEL}.get(str(c[0]), GOAL_STATE)
        gt = BELIEF if c[1] is None else (ACHIEVE if str(c[1]) == "!" else TEST)
        return Trigger(op, gt, _fix(c[2]))

    def goal_condition(self, meta: Any, c: builtins.list) -> Any:
        self.opened_at[id(c[0])] = meta.line
        return c[0]

    def plan(self, meta: Any, c: builtins.list) -> tuple:
        label, trigger, context, goal_condition, body = c
        # Jason's code_line: the label's line, else that of what follows the trigger
        line = meta.line
        if label is None:
            after = next((x for x in (context, goal_condition, body) if x is not None), None)
            line = self.opened_at.get(id(after), line) if after is not None else line
        deeds = tuple(body or ())
        if deeds and deeds[0].kind == K_ACTION and deeds[0].term == TRUE:
            deeds = deeds[1:]   # as Jason's parser: a body's first deed `true` is no deed
        return ("plan", Plan(label, trigger, context, deeds, line, self.src,
                             goal_condition=goal_condition), meta)

    def sub_plans(self, meta: Any, c: builtins.list) -> tuple:
        """``{ plan... }`` after a plan: its sub-plans (Jason 3.3, from Jason(ER)), attached
        to the plan before by :func:`_attach_sub_plans`."""
        return ("sub_plans", _attach_sub_plans(c), meta)

    def start(self, meta: Any, c: builtins.list) -> builtins.list:
        return _attach_sub_plans(c)


class _ReduceBuilder:
    """The callbacks the LALR parser calls while it reduces a rule (no parse tree is made, which
    halves the cost of parsing): it hands each rule to the current :class:`_ToAst` with the
    rule's start position, the position of its first child (a token's own, else the one
    recorded for the child's object while this text is parsed). ``token_type``: the class of
    the parser's tokens (lark's, for the tests that compare with lark's parser)."""

    def __init__(self, token_type: Any = Token) -> None:
        self.token_type = token_type
        self.ast: _ToAst | None = None
        self.positions: dict[int, _Meta] = {}
        self.made: builtins.list = []      # keeps every made object alive: ids stay unique

    def __getattr__(self, rule: str) -> Callable[[builtins.list], Any]:
        if rule.startswith("_") or not hasattr(_ToAst, rule):
            raise AttributeError(rule)
        positions = self.positions
        made = self.made
        token_type = self.token_type

        def reduce(children: builtins.list) -> Any:
            meta = _NO_POSITION
            for child in children:
                if child is None:
                    continue
                if isinstance(child, token_type):
                    meta = _Meta(child.line or 0, child.column or 0)
                else:
                    meta = positions.get(id(child), _NO_POSITION)
                break
            result = getattr(self.ast, rule)(meta, children)
            positions[id(result)] = meta
            made.append(result)
            return result
        return reduce

    def parse(self, ast: _ToAst, text: str) -> Any:
        """``text`` parsed into ``ast``'s objects (one text at a time: see ``_PARSE_LOCK``)."""
        self.ast = ast
        try:
            return _get_parser().parse(text)
        finally:
            self.ast = None
            self.positions.clear()
            self.made.clear()


_BUILDER = _ReduceBuilder()
#: the builder's state belongs to one text at a time (agents may parse from several threads)
_PARSE_LOCK = threading.Lock()


def _plan_term_deed(t: PlanTerm, op: str, line: int) -> Deed:
    """``+{ rule }`` / ``-{ rule }`` change the rules; ``+{ plan }`` is ``.add_plan(P, self,
    begin)`` and ``-{ plan }`` is ``.remove_plan(P)`` (as Jason's parser makes them)."""
    if (t.plan is None and t.rule is None and len(t.body) == 1
            and t.body[0].kind in (K_ADD_BEL, K_DEL_BEL)):
        # +{ +b } is not a plan: keep the old reading of a braced body
        return Deed(K_ADD_BEL if op == ADD else K_DEL_BEL, t, line)
    if t.rule is not None:
        return Deed(K_ADD_BEL if op == ADD else K_DEL_BEL, t, line)
    if op == ADD:
        return Deed(K_INTERNAL, Literal(".add_plan", (t, Literal("self"), Literal("begin"))), line)
    return Deed(K_INTERNAL, Literal(".remove_plan", (t,)), line)


#: what ``+t`` / ``-t`` in a body may add or remove
_BELIEF_TERMS = (Literal, Var, AnnotVar, NsLit)


class _SemErr(Exception):
    def __init__(self, meta: Any, msg: str) -> None:
        super().__init__(msg)
        self.line = getattr(meta, "line", 0)
        self.col = getattr(meta, "column", 0)
        self.msg = msg


def _fix(t: Any) -> Any:
    """Turn leftover unary-plus markers into plain terms (``+X`` in an expression is ``X``)."""
    if isinstance(t, tuple) and t and t[0] == "+pos":
        return _fix(t[1])
    if isinstance(t, Literal):
        if any(isinstance(a, tuple) for a in t.args) or any(isinstance(a, tuple) for a in t.annots):
            return Literal(t.functor, tuple(_fix(a) for a in t.args),
                           tuple(_fix(a) for a in t.annots), t.tail, t.neg)
        return t
    if isinstance(t, ListTerm):
        if any(isinstance(a, tuple) for a in t.items):
            return ListTerm(tuple(_fix(a) for a in t.items), t.tail)
        return t
    if isinstance(t, AnnotVar):
        if any(isinstance(a, tuple) for a in t.annots):
            return AnnotVar(t.name, tuple(_fix(a) for a in t.annots), t.tail)
        return t
    if isinstance(t, (ArithExpr, LogExpr)):
        if isinstance(t.left, tuple) or isinstance(t.right, tuple):
            return type(t)(t.op, _fix(t.left), _fix(t.right))
        return t
    if isinstance(t, RelExpr):
        if isinstance(t.left, tuple) or isinstance(t.right, tuple):
            return RelExpr(t.op, _fix(t.left), _fix(t.right))
        return t
    return t


def describe_syntax_error(e: Exception) -> str:
    """One line saying what the parser (ours or lark's) found unexpected (and what it expected)."""
    kind = type(e).__name__
    if isinstance(e, UnexpectedCharacters) or kind == "UnexpectedCharacters":
        return f"unexpected character {e.char!r}"  # type: ignore[attr-defined]
    if kind == "UnexpectedEOF":
        return "unexpected end of file"
    if isinstance(e, UnexpectedToken) or kind == "UnexpectedToken":
        tok = e.token  # type: ignore[attr-defined]
        if tok.type == "$END":
            return "unexpected end of file"
        exp = sorted(e.expected)[:8]  # type: ignore[attr-defined]
        return f"unexpected {tok.type} {str(tok)!r}" + (f", expected one of {', '.join(exp)}" if exp else "")
    return str(e).splitlines()[0] if str(e) else "syntax error"


def _parse_items(text: str, filename: str, tr: _ToAst) -> Any:
    """The top-level items of ``text`` made by ``tr``; every error as :class:`AslSyntaxError`
    (a text longer than MAX_SOURCE_CHARS or nested deeper than MAX_TERM_DEPTH is one)."""
    if len(text) > MAX_SOURCE_CHARS:
        raise AslSyntaxError(filename, 1, 1, too_long(len(text), MAX_SOURCE_CHARS, "program"))
    try:
        with _PARSE_LOCK:
            return _BUILDER.parse(tr, text)
    except _SemErr as e:
        raise AslSyntaxError(filename, e.line, e.col, e.msg) from None
    except UnexpectedInput as e:
        line = getattr(e, "line", -1)
        col = getattr(e, "column", -1)
        if line is None or line < 1:
            line = text.count("\n") + 1
            col = len(text) - (text.rfind("\n") + 1) + 1
        if isinstance(e, NestedTooDeep):
            raise AslSyntaxError(filename, line, col, too_deep()) from None
        raise AslSyntaxError(filename, line, col, describe_syntax_error(e)) from None
    except RecursionError:
        raise AslSyntaxError(filename, 1, 1, "program nested too deeply") from None


#: Resolves an ``include`` directive: (file as written, including file) -> (path, text, src name).
IncludeResolver = Callable[[str, str], tuple[str, str, str]]

#: environment variable naming a Jason jar or a Jason source tree, where ``$jasonJar/...`` is
JASON_JAR_ENV = "RASON_JASON_JAR"
#: the prefix of a path Jason resolves inside its own jar
JASON_JAR_PREFIX = "$jasonJar/"


def jason_jar_places(path: str) -> list[str]:
    """Where ``$jasonJar/ENTRY`` may be, given :data:`JASON_JAR_ENV` (none without it): the
    jar's entry (``jar:file:JAR!/ENTRY``) when it names a file; when it names a folder, the
    folder's ``ENTRY``, then where Jason's build takes the jar's entries from in its source
    tree (``jason-interpreter/src/ENTRY`` for the test includes,
    ``jason-interpreter/src/main/resources/ENTRY`` for the rest)."""
    home = os.environ.get(JASON_JAR_ENV, "")
    if not home or not path.startswith(JASON_JAR_PREFIX):
        return []
    entry = path[len(JASON_JAR_PREFIX):]
    if os.path.isfile(home):
        return [f"jar:file:{os.path.abspath(home)}!/{entry}"]
    src = os.path.join(home, "jason-interpreter", "src")
    return [os.path.join(home, entry), os.path.join(src, entry),
            os.path.join(src, "main", "resources", entry)]


def path_include_resolver(search_path: list[str]) -> IncludeResolver:
    """Jason's include lookup (``SourcePath.fixPath``): the file as written (``file:`` before
    it or not), relative to the including file's folder, then to each folder of the source
    path (``aslSourcePath``); ``jar:file:JAR!/ENTRY`` reads the entry of that jar (a zip), and a
    file included from a jar looks beside itself in it first. A path Jason resolves inside its
    own jar (``$jasonJar/...``) or any other path not found is then looked up by its file name
    in the same folders, unless :data:`JASON_JAR_ENV` names a Jason jar or source tree that
    has it (:func:`jason_jar_places`). The src name (the plans' ``url``) is Jason's: ``file:``
    and the path found, relative to the current folder when it is inside it (a ``$`` path
    found by file name: as written)."""
    def resolve_include(name: str, including: str) -> tuple[str, str, str]:
        name = name.replace("\\", "/")
        if name.startswith("jar:"):
            return name, _jar_entry(name), name
        plain = name[len("file:"):] if name.startswith("file:") else name
        for place in jason_jar_places(plain):
            if place.startswith("jar:"):
                try:
                    return place, _jar_entry(place), place
                except OSError:
                    continue
            if os.path.isfile(place):
                with open(place, encoding="utf-8") as f:
                    return place, f.read(), "file:" + _url_path(place)
        folders = []
        if including.startswith("jar:") and "!/" in including:
            jar, entry = including.split("!/", 1)
            inside = f"{jar}!/{posixpath.join(posixpath.dirname(entry), plain)}"
            try:
                return inside, _jar_entry(inside), inside
            except OSError:
                pass
        elif including and not including.startswith("<"):
            folders.append(os.path.dirname(os.path.abspath(including.removeprefix("file:"))))
        folders.extend(search_path)
        candidates = [plain]
        rel = plain.split("/", 1)[1] if plain.startswith("$") and "/" in plain else plain
        candidates += [os.path.join(d, rel) for d in folders if not os.path.isabs(rel)]
        for cand in candidates:
            if os.path.isfile(cand):
                with open(cand, encoding="utf-8") as f:
                    return cand, f.read(), name if plain.startswith("$") else "file:" + _url_path(cand)
        for cand in (os.path.join(d, os.path.basename(plain)) for d in folders):
            if os.path.isfile(cand):     # found by its file name only: named as written
                with open(cand, encoding="utf-8") as f:
                    return cand, f.read(), name
        raise FileNotFoundError(name)
    return resolve_include


def _url_path(path: str) -> str:
    """A found file's path as Jason's url has it: relative to the current folder when inside
    it (Jason joins the relative folders it was given), else absolute."""
    full = os.path.abspath(path)
    rel = os.path.relpath(full)
    return full if rel.startswith("..") else rel


def _jar_entry(url: str) -> str:
    """The text of ``jar:file:JAR!/ENTRY`` (``OSError`` when the jar or the entry is missing)."""
    jar, sep, entry = url[len("jar:"):].partition("!/")
    if not sep or not jar.startswith("file:"):
        raise FileNotFoundError(url)
    # imported here: zipfile brings pathlib, urllib.parse, shutil, bz2 and lzma (about 5 ms of
    # an empty agent's start), and only ``{ include }`` from inside a jar needs it
    import zipfile

    try:
        with zipfile.ZipFile(jar[len("file:"):]) as z:
            return z.read(entry).decode("utf-8")
    except (KeyError, zipfile.BadZipFile) as err:
        raise FileNotFoundError(url) from err


def parse_source(text: str, filename: str = "<string>", src: str | None = None,
                 exact: bool = False, include: IncludeResolver | None = None,
                 _depth: int = 0, namespace: str | None = None,
                 _max_depth: int = MAX_TERM_DEPTH) -> AgentSource:
    """Parse a whole ``.asl`` program (``exact``: text written by ``term_text``, see
    :func:`parse_term_text`); ``include`` finds the files of ``{ include("f.asl") }``
    directives (default: relative to ``filename``'s folder); ``namespace``: the one its
    literals without a namespace go to (a file included in a namespace). A text longer than
    MAX_SOURCE_CHARS, or holding a term nested deeper than MAX_TERM_DEPTH, is refused
    (:mod:`rason.asl.limits`)."""
    tr = _ToAst(filename, exact)
    if src is not None:
        tr.src = src
    items = _parse_items(text, filename, tr)
    out = AgentSource(filename=filename)
    # the namespace of each open { begin ... } block (the file's own first)
    blocks: list[str | None] = [namespace if namespace != "default" else None]
    local: dict[str, str] = {}        # this file's local namespaces -> their unique names
    # a term nested N deep takes N characters at least: short texts need no look
    look_deep = len(text) > _max_depth
    for kind, obj, meta in items:
        if look_deep and _nested_too_deep(kind, obj, _max_depth):
            raise AslSyntaxError(filename, meta.line, meta.column, too_deep())
        ns = next((b for b in reversed(blocks) if b is not None), None)
        if kind in ("block", "directive"):
            _declare_namespace(obj, local)
        if kind == "block":
            block_ns = _block_namespace(obj)
            blocks.append(local.get(block_ns, block_ns) if block_ns is not None else None)
            continue
        if kind == "directive" and isinstance(obj, Literal) and obj.functor == "end" and not obj.args:
            if len(blocks) > 1:
                blocks.pop()
            continue
        if tr.abstract_ns and kind != "directive":
            obj = _fill_namespace(kind, obj, ns or "default")
        if local and kind != "directive":
            obj = _rename_namespaces(kind, obj, local)
        if ns is not None and kind != "directive":
            obj = in_namespace(kind, obj, ns)
        if kind == "belief":
            if not isinstance(obj, Literal):
                raise AslSyntaxError(filename, meta.line, meta.column, "a belief must be a literal")
            out.beliefs.append(obj)
        elif kind == "rule":
            if not isinstance(obj.head, Literal):
                raise AslSyntaxError(filename, meta.line, meta.column, "a rule head must be a literal")
            out.beliefs.append(obj)
        elif kind == "goal":
            if not isinstance(obj, Literal):
                raise AslSyntaxError(filename, meta.line, meta.column, "an initial goal must be a literal")
            out.goals.append(obj)
        elif kind == "directive":
            _directive(out, obj, meta, filename, include, _depth, ns)
        else:
            out.plans.append(obj)
    return out


def _attach_sub_plans(items: builtins.list) -> builtins.list:
    """``items`` with each ``{ plan... }`` block made the sub-plans of the plan before it (a
    block after anything else is a syntax error, as in Jason)."""
    out: builtins.list = []
    for item in items:
        if item[0] != "sub_plans":
            out.append(item)
            continue
        if not out or out[-1][0] != "plan":
            raise _SemErr(item[2], "sub-plans ({ ... }) must follow a plan")
        kind, plan, meta = out[-1]
        out[-1] = (kind, plan.with_sub_plans(tuple(p for _, p, _ in item[1])), meta)
    return out


def _nested_too_deep(kind: str, obj: Any, limit: int) -> bool:
    """Does a parsed item (a belief, rule, goal, plan...) hold a term deeper than `limit`?"""
    if kind != "plan":
        return deeper_than(obj, limit)
    found: builtins.list[Any] = []

    def look(t: Any) -> Any:
        if not found and deeper_than(t, limit):
            found.append(t)
        return t
    obj.map_terms(look)
    return bool(found)


def _fork_deed(kind: str, left: Deed | builtins.list, right: Deed | builtins.list, line: int) -> Deed:
    """``A |&| B`` / ``A ||| B``: ``.fork(and|or, {A}, {B})``, as Jason's parser makes it (a
    chain of the same operator is one fork, each operand one formula, or the deeds of a
    plan-body term ``{a; b}``); the branches print without braces, as Jason's."""
    def branch(d: Deed | builtins.list) -> PlanTerm:
        deeds = tuple(d) if isinstance(d, builtins.list) else (d,)
        return PlanTerm(deeds, body_str(deeds), braces=False)
    branches = [branch(left)]
    rt = right.term if isinstance(right, Deed) else None
    if (isinstance(right, Deed) and right.kind == K_INTERNAL and isinstance(rt, Literal)
            and rt.functor == ".fork" and rt.args and rt.args[0] == Literal(kind)):
        branches.extend(rt.args[1:])
    else:
        branches.append(branch(right))
    return Deed(K_INTERNAL, Literal(".fork", (Literal(kind), *branches)), line)


def _block_namespace(d: Any) -> str | None:
    """The namespace a ``{ begin namespace(ns) }`` block puts its literals in (``default``:
    none), or None for another block."""
    if (isinstance(d, Literal) and d.functor == "namespace" and d.args
            and isinstance(d.args[0], Literal) and not d.args[0].args):
        name = d.args[0].functor
        return "" if name == "default" else name
    return None


#: numbers the local namespaces of every file parsed in this process (Jason's counter)
_LOCAL_NS_IDS = itertools.count(1)


def _declare_namespace(d: Any, local: dict[str, str]) -> None:
    """``namespace(ns, local)`` (a directive or a block's): ``ns`` is private to this file, under
    a unique name (``#1ns``); ``namespace(ns, global)`` makes it shared again."""
    if not (isinstance(d, Literal) and d.functor == "namespace" and len(d.args) == 2
            and isinstance(d.args[0], Literal) and isinstance(d.args[1], Literal)):
        return
    name, scope = d.args[0].functor, d.args[1].functor
    if scope == "local" and name not in local:
        local[name] = f"{LOCAL_NS_PREFIX}{next(_LOCAL_NS_IDS)}{name}"
    elif scope == "global":
        local.pop(name, None)


def _local_names(t: Any, local: dict[str, str]) -> Any:
    """``t`` with each literal of a local namespace under that namespace's unique name."""
    if isinstance(t, Literal):
        functor = t.functor
        ns, sep, name = functor.partition("::")
        if sep and ns in local:
            functor = f"{local[ns]}::{name}"
        if functor == t.functor and not t.args and not t.annots:
            return t
        return Literal(functor, tuple(_local_names(a, local) for a in t.args),
                       tuple(_local_names(a, local) for a in t.annots), t.tail, t.neg)
    if isinstance(t, NsLit):
        ns_term = t.ns
        if isinstance(ns_term, Literal) and ns_term.functor in local:
            ns_term = Literal(local[ns_term.functor])
        return NsLit(ns_term, _local_names(t.lit, local))
    if isinstance(t, ListTerm):
        return ListTerm(tuple(_local_names(a, local) for a in t.items), t.tail)
    if isinstance(t, (ArithExpr, LogExpr, RelExpr)):
        return type(t)(t.op, _local_names(t.left, local),
                       None if t.right is None else _local_names(t.right, local))
    if isinstance(t, PlanTerm):
        return t.map_terms(lambda x: _local_names(x, local))
    return t


def _rename_namespaces(kind: str, obj: Any, local: dict[str, str]) -> Any:
    """A belief, rule, goal or plan with its local namespaces renamed (:func:`_local_names`)."""
    if kind == "rule":
        return Rule(_local_names(obj.head, local), _local_names(obj.body, local))
    if kind == "plan":
        renamed = obj.map_terms(lambda x: _local_names(x, local))
        renamed.atomic = obj.atomic
        return renamed
    return _local_names(obj, local)


def _ns_formula(t: Any, ns: str) -> Any:
    """A formula's literals in namespace ``ns`` (those without one of their own; internal
    actions, their arguments and the terms of relations stay as they are)."""
    if isinstance(t, Literal):
        if not ns or "." in t.functor or "::" in t.functor or t.functor in ("true", "false"):
            return t
        return Literal(f"{ns}::{t.functor}", t.args, t.annots, t.tail, t.neg)
    if isinstance(t, LogExpr):
        return LogExpr(t.op, _ns_formula(t.left, ns), None if t.right is None else _ns_formula(t.right, ns))
    return t


_NS_DEEDS = frozenset({K_ACHIEVE, K_ACHIEVE_NEW, K_TEST, K_ADD_BEL, K_DEL_BEL, K_DEL_ADD_BEL,
                       K_ADD_BEL_NEW, K_DEL_BEL_NEW, K_WHILE, K_FOR})


def _ns_deeds(body: tuple, ns: str) -> tuple:
    out = []
    for d in body:
        if d.kind == K_IF:
            branches, els = d.extra
            extra = ([(_ns_formula(c, ns), _ns_deeds(b, ns)) for c, b in branches],
                     None if els is None else _ns_deeds(els, ns))
            d = Deed(d.kind, d.term, d.line, extra)
        elif d.kind in _NS_DEEDS:
            extra = _ns_deeds(d.extra, ns) if d.kind in (K_WHILE, K_FOR) else d.extra
            d = Deed(d.kind, _ns_formula(d.term, ns), d.line, extra)
        elif (d.kind == K_INTERNAL and ns and isinstance(d.term, Literal) and d.term.functor == ".include"
              and len(d.term.args) == 1):
            # as Jason's: .include in a namespace includes the file in that namespace
            d = Deed(K_INTERNAL, Literal(".include", (d.term.args[0], Literal(ns))), d.line)
        out.append(d)
    return tuple(out)


def _fill_ns(t: Any, ns: str, in_relation: bool = False) -> Any:
    """``t`` with ``::lit`` in namespace ``ns`` and, as Jason's parser, the atom ``this_ns``
    made ``ns`` (not inside a relation such as ``X = this_ns``, where Jason keeps it)."""
    if isinstance(t, Literal):
        functor = t.functor
        if functor.startswith("::"):
            functor = functor[2:] if ns == "default" else ns + functor
        elif functor == "this_ns" and not t.args and not t.annots and not in_relation:
            return Literal(ns)
        lit = Literal(functor, tuple(_fill_ns(a, ns, in_relation) for a in t.args),
                      tuple(_fill_ns(a, ns, in_relation) for a in t.annots), t.tail, t.neg)
        is_constant(lit)
        return lit
    if isinstance(t, ListTerm):
        return ListTerm(tuple(_fill_ns(a, ns, in_relation) for a in t.items),
                        None if t.tail is None else _fill_ns(t.tail, ns, in_relation))
    if isinstance(t, RelExpr):
        return RelExpr(t.op, _fill_ns(t.left, ns, True), _fill_ns(t.right, ns, True))
    if isinstance(t, (ArithExpr, LogExpr)):
        return type(t)(t.op, _fill_ns(t.left, ns, in_relation),
                       None if t.right is None else _fill_ns(t.right, ns, in_relation))
    if isinstance(t, NsLit):
        return NsLit(t.ns, _fill_ns(t.lit, ns, in_relation))
    if isinstance(t, PlanTerm):
        return t.map_terms(lambda x: _fill_ns(x, ns, in_relation))
    return t


def _fill_namespace(kind: str, obj: Any, ns: str) -> Any:
    """A belief, rule, goal or plan with ``::lit`` and ``this_ns`` in namespace ``ns`` (the
    one in effect where it is written: the file's or the block's, else ``default``)."""
    if kind == "rule":
        return Rule(_fill_ns(obj.head, ns), _fill_ns(obj.body, ns))
    if kind == "plan":
        return obj.map_terms(lambda t: _fill_ns(t, ns))
    return _fill_ns(obj, ns)


def in_namespace(kind: str, obj: Any, ns: str) -> Any:
    """A belief, rule, initial goal or plan of a ``{ begin namespace(ns) }`` block: its literals
    (beliefs, rule heads and bodies, triggers, contexts, goals and belief changes of bodies)
    in ``ns``, as Jason's parser puts them."""
    if kind in ("belief", "goal"):
        return _ns_formula(obj, ns)
    if kind == "rule":
        return Rule(_ns_formula(obj.head, ns), _ns_formula(obj.body, ns))
    if kind == "plan":
        trig = obj.trigger
        return Plan(obj.label, Trigger(trig.op, trig.type, _ns_formula(trig.literal, ns)),
                    _ns_formula(obj.context, ns), _ns_deeds(obj.body, ns), obj.line, obj.src,
                    atomic=obj.atomic, in_file=obj.in_file,
                    goal_condition=_ns_formula(obj.goal_condition, ns),
                    sub_plans=tuple(in_namespace(kind, p, ns) for p in obj.sub_plans))
    return obj


#: Jason's directives that need no action here (namespaces are kept as functor prefixes)
_IGNORED_DIRECTIVES = frozenset({"begin", "end", "namespace"})


def include_namespace(arg: Any) -> str:
    """The namespace ``include(File, NS)`` puts the file in: NS itself, or for a variable a new
    one (``ns<n>``, numbered as local namespaces are)."""
    if isinstance(arg, Literal) and not arg.args:
        return arg.functor
    return f"ns{next(_LOCAL_NS_IDS)}"


def parse_include(name: str, including: str, include: IncludeResolver | None,
                  namespace: str | None, depth: int = 0) -> AgentSource:
    """The program of an included file (``OSError`` when not found, :class:`AslSyntaxError`)."""
    resolver = include or path_include_resolver([])
    path, text, src_name = resolver(name, including)
    return parse_source(text, path, src=src_name, include=include, _depth=depth + 1,
                        namespace=namespace)


def _directive(out: AgentSource, d: Any, meta: Any, filename: str, include: IncludeResolver | None,
               depth: int, namespace: str | None) -> None:
    """Apply a directive ``{ name(args) }``: ``include`` merges the other file in place (in the
    namespace of its second argument, else the one in effect)."""
    if not isinstance(d, Literal):
        raise AslSyntaxError(filename, meta.line, meta.column, "invalid directive")
    if d.functor == "include" and d.args and isinstance(d.args[0], str):
        if depth > 20:
            raise AslSyntaxError(filename, meta.line, meta.column, "include nested too deeply")
        ns = include_namespace(d.args[1]) if len(d.args) > 1 else namespace
        try:
            inner = parse_include(d.args[0], filename, include, ns, depth)
        except OSError:
            raise AslSyntaxError(filename, meta.line, meta.column,
                                 f"the included file '{d.args[0]}' was not found") from None
        out.beliefs.extend(inner.beliefs)
        out.goals.extend(inner.goals)
        out.plans.extend(inner.plans)
        return
    if d.functor == "register_function":
        return   # applied when it was read (_ToAst.directive)
    if d.functor not in _IGNORED_DIRECTIVES:
        print(f"{filename}:{meta.line}: warning: directive {term_str(d)} is not known here; ignored",
              file=sys.stderr)


def _register_function(d: Literal, meta: Any, filename: str) -> None:
    """``{ register_function("name", Arity, "rule") }``: ``name(A1..An)`` becomes an arithmetic
    function whose value is the last argument of the rule's first solution (Jason's
    ``FunctionRegister``); the one-argument form names a Java class, which cannot be loaded.
    A wrong directive is reported, as Jason logs it, and the file is read on."""
    args = d.args
    if (len(args) == 3 and isinstance(args[0], str) and type(args[1]) is float
            and args[1] == int(args[1]) and isinstance(args[2], str)):
        try:
            register_function(args[0], int(args[1]), rule=args[2])
        except ValueError as e:
            print(f"{filename}:{meta.line}: warning: {e}", file=sys.stderr)
        return
    why = ("names a Java class, which cannot be loaded here" if len(args) == 1
           else 'expects ("name", Arity, "rule")')
    print(f"{filename}:{meta.line}: warning: directive {term_str(d)} {why}; ignored", file=sys.stderr)


def parse_term(text: str, exact: bool = False) -> Any:
    """Parse one term (e.g. ``f(X, [1,2])``) as Jason reads source text; raises
    :class:`AslSyntaxError`. ``exact``: see :func:`parse_term_text`."""
    if not isinstance(text, str):
        raise AslSyntaxError("<term>", 1, 1, "not a string")
    if len(text) > MAX_TERM_CHARS:
        raise AslSyntaxError("<term>", 1, 1, too_long(len(text), MAX_TERM_CHARS, "term"))
    plain = read_plain_term(text)
    if plain is not None:
        return plain
    return parse_term_by_grammar(text, exact)


def parse_term_by_grammar(text: str, exact: bool = False) -> Any:
    """:func:`parse_term` without the plain-term reader (the reference it is tested against)."""
    # the term is t__'s argument, one level down: the same limit as the plain reader's
    src = parse_source(f"t__({text}).", "<term>", exact=exact, _max_depth=MAX_TERM_DEPTH + 1)
    if len(src.beliefs) != 1 or not isinstance(src.beliefs[0], Literal) or len(src.beliefs[0].args) != 1 \
            or src.beliefs[0].functor != "t__" or src.beliefs[0].annots:
        raise AslSyntaxError("<term>", 1, 1, f"not a single term: {text!r}")
    return src.beliefs[0].args[0]


def parse_term_text(text: str) -> Any:
    """The term written by :func:`~rason.asl.terms.term_text` (how terms travel between
    processes): quoted atoms lose their quotes and ``\\\\`` is one backslash, so every term
    reads back equal to the one written; sets, maps and queues come back as such."""
    t = parse_term(text, exact=True)
    return from_wire(t) if "$" in text else t


def parse_literal(text: str) -> Literal:
    """Parse one literal such as ``robot(faulty,-3.5,1.2,88)``; raises :class:`AslSyntaxError`."""
    t = parse_term(text)
    if not isinstance(t, Literal):
        raise AslSyntaxError("<literal>", 1, 1, f"not a literal: {text!r}")
    return t


__all__ = [
    "AgentSource",
    "AslSyntaxError",
    "Token",
    "parse_literal",
    "parse_source",
    "parse_term",
    "parse_term_text",
]
