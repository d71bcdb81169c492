"""Writes the tables of :mod:`rason.asl.lalr` for a lark grammar (the parser's ``GRAMMAR``):
lark builds the LALR(1) table, its contextual lexer's terminals and the tree-shaping rules of
each grammar rule, and this module prints them as a Python module of plain literals.

Regenerate ``asl_tables.py`` after changing ``GRAMMAR`` (``tests/asl/test_asl_lalr.py`` fails
until then)::

    python -m rason.asl.lalr_gen > catkin_ws/src/rason/src/rason/asl/asl_tables.py

Only this module (and the tests) import lark for the agent language; parsing at run time needs
the generated tables alone.
"""

from __future__ import annotations

import pprint
import re
import sys
from collections import deque
from typing import Any

from lark import Lark
from lark.lexer import PatternRE, PatternStr
from lark.parse_tree_builder import maybe_create_child_filter
from lark.parsers.lalr_analysis import Shift

from .parser import GRAMMAR


def reference_lark(grammar: str) -> Lark:
    """The lark parser the tables are taken from (LALR, contextual lexer, ``[x]`` as None)."""
    return Lark(grammar, parser="lalr", lexer="contextual", maybe_placeholders=True)


def _child_filter(rule) -> tuple | None:
    """Which children a rule's callback receives, as lark's tree builder picks them:
    ``((index, splice, nones_before), ...)`` and the Nones appended, or None for all as they are."""
    made = maybe_create_child_filter(rule.expansion, rule.options.keep_all_tokens, False,
                                     rule.options.empty_indices)
    if made is None:
        return None
    args = made.args
    if len(args) == 1:                       # no placeholders in this rule
        return tuple((i, bool(x), 0) for i, x in args[0]), 0
    include, append_none = args
    return tuple((i, bool(x), n) for i, x, n in include), append_none


def _whole_match(regexp: str, text: str) -> bool:
    """Whether ``regexp`` matches all of ``text`` from its start (lark's test for a keyword)."""
    m = re.match(regexp, text)
    return m is not None and m.group(0) == text


def tables(grammar: str) -> dict:
    """The tables of ``grammar`` as plain data (states numbered breadth-first from the start
    state, symbols in sorted order, so the result does not depend on lark's numbering)."""
    lk = reference_lark(grammar)
    table = lk.parser.parser.parser.parse_table
    root = lk.parser.lexer.root_lexer
    assert len(lk.options.start) == 1
    start = lk.options.start[0]

    # terminals in the order lark's lexers try them (priority, width, length, name)
    terminals = []
    for t in root.terminals:
        assert isinstance(t.pattern, (PatternRE, PatternStr)) and not t.pattern.flags, t
        terminals.append((str(t.name), str(t.pattern.to_regexp())))
    assert len(terminals) < 100, "Python's re allows 100 groups: split the alternation"
    # strings that a regular terminal also matches, told apart after the match (keywords)
    unless: dict[str, dict[str, str]] = {}
    for retok in root.terminals:
        if not isinstance(retok.pattern, PatternRE):
            continue
        for strtok in root.terminals:
            if (isinstance(strtok.pattern, PatternStr) and strtok.priority == retok.priority
                    and _whole_match(retok.pattern.to_regexp(), strtok.pattern.value)):
                assert all(strtok.name not in u.values() for u in unless.values()), strtok
                unless.setdefault(str(retok.name), {})[str(strtok.pattern.value)] = str(strtok.name)

    # states renumbered breadth-first, symbols sorted
    order = {table.start_states[start]: 0}
    pending = deque([table.start_states[start]])
    while pending:
        s = pending.popleft()
        for sym in sorted(table.states[s]):
            action, arg = table.states[s][sym]
            if action is Shift and arg not in order:
                order[arg] = len(order)
                pending.append(arg)
    assert len(order) == len(table.states)
    rule_list = sorted({arg for acts in table.states.values() for action, arg in acts.values()
                        if action is not Shift}, key=lambda r: (r.origin.name, str(r), r.alias or ""))
    rule_index = {r: i for i, r in enumerate(rule_list)}
    states: list[Any] = [None] * len(order)
    for s, acts in table.states.items():
        states[order[s]] = {str(sym): (order[arg] if action is Shift else ~rule_index[arg])
                            for sym, (action, arg) in sorted(acts.items())}
    rules = []
    for r in rule_list:
        name = str(r.alias or r.options.template_source or r.origin.name)
        internal = name.startswith("_")      # lark's inlined rules (``item*`` and the like)
        assert not (internal and r.options.expand1), r
        rules.append((str(r.origin.name), len(r.expansion), None if internal else name,
                      bool(r.options.expand1 and not r.alias), _child_filter(r)))
    return {
        "GRAMMAR": grammar,           # what the tables were made from (the parser checks it)
        "TERMINALS": tuple(terminals),
        "UNLESS": unless,
        "IGNORE": frozenset(str(n) for n in lk.lexer_conf.ignore),
        "START_STATE": order[table.start_states[start]],
        "END_STATE": order[table.end_states[start]],
        "STATES": tuple(states),
        "RULES": tuple(rules),
    }


def module_text(grammar: str) -> str:
    """The generated module's text for ``grammar``."""
    lines = [
        '"""Generated by ``python -m rason.asl.lalr_gen`` from ``rason.asl.parser.GRAMMAR``:',
        "do not edit (see :mod:`rason.asl.lalr`)."
        '"""',
        "",
        "# ruff: noqa: E501",
        "",
    ]
    for name, value in tables(grammar).items():
        if name == "IGNORE":
            lines.append(f"{name} = frozenset({sorted(value)!r})")
        elif name in ("STATES", "RULES"):     # one state (rule) a line, in order
            kind = "tuple[dict[str, int], ...]" if name == "STATES" else "tuple[tuple, ...]"
            lines.append(f"{name}: {kind} = (")
            lines.extend(f"    {item!r}," for item in value)
            lines.append(")")
        else:
            lines.append(f"{name} = " + pprint.pformat(value, width=120, sort_dicts=False))
    return "\n".join(lines) + "\n"


def main() -> int:
    sys.stdout.write(module_text(GRAMMAR))
    return 0


if __name__ == "__main__":
    sys.exit(main())
