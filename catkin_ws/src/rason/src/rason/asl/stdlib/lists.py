"""List internal actions: ``.member .length .concat .nth .max .min .sort .reverse ...``."""

from __future__ import annotations

import functools
from typing import Any

from ..containers import MapTerm, QueueTerm, SetTerm
from ..ia import IAContext, IAError, internal_action, wrong_arg
from ..terms import ListTerm, Literal, Var, list_to_python, make_list, sort_key, term_str
from ..unify import compare_terms, unify
from .strings import java_replace_all


def _items(t: Any, what: str = "first argument must be a list") -> list:
    items = list_to_python(t)
    if items is None:
        raise wrong_arg(what)
    return items


@internal_action(".member", arity=2)
def member(ctx: IAContext, args: list) -> Any:
    coll = args[1]
    if isinstance(coll, (SetTerm, QueueTerm)):
        items = coll.items()
    else:
        items = _items(coll, "second argument must be a list or a set")

    def gen():
        for x in items:
            s2 = dict(ctx.s)
            if unify(args[0], x, s2):
                yield s2
    return gen()


@internal_action(".length", arity=2)
def length(ctx: IAContext, args: list) -> bool:
    if isinstance(args[0], (str, SetTerm, MapTerm, QueueTerm)):
        return ctx.unify(args[1], float(len(args[0])))
    items = list_to_python(args[0])
    if items is None:   # Jason: neither a list nor a string is just false
        return False
    return ctx.unify(args[1], float(len(items)))


def _plain(t: Any) -> str:
    """Jason's ``concat.getPlainValue``: strings unquoted, quoted atoms without their quotes."""
    if isinstance(t, str):
        return t
    s = term_str(t)
    if (isinstance(t, Literal) and not t.args and not t.annots and not t.neg and len(s) > 1
            and s[0] == "'" and s[-1] == "'"):
        return s[1:-1]
    return s


@internal_action(".concat")
def concat(ctx: IAContext, args: list) -> bool:
    """Lists when the first argument is a list (every other part must be one), else strings."""
    if len(args) < 2:
        raise IAError("wrong number of arguments", "wrong_arguments")
    parts, out = args[:-1], args[-1]
    if isinstance(parts[0], ListTerm):
        if not isinstance(out, (Var, ListTerm)):
            raise IAError(f"Last argument of concat '{term_str(out)}'is not a list nor a variable.",
                          "internal_action")
        res: list = list(_items(parts[0]))
        for k, p in enumerate(parts[1:], 1):
            items = list_to_python(p)
            if items is None:
                raise wrong_arg(f"arg[{k}] is not a list")
            res.extend(items)
        return ctx.unify(make_list(res), out)
    if not isinstance(out, (str, Var)):
        out = term_str(out)
    return ctx.unify("".join(_plain(p) for p in parts), out)


@internal_action(".nth", arity=3)
def nth(ctx: IAContext, args: list) -> Any:
    if not isinstance(args[0], (float, Var)):
        raise wrong_arg(f"the first argument should be numeric or a variable -- not '{term_str(args[0])}'.")
    items = _items(args[1], f"the second argument should be a list and not '{term_str(args[1])}'.")
    if isinstance(args[0], float):
        i = int(args[0])
        if 0 <= i < len(items):
            return ctx.unify(args[2], items[i])
        raise IAError(f"nth: index {i} is out of bounds ({len(items)})", "internal_action")

    def gen():
        for i, x in enumerate(items):
            s2 = dict(ctx.s)
            if unify(args[0], float(i), s2) and unify(args[2], x, s2):
                yield s2
    return gen()


def _plain_str(t: Any) -> str:
    return t if isinstance(t, str) else term_str(t)


def _cmp(a: Any, b: Any) -> int:
    return compare_terms(a, b)


@internal_action(".max", arity=2)
def max_(ctx: IAContext, args: list) -> bool:
    items = _items(args[0])
    if not items:
        return False
    return ctx.unify(args[1], max(items, key=functools.cmp_to_key(_cmp)))


@internal_action(".min", arity=2)
def min_(ctx: IAContext, args: list) -> bool:
    items = _items(args[0])
    if not items:
        return False
    return ctx.unify(args[1], min(items, key=functools.cmp_to_key(_cmp)))


@internal_action(".sort", arity=2)
def sort(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], make_list(sorted(_items(args[0]), key=sort_key)))


@internal_action(".reverse", arity=2)
def reverse(ctx: IAContext, args: list) -> bool:
    if isinstance(args[0], ListTerm):
        return ctx.unify(args[1], make_list(list(reversed(_items(args[0])))))
    return ctx.unify(args[1], _plain_str(args[0])[::-1])


@internal_action(".empty", arity=1)
def empty(ctx: IAContext, args: list) -> bool:
    if isinstance(args[0], str):
        return args[0] == ""
    return isinstance(args[0], ListTerm) and not _items(args[0])


@internal_action(".delete", arity=(3, 4))
def delete(ctx: IAContext, args: list) -> bool:
    """``.delete(X, L, R)``; a number X is a position, ``.delete(Start, End, L, R)`` a range.

    As in Jason, bindings made by the first element that unifies with X are kept for the
    following ones (``.delete(p(_), [p(1), p(2)], R)`` gives ``[p(2)]``).
    """
    if isinstance(args[0], float):
        nxt, start = 1, int(args[0])
        end = start + 1
        if len(args) == 4 and isinstance(args[1], float):
            nxt, end = 2, int(args[1])
        where = args[nxt]
        if isinstance(where, str):
            if 0 <= start <= len(where) and start <= end <= len(where):
                return ctx.unify(args[nxt + 1], where[:start] + where[end:])
            return ctx.unify(args[nxt + 1], where)
        items = list_to_python(where)
        if items is not None:
            return ctx.unify(args[nxt + 1],
                             make_list([x for k, x in enumerate(items) if k < start or k >= end]))
    if isinstance(args[0], str):
        text = args[1] if isinstance(args[1], str) else term_str(args[1])
        return ctx.unify(args[2], java_replace_all(args[0], text, ""))
    items = list_to_python(args[1])
    if items is None:
        raise IAError("Incorrect use of the internal action '.delete' (see documentation).",
                      "internal_action")
    s = dict(ctx.s)
    res = []
    for x in items:
        s2 = dict(s)
        if unify(args[0], x, s2):
            s = s2
        else:
            res.append(x)
    return ctx.unify(args[2], make_list(res))


def _set_args(args: list) -> list:
    """Jason's argument checks of ``.difference/.intersection/.union``; the second list's items."""
    for k, what in ((0, "first"), (1, "second")):
        if list_to_python(args[k]) is None:
            raise wrong_arg(f"{what} argument '{term_str(args[k])}'is not a list.")
    if not isinstance(args[2], (Var, ListTerm)):
        raise wrong_arg(f"last argument '{term_str(args[2])}'is not a list nor a variable.")
    return _items(args[1])


@internal_action(".difference", arity=3)
def difference(ctx: IAContext, args: list) -> bool:
    b = _set_args(args)
    res = sorted({x for x in _items(args[0]) if x not in b}, key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".intersection", arity=3)
def intersection(ctx: IAContext, args: list) -> bool:
    b = _set_args(args)
    res = sorted({x for x in _items(args[0]) if x in b}, key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".union", arity=3)
def union(ctx: IAContext, args: list) -> bool:
    _set_args(args)
    res = sorted(set(_items(args[0])) | set(_items(args[1])), key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".shuffle", arity=2)
def shuffle(ctx: IAContext, args: list) -> bool:
    items = _items(args[0])
    ctx.ag.random.shuffle(items)
    return ctx.unify(args[1], make_list(items))


def _sublist_args(args: list) -> list:
    """The argument checks shared by ``.prefix .suffix .sublist``; the list's items."""
    if not isinstance(args[0], (ListTerm, Var)):
        raise wrong_arg("first argument must be a list or a variable")
    if not isinstance(args[1], ListTerm):
        raise wrong_arg("second argument must be a list")
    items, tail = list(args[1].items), args[1].tail
    while isinstance(tail, ListTerm):
        items.extend(tail.items)
        tail = tail.tail
    return items


def _each_candidate(ctx: IAContext, pattern: Any, candidates: Any) -> Any:
    def gen():
        for c in candidates:
            s2 = dict(ctx.s)
            if unify(pattern, make_list(c), s2):
                yield s2
    return gen()


@internal_action(".prefix", arity=2)
def prefix(ctx: IAContext, args: list) -> Any:
    """``.prefix(P, L)``: longest prefix first, ``[]`` last (jason.stdlib.prefix)."""
    items = _sublist_args(args)
    return _each_candidate(ctx, args[0], (items[:n] for n in range(len(items), -1, -1)))


@internal_action(".suffix", arity=2)
def suffix(ctx: IAContext, args: list) -> Any:
    """``.suffix(S, L)``: the whole list first, ``[]`` last (jason.stdlib.suffix)."""
    items = _sublist_args(args)
    return _each_candidate(ctx, args[0], (items[k:] for k in range(len(items) + 1)))


@internal_action(".sublist", arity=2)
def sublist(ctx: IAContext, args: list) -> Any:
    """``.sublist(S, L)``: the prefixes of each suffix, longest first, then ``[]``
    (jason.stdlib.sublist: [a,b,c], [a,b], [a], [b,c], [b], [c], [])."""
    items = _sublist_args(args)
    cands = [items[k:e] for k in range(len(items)) for e in range(len(items), k, -1)]
    return _each_candidate(ctx, args[0], [*cands, []])


def _add_annot(t: Any, annot: Any) -> Any:
    if isinstance(t, ListTerm):
        items = list_to_python(t)
        if items is not None:
            return make_list([_add_annot(x, annot) for x in items])
    if isinstance(t, Literal):
        return t.add_annots([annot])
    return t


@internal_action(".add_annot", arity=3)
def add_annot(ctx: IAContext, args: list) -> bool:
    """``.add_annot(T, A, R)``: R is T (or each literal of the list T) with annotation A."""
    return ctx.unify(_add_annot(args[0], args[1]), args[2])
