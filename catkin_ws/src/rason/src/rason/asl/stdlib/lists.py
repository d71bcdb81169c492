"""List internal actions: ``.member .length .concat .nth .max .min .sort .reverse ...``."""

from __future__ import annotations

import functools
from typing import Any

from ..terms import ListTerm, list_to_python, make_list, sort_key, to_print_str
from ..unify import compare_terms, unify
from . import IAError, arg_count, internal_action


def _items(t: Any) -> list:
    items = list_to_python(t)
    if items is None:
        raise IAError(f"not a list: {t!r}", "wrong_arguments")
    return items


@internal_action(".member")
def member(ctx: Any, args: list) -> Any:
    arg_count(args, 2)
    items = _items(args[1])

    def gen():
        for x in items:
            s2 = dict(ctx.s)
            if unify(args[0], x, s2):
                yield s2
    return gen()


@internal_action(".length")
def length(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    if isinstance(args[0], str):
        return ctx.unify(args[1], float(len(args[0])))
    return ctx.unify(args[1], float(len(_items(args[0]))))


@internal_action(".concat")
def concat(ctx: Any, args: list) -> bool:
    if len(args) < 2:
        raise IAError("wrong number of arguments", "wrong_arguments")
    parts, out = args[:-1], args[-1]
    if all(isinstance(p, ListTerm) for p in parts):
        res: list = []
        for p in parts:
            res.extend(_items(p))
        return ctx.unify(out, make_list(res))
    return ctx.unify(out, "".join(to_print_str(p) for p in parts))


@internal_action(".nth")
def nth(ctx: Any, args: list) -> Any:
    arg_count(args, 3)
    items = _items(args[1])
    if isinstance(args[0], float):
        i = int(args[0])
        if 0 <= i < len(items):
            return ctx.unify(args[2], items[i])
        return False

    def gen():
        for i, x in enumerate(items):
            s2 = dict(ctx.s)
            if unify(args[0], float(i), s2) and unify(args[2], x, s2):
                yield s2
    return gen()


def _cmp(a: Any, b: Any) -> int:
    return compare_terms(a, b)


@internal_action(".max")
def max_(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    items = _items(args[0])
    if not items:
        return False
    return ctx.unify(args[1], max(items, key=functools.cmp_to_key(_cmp)))


@internal_action(".min")
def min_(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    items = _items(args[0])
    if not items:
        return False
    return ctx.unify(args[1], min(items, key=functools.cmp_to_key(_cmp)))


@internal_action(".sort")
def sort(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], make_list(sorted(_items(args[0]), key=sort_key)))


@internal_action(".reverse")
def reverse(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    if isinstance(args[0], str):
        return ctx.unify(args[1], args[0][::-1])
    return ctx.unify(args[1], make_list(list(reversed(_items(args[0])))))


@internal_action(".sum")
def sum_(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], float(sum(x for x in _items(args[0]) if isinstance(x, float))))


@internal_action(".empty")
def empty(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    if isinstance(args[0], str):
        return args[0] == ""
    return isinstance(args[0], ListTerm) and not _items(args[0])


@internal_action(".delete")
def delete(ctx: Any, args: list) -> bool:
    """``.delete(X, L, R)``: remove every element unifying X (X a number = index)."""
    arg_count(args, 3)
    if isinstance(args[1], str):
        return ctx.unify(args[2], args[1].replace(to_print_str(args[0]), ""))
    items = _items(args[1])
    if isinstance(args[0], float) and not any(isinstance(x, float) for x in items):
        i = int(args[0])
        res = items[:i] + items[i + 1:]
    else:
        res = [x for x in items if not unify(args[0], x, dict(ctx.s))]
    return ctx.unify(args[2], make_list(res))


@internal_action(".difference")
def difference(ctx: Any, args: list) -> bool:
    arg_count(args, 3)
    b = _items(args[1])
    res = sorted({x for x in _items(args[0]) if x not in b}, key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".intersection")
def intersection(ctx: Any, args: list) -> bool:
    arg_count(args, 3)
    b = _items(args[1])
    res = sorted({x for x in _items(args[0]) if x in b}, key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".union")
def union(ctx: Any, args: list) -> bool:
    arg_count(args, 3)
    res = sorted(set(_items(args[0])) | set(_items(args[1])), key=sort_key)
    return ctx.unify(args[2], make_list(res))


@internal_action(".shuffle")
def shuffle(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    items = _items(args[0])
    ctx.ag.random.shuffle(items)
    return ctx.unify(args[1], make_list(items))
