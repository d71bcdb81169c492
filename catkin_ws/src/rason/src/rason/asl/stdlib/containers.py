"""The ``.set``, ``.map`` and ``.queue`` families of Jason 3.3 (collections changed in place).

``.set.add(S, X)`` and ``.map.put(M, K, V)`` create the collection when S/M is still free;
the other actions need one. Collection arguments (``.set.union(S, C)``) may be lists, sets or
queues."""

from __future__ import annotations

from typing import Any

from ..containers import MapTerm, QueueTerm, SetTerm, collection_items
from ..ia import IAContext, internal_action, wrong_arg
from ..terms import AnnotVar, Literal, Var, make_list
from ..unify import unify


def _free(t: Any) -> bool:
    return isinstance(t, (Var, AnnotVar))


def _set(ctx: IAContext, t: Any, create: bool = False) -> SetTerm:
    if isinstance(t, SetTerm):
        return t
    if create and _free(t):
        s = SetTerm()
        ctx.unify(t, s)
        return s
    raise wrong_arg("first argument must be a set")


def _map(ctx: IAContext, t: Any, create: bool = False) -> MapTerm:
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


def _each(ctx: IAContext, pattern: Any, values: list):
    for v in values:
        s2 = dict(ctx.s)
        if unify(pattern, v, s2):
            yield s2


# ------------------------------------------------------------------ sets
@internal_action(".set.create", arity=1)
def set_create(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[0], SetTerm())


@internal_action(".set.add", arity=2)
def set_add(ctx: IAContext, args: list) -> bool:
    _set(ctx, args[0], create=True).add(args[1])
    return True


@internal_action(".set.add_all", ".set.union", arity=2)
def set_add_all(ctx: IAContext, args: list) -> bool:
    s = _set(ctx, args[0], create=True)
    for t in _collection(args[1]):
        s.add(t)
    return True


@internal_action(".set.remove", arity=2)
def set_remove(ctx: IAContext, args: list) -> bool:
    _set(ctx, args[0], create=True).remove(args[1])
    return True


@internal_action(".set.intersection", arity=2)
def set_intersection(ctx: IAContext, args: list) -> bool:
    _set(ctx, args[0], create=True).keep_only(_collection(args[1]))
    return True


@internal_action(".set.difference", arity=2)
def set_difference(ctx: IAContext, args: list) -> bool:
    s = _set(ctx, args[0], create=True)
    for t in _collection(args[1]):
        s.remove(t)
    return True


@internal_action(".set.clear", arity=1)
def set_clear(ctx: IAContext, args: list) -> bool:
    _set(ctx, args[0], create=True).clear()
    return True


@internal_action(".set.copy", arity=2)
def set_copy(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], _set(ctx, args[0], create=True).copy())


@internal_action(".set.to_list", arity=2)
def set_to_list(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], make_list(_set(ctx, args[0], create=True).items()))


# ------------------------------------------------------------------ maps
@internal_action(".map.create", arity=1)
def map_create(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[0], MapTerm())


@internal_action(".map.put", arity=3)
def map_put(ctx: IAContext, args: list) -> bool:
    _map(ctx, args[0], create=True).put(args[1], args[2])
    return True


@internal_action(".map.get", arity=(3, 4))
def map_get(ctx: IAContext, args: list) -> bool:
    """``.map.get(M, K, V)`` fails for a missing key; ``.map.get(M, K, V, Default)`` gives V
    the default then."""
    v = _map(ctx, args[0], create=True).get(args[1])
    if v is None:
        return len(args) == 4 and ctx.unify(args[2], args[3])
    return ctx.unify(args[2], v)


@internal_action(".map.remove", arity=3)
def map_remove(ctx: IAContext, args: list) -> bool:
    v = _map(ctx, args[0], create=True).remove(args[1])
    return v is not None and ctx.unify(args[2], v)


@internal_action(".map.key", arity=2)
def map_key(ctx: IAContext, args: list) -> Any:
    """Backtracks over the keys (in order) that unify with the second argument."""
    return _each(ctx, args[1], [k for k, _ in _map(ctx, args[0], create=True).entries()])


@internal_action(".map.value", arity=2)
def map_value(ctx: IAContext, args: list) -> Any:
    """Backtracks over the values (in the order of their keys)."""
    return _each(ctx, args[1], [v for _, v in _map(ctx, args[0], create=True).entries()])


@internal_action(".map.clear", arity=1)
def map_clear(ctx: IAContext, args: list) -> bool:
    _map(ctx, args[0], create=True).clear()
    return True


@internal_action(".map.copy", arity=2)
def map_copy(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], _map(ctx, args[0], create=True).copy())


# ------------------------------------------------------------------ queues
@internal_action(".queue.create", arity=(1, 2))
def queue_create(ctx: IAContext, args: list) -> bool:
    """``.queue.create(Q)`` (first-in first-out) or ``.queue.create(Q, priority)`` (the least
    term first); false when Q is not free."""
    if not _free(args[0]):
        return False
    priority = len(args) == 2 and isinstance(args[1], Literal) and args[1].functor == "priority"
    return ctx.unify(args[0], QueueTerm(priority))


@internal_action(".queue.add", arity=2)
def queue_add(ctx: IAContext, args: list) -> bool:
    _queue(args[0]).offer(args[1])
    return True


@internal_action(".queue.add_all", arity=2)
def queue_add_all(ctx: IAContext, args: list) -> bool:
    q = _queue(args[0])
    for t in _collection(args[1]):
        q.offer(t)
    return True


@internal_action(".queue.head", arity=2)
def queue_head(ctx: IAContext, args: list) -> bool:
    """The first member, kept; false when the queue is empty."""
    t = _queue(args[0]).peek()
    return t is not None and ctx.unify(args[1], t)


@internal_action(".queue.remove", arity=2)
def queue_remove(ctx: IAContext, args: list) -> bool:
    """The first member, taken out; false when the queue is empty."""
    t = _queue(args[0]).poll()
    return t is not None and ctx.unify(args[1], t)


@internal_action(".queue.clear", arity=1)
def queue_clear(ctx: IAContext, args: list) -> bool:
    _queue(args[0]).clear()
    return True


@internal_action(".queue.copy", arity=2)
def queue_copy(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], _queue(args[0]).copy())


@internal_action(".queue.to_list", arity=2)
def queue_to_list(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], make_list(_queue(args[0]).items()))
