"""Plain data terms read without the grammar (compiled with the reasoning cycle).

Messages and percepts are mostly plain data (numbers, strings without escapes, atoms,
structures, annotations, proper lists, variables), read thousands of times a second in a
fleet. This small reader takes those; it accepts a subset of the grammar's language and builds
the very terms the grammar builds. Anything else (operators, list or annotation tails, quoted
atoms, escapes, namespaces, comments, keywords...) and every error go to the grammar
(:func:`rason.asl.parser.parse_term`), which stays the one definition of the language and of
its error messages. A term nested deeper than :data:`~rason.asl.limits.MAX_TERM_DEPTH` is
left to the grammar too, which refuses it (this reader recurses, on the C stack when compiled).
"""

from __future__ import annotations

import re
from typing import Any

from .limits import MAX_TERM_DEPTH
from .terms import ListTerm, Literal, Var, fresh_name, is_constant, merge_annots

_PLAIN_TOKEN = re.compile(r"""[ \t\f\r\n]*(?:
      (?P<num>-?[0-9]+(?:\.[0-9]+)?(?:[eE][+-]?[0-9]+)?)(?![A-Za-z0-9_.])
    | (?P<atom>~?[a-z][A-Za-z0-9_]*)(?![.:'])
    | (?P<var>[A-Z_][A-Za-z0-9_]*)
    | (?P<str>"[^"\\]*")
    | (?P<sym>[(),\[\]])
    )""", re.VERBOSE)
_PLAIN_END = re.compile(r"[ \t\f\r\n]*")
#: words the grammar reads as operators or statements, never as plain atoms here
_NOT_PLAIN = frozenset({"not", "div", "mod", "if", "elif", "else", "while", "for"})


class _NotPlain(Exception):
    """The text is not a plain data term: the grammar reads it."""


def _plain_tokens(text: str) -> list[tuple[str, str]]:
    tokens: list[tuple[str, str]] = []
    pos, end = 0, len(text)
    match = _PLAIN_TOKEN.match
    while True:
        m = match(text, pos)
        if m is None:
            if _PLAIN_END.match(text, pos).end() == end:   # type: ignore[union-attr]
                return tokens
            raise _NotPlain
        kind = m.lastgroup
        assert kind is not None
        tokens.append((kind, m.group(kind)))
        pos = m.end()


def _read_plain(tokens: list[tuple[str, str]], i: int, depth: int) -> tuple[Any, int]:
    """The plain term starting at token `i` (`depth` levels down), and the index after it."""
    if depth > MAX_TERM_DEPTH:
        raise _NotPlain
    kind, value = tokens[i]
    n = len(tokens)
    nxt = tokens[i + 1][1] if i + 1 < n else ""
    if kind == "num":
        return float(value), i + 1
    if kind == "str":
        return value[1:-1], i + 1
    if kind == "var":
        if nxt in ("(", "["):
            raise _NotPlain
        return (Var(fresh_name()) if value == "_" else Var(value)), i + 1
    if kind == "atom":
        neg = value[0] == "~"
        name = value[1:] if neg else value
        if name in _NOT_PLAIN:
            raise _NotPlain
        i += 1
        args: tuple = ()
        annots: tuple = ()
        if nxt == "(":
            args, i = _read_plain_items(tokens, i + 1, ")", False, depth + 1)
            nxt = tokens[i][1] if i < n else ""
        if nxt == "[":
            annots, i = _read_plain_items(tokens, i + 1, "]", True, depth + 1)
            annots = merge_annots((), annots)
        lit = Literal(name, args, annots, None, neg)
        is_constant(lit)
        return lit, i
    if value == "[":
        items, i = _read_plain_items(tokens, i + 1, "]", True, depth + 1)
        return (ListTerm(items) if items else ListTerm()), i
    raise _NotPlain


def _read_plain_items(tokens: list[tuple[str, str]], i: int, close: str,
                      allow_empty: bool, depth: int) -> tuple[tuple, int]:
    """Comma separated plain terms up to `close` (token `i` follows the opening bracket)."""
    items = []
    n = len(tokens)
    if i < n and tokens[i][1] == close and tokens[i][0] == "sym":
        if not allow_empty:
            raise _NotPlain
        return (), i + 1
    while i < n:
        item, i = _read_plain(tokens, i, depth)
        items.append(item)
        if i >= n or tokens[i][0] != "sym":
            raise _NotPlain
        if tokens[i][1] == close:
            return tuple(items), i + 1
        if tokens[i][1] != ",":
            raise _NotPlain
        i += 1
    raise _NotPlain


def read_plain_term(text: str) -> Any | None:
    """`text` as a plain data term (the grammar would read the same), or None when it is not
    one (then only the grammar may read it, or reject it)."""
    try:
        tokens = _plain_tokens(text)
        if not tokens:
            return None
        term, end = _read_plain(tokens, 0, 0)
    except (_NotPlain, IndexError, RecursionError):
        return None
    return term if end == len(tokens) else None
