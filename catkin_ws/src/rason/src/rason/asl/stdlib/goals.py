"""Goal internal actions: ``.desire .intend .drop_desire .drop_intention .succeed_goal .fail_goal``."""

from __future__ import annotations

from typing import Any

from ..plans import ACHIEVE, ADD
from ..unify import unify
from . import arg_count, internal_action


def _goal_literals(ag: Any, with_events: bool) -> list:
    out = []
    for i in ag.all_intentions():
        for im in reversed(i.ims):
            t = im.trigger
            if t.op == ADD and t.type == ACHIEVE:
                out.append(t.literal)
    if with_events:
        for ev in ag.events:
            t = ev.trigger
            if t.op == ADD and t.type == ACHIEVE:
                out.append(t.literal)
    return out


def _enumerate(ctx: Any, pattern: Any, lits: list) -> Any:
    def gen():
        for lit in lits:
            s2 = dict(ctx.s)
            if unify(pattern, lit, s2):
                yield s2
    return gen()


@internal_action(".desire")
def desire(ctx: Any, args: list) -> Any:
    arg_count(args, 1, 2)
    return _enumerate(ctx, args[0], _goal_literals(ctx.ag, True))


@internal_action(".intend")
def intend(ctx: Any, args: list) -> Any:
    arg_count(args, 1, 2)
    return _enumerate(ctx, args[0], _goal_literals(ctx.ag, False))


@internal_action(".drop_desire")
def drop_desire(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    ctx.ag.drop_goal(args[0], ctx.s, drop_events=True)
    return True


@internal_action(".drop_intention")
def drop_intention(ctx: Any, args: list) -> bool:
    arg_count(args, 0, 1)
    if not args:
        if ctx.intention is not None:
            ctx.ag.drop_whole_intention(ctx.intention)
        return True
    ctx.ag.drop_goal(args[0], ctx.s, drop_events=False)
    return True


@internal_action(".drop_all_desires")
def drop_all_desires(ctx: Any, args: list) -> bool:
    """Drop every event and intention but the current one (jason.stdlib.drop_all_desires)."""
    arg_count(args, 0)
    ctx.ag.drop_all(events=True, keep=ctx.intention)
    return True


@internal_action(".drop_all_intentions")
def drop_all_intentions(ctx: Any, args: list) -> bool:
    """Drop every intention (and its events) but the current one (jason.stdlib.drop_all_intentions)."""
    arg_count(args, 0)
    ctx.ag.drop_all(events=False, keep=ctx.intention)
    return True


@internal_action(".drop_all_events")
def drop_all_events(ctx: Any, args: list) -> bool:
    ctx.ag.events.clear()
    return True


@internal_action(".suspend")
def suspend(ctx: Any, args: list) -> Any:
    """``.suspend(G)``: suspend the intentions for goal G (no argument: the current one)."""
    from . import SUSPEND
    arg_count(args, 0, 1)
    if not args:
        if ctx.intention is None:
            return False
        ctx.ag.suspend(ctx.intention, "suspended")
        return SUSPEND
    cur = False
    for i, _ in list(ctx.ag._goal_positions(args[0], ctx.s)):
        if i is ctx.intention:
            cur = True
        ctx.ag.detach(i)
        ctx.ag.suspend(i, "suspended")
    return SUSPEND if cur else True


@internal_action(".resume")
def resume(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    for i, _ in list(ctx.ag._goal_positions(args[0], ctx.s)):
        if i.suspended == "suspended":
            ctx.ag.resume(i)
    return True


@internal_action(".succeed_goal")
def succeed_goal(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    ctx.ag.succeed_goal(args[0], ctx.s)
    return True


@internal_action(".fail_goal")
def fail_goal(ctx: Any, args: list) -> bool:
    arg_count(args, 1)
    ctx.ag.fail_goal(args[0], ctx.s)
    return True
