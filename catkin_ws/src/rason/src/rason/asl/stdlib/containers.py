"""The ``.set``, ``.map`` and ``.queue`` families of Jason 3.3 (collections changed in place).

``.set.add(S, X)`` and ``.map.put(M, K, V)`` create the collection when S/M is still free;
the other actions need one. Collection arguments (``.set.union(S, C)``) may be lists, sets or
queues."""

from __future__ import annotations

from typing import Any

from ..containers import MapTerm, QueueTerm, SetTerm, collection_items
from ..terms import AnnotVar, Literal, Var, make_list
from ..unify import unify
from . import arg_count, internal_action, wrong_arg


def _free(t: Any) -> bool:
    return isinstance(t, (Var, AnnotVar))


def _set(ctx: Any, t: Any, create: bool = False) -> SetTerm:
    if isinstance(t, SetTerm):
        return t
    if create and _free(t):
        s = SetTerm()
        ctx.unify(t, s)
        return s
    raise wrong_arg("first argument must be a set")


def _map(ctx: Any, t: Any, create: bool = False) -> MapTerm:
    if isinstance(t, MapTerm):
        return t
    if create and _free(t):
        m = MapTerm()
        ctx.unify(t, m)
        return m
    raise wrong_arg("first argument must be a map")


def _queue(t: Any) -> QueueTerm:
    if isinstance(t, QueueTerm):
        return t
    raise wrong_arg("first argument must be a queue")


def _collection(t: Any) -> list:
    items = collection_items(t)
    if items is None:
        raise wrong_arg("second argument must be a list, a set or a queue")
    return items


def _each(ctx: Any, pattern: Any, values: list):
    for v in values:
        s2 = dict(ctx.s)
        if unify(pattern, v, s2):
            yield s2


# ------------------------------------------------------------------ sets
@internal_action(".set.create")
def set_create(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    return ctx.unify(args[0], SetTerm())


@internal_action(".set.add")
def set_add(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    _set(ctx, args[0], create=True).add(args[1])
    return True


@internal_action(".set.add_all", ".set.union")
def set_add_all(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    s = _set(ctx, args[0], create=True)
    for t in _collection(args[1]):
        s.add(t)
    return True


@internal_action(".set.remove")
def set_remove(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    _set(ctx, args[0], create=True).remove(args[1])
    return True


@internal_action(".set.intersection")
def set_intersection(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    _set(ctx, args[0], create=True).keep_only(_collection(args[1]))
    return True


@internal_action(".set.difference")
def set_difference(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    s = _set(ctx, args[0], create=True)
    for t in _collection(args[1]):
        s.remove(t)
    return True


@internal_action(".set.clear")
def set_clear(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    _set(ctx, args[0], create=True).clear()
    return True


@internal_action(".set.copy")
def set_copy(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], _set(ctx, args[0], create=True).copy())


@internal_action(".set.to_list")
def set_to_list(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], make_list(_set(ctx, args[0], create=True).items()))


# ------------------------------------------------------------------ maps
@internal_action(".map.create")
def map_create(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    return ctx.unify(args[0], MapTerm())


@internal_action(".map.put")
def map_put(ctx: Any, args: list) -> bool:
    arg_count(args, 3)
    _map(ctx, args[0], create=True).put(args[1], args[2])
    return True


@internal_action(".map.get")
def map_get(ctx: Any, args: list) -> bool:
    """``.map.get(M, K, V)`` fails for a missing key; ``.map.get(M, K, V, Default)`` gives V
    the default then."""
    arg_count(args, 3, 4)
    v = _map(ctx, args[0], create=True).get(args[1])
    if v is None:
        return len(args) == 4 and ctx.unify(args[2], args[3])
    return ctx.unify(args[2], v)


@internal_action(".map.remove")
def map_remove(ctx: Any, args: list) -> bool:
    arg_count(args, 3)
    v = _map(ctx, args[0], create=True).remove(args[1])
    return v is not None and ctx.unify(args[2], v)


@internal_action(".map.key")
def map_key(ctx: Any, args: list) -> Any:
    """Backtracks over the keys (in order) that unify with the second argument."""
    arg_count(args, 2)
    return _each(ctx, args[1], [k for k, _ in _map(ctx, args[0], create=True).entries()])


@internal_action(".map.value")
def map_value(ctx: Any, args: list) -> Any:
    """Backtracks over the values (in the order of their keys)."""
    arg_count(args, 2)
    return _each(ctx, args[1], [v for _, v in _map(ctx, args[0], create=True).entries()])


@internal_action(".map.clear")
def map_clear(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    _map(ctx, args[0], create=True).clear()
    return True


@internal_action(".map.copy")
def map_copy(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], _map(ctx, args[0], create=True).copy())


# ------------------------------------------------------------------ queues
@internal_action(".queue.create")
def queue_create(ctx: Any, args: list) -> bool:
    """``.queue.create(Q)`` (first-in first-out) or ``.queue.create(Q, priority)`` (the least
    term first); false when Q is not free."""
    arg_count(args, 1, 2)
    if not _free(args[0]):
        return False
    priority = len(args) == 2 and isinstance(args[1], Literal) and args[1].functor == "priority"
    return ctx.unify(args[0], QueueTerm(priority))


@internal_action(".queue.add")
def queue_add(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    _queue(args[0]).offer(args[1])
    return True


@internal_action(".queue.add_all")
def queue_add_all(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    q = _queue(args[0])
    for t in _collection(args[1]):
        q.offer(t)
    return True


@internal_action(".queue.head")
def queue_head(ctx: Any, args: list) -> bool:
    """The first member, kept; false when the queue is empty."""
    arg_count(args, 2)
    t = _queue(args[0]).peek()
    return t is not None and ctx.unify(args[1], t)


@internal_action(".queue.remove")
def queue_remove(ctx: Any, args: list) -> bool:
    """The first member, taken out; false when the queue is empty."""
    arg_count(args, 2)
    t = _queue(args[0]).poll()
    return t is not None and ctx.unify(args[1], t)


@internal_action(".queue.clear")
def queue_clear(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    _queue(args[0]).clear()
    return True


@internal_action(".queue.copy")
def queue_copy(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], _queue(args[0]).copy())


@internal_action(".queue.to_list")
def queue_to_list(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], make_list(_queue(args[0]).items()))
