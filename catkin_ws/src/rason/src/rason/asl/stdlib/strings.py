"""String internal actions: ``.substring .lower_case .upper_case .replace``."""

from __future__ import annotations

import re
from typing import Any

from ..terms import Var, to_print_str
from ..unify import eval_arith, unify
from . import arg_count, internal_action


def _s(t: Any) -> str:
    return to_print_str(t)


@internal_action(".substring")
def substring(ctx: Any, args: list) -> Any:
    """``.substring(Sub, S[, Pos])`` tests/enumerates positions; ``.substring(S, R, Begin[, End])``
    extracts when R is unbound."""
    arg_count(args, 2, 3, 4)
    if len(args) >= 3 and isinstance(args[1], Var):
        s = _s(args[0])
        b = int(eval_arith(args[2], ctx.s))
        e = int(eval_arith(args[3], ctx.s)) if len(args) == 4 else len(s)
        return ctx.unify(args[1], s[b:e])
    sub, s = _s(args[0]), _s(args[1])
    if len(args) == 2:
        return sub in s

    def gen():
        start = 0
        while True:
            i = s.find(sub, start)
            if i < 0:
                return
            s2 = dict(ctx.s)
            if unify(args[2], float(i), s2):
                yield s2
            start = i + 1
    return gen()


@internal_action(".lower_case")
def lower_case(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], _s(args[0]).lower())


@internal_action(".upper_case")
def upper_case(ctx: Any, args: list) -> bool:
    arg_count(args, 2)
    return ctx.unify(args[1], _s(args[0]).upper())


def java_replace_all(pattern: str, text: str, replacement: str) -> str:
    """Java's ``String.replaceAll``: ``pattern`` is a regular expression, ``$1`` a group."""
    def expand(m: re.Match) -> str:
        out, i, n = [], 0, len(replacement)
        while i < n:
            c = replacement[i]
            if c == "\\" and i + 1 < n:
                out.append(replacement[i + 1])
                i += 2
            elif c == "$" and i + 1 < n and replacement[i + 1].isdigit():
                out.append(m.group(int(replacement[i + 1])) or "")
                i += 2
            else:
                out.append(c)
                i += 1
        return "".join(out)
    try:
        return re.sub(pattern, expand, text)
    except (re.error, IndexError):
        return text.replace(pattern, replacement)


@internal_action(".replace")
def replace(ctx: Any, args: list) -> bool:
    """``.replace(S, Old, New, R)``: Java ``replaceAll`` (Old is a regular expression)."""
    arg_count(args, 4)
    return ctx.unify(args[3], java_replace_all(_s(args[1]), _s(args[0]), _s(args[2])))
