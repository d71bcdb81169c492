"""String internal actions: ``.substring .lower_case .upper_case .replace``."""

from __future__ import annotations

import re
from typing import Any

from ..ia import IAContext, IAError, internal_action
from ..terms import Var, to_print_str
from ..unify import unify


def _s(t: Any) -> str:
    return to_print_str(t)


def _java_substring(s: str, begin: int, end: int) -> str:
    if begin < 0 or end > len(s) or begin > end:
        raise IAError(f"begin {begin}, end {end}, length {len(s)}", "ia_failed")
    return s[begin:end]


@internal_action(".substring", arity=(2, 4))
def substring(ctx: IAContext, args: list) -> Any:
    """jason.stdlib.substring: ``.substring(Sub, S)`` tests; ``.substring(R, S, B[, E])`` with R
    unbound extracts S[B:E]; ``.substring(Sub, S, P[, E])`` enumerates the positions P where Sub
    occurs (E is then P + length - 1, as Jason computes it)."""
    sub, s = _s(args[0]), _s(args[1])
    if len(args) == 2:
        return sub in s
    if isinstance(args[2], float) and (isinstance(args[0], Var) or isinstance(args[1], Var)):
        src = s if isinstance(args[0], Var) else sub
        start = int(args[2])
        end = int(args[3]) if len(args) == 4 and isinstance(args[3], float) else len(src)
        return ctx.unify(args[0] if isinstance(args[0], Var) else args[1],
                         _java_substring(src, start, end))

    def gen():
        pos = 0
        while pos < len(s):
            i = s.find(sub, pos)
            if i < 0:
                return
            pos = i + 1
            s2 = dict(ctx.s)
            if unify(args[2], float(i), s2) and (
                    len(args) == 3 or unify(args[3], float(i - 1 + len(sub)), s2)):
                yield s2
    return gen()


@internal_action(".lower_case", arity=2)
def lower_case(ctx: IAContext, args: list) -> bool:
    return ctx.unify(args[1], _s(args[0]).lower())


@internal_action(".upper_case", arity=2)
def upper_case(ctx: IAContext, args: list) -> bool:
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


@internal_action(".replace", arity=4)
def replace(ctx: IAContext, args: list) -> bool:
    """``.replace(S, Old, New, R)``: Java ``replaceAll`` (Old is a regular expression)."""
    return ctx.unify(args[3], java_replace_all(_s(args[1]), _s(args[0]), _s(args[2])))
