"""A table-driven LALR(1) parser with a contextual lexer, for a grammar compiled ahead of time by
:mod:`rason.asl.lalr_gen` (lark makes the tables when the grammar changes; parsing needs no lark).

It behaves as lark's LALR parser with its contextual lexer and ``maybe_placeholders``: the same
tokens, the same reductions, the same children handed to each rule's callback, the same errors
(``tests/asl/test_asl_lalr.py`` compares the two). What differs is the cost of starting: one
regular expression of every terminal is compiled (lark compiles one for each parser state that
lexes), and a token that expression finds is taken when the parser's state accepts it. Only
when it does not is the state's own expression (its terminals alone) compiled and asked, which
is what lark's lexer does for every token. Both agree whenever the first is accepted: a state's
terminals are tried in the same order, and keywords are told apart from the atom they look like
only when the state accepts them.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from types import ModuleType
from typing import Any


class Token(str):
    """A terminal found in the text: its text, ``type`` (the terminal's name) and where it starts
    (1-based ``line`` and ``column``)."""

    type: str
    line: int
    column: int

    def __new__(cls, type_: str, value: str, line: int, column: int) -> Token:
        t = str.__new__(cls, value)
        t.type = type_
        t.line = line
        t.column = column
        return t

    def __repr__(self) -> str:
        return f"Token({self.type!r}, {str(self)!r})"

    def __reduce__(self) -> tuple:
        return (Token, (self.type, str(self), self.line, self.column))


class UnexpectedInput(Exception):
    """The text is not in the language; ``line`` and ``column`` say where (1-based)."""

    line: int
    column: int


class UnexpectedCharacters(UnexpectedInput):
    """No terminal the parser's state accepts starts at this character."""

    def __init__(self, text: str, pos: int, line: int, column: int, allowed: set[str]) -> None:
        self.char = text[pos]
        self.pos = pos
        self.line = line
        self.column = column
        self.allowed = allowed
        super().__init__(f"unexpected character {self.char!r} at line {line} column {column}")


class UnexpectedToken(UnexpectedInput):
    """A terminal the parser's state does not accept (``$END``: the text ended too early)."""

    def __init__(self, token: Token, expected: set[str]) -> None:
        self.token = token
        self.expected = expected
        self.line = token.line
        self.column = token.column
        super().__init__(f"unexpected {token.type} {str(token)!r} at line {token.line} column {token.column}")


class NestedTooDeep(UnexpectedInput):
    """The parser's state stack outgrew its bound: the text nests too deeply."""

    def __init__(self, token: Token, bound: int) -> None:
        self.token = token
        self.line = token.line
        self.column = token.column
        super().__init__(f"nested too deeply at line {token.line} column {token.column} "
                         f"(more than {bound} parser states)")


class _Inlined(list):
    """The children of one of lark's inlined rules (``item*`` and the like): its parent splices
    them into its own."""


class _Scanner:
    """The terminals of one lexing context as one regular expression (lark's ``Scanner``)."""

    def __init__(self, tables: ModuleType, names: frozenset[str] | None) -> None:
        terms = [(n, rx) for n, rx in tables.TERMINALS if names is None or n in names]
        present = {n for n, _ in terms}
        #: for a regular terminal, the strings it also matches that are told apart after a match
        self.unless: dict[str, dict[str, str]] = {}
        embedded = set()
        for n, _ in terms:
            for text, kind in tables.UNLESS.get(n, {}).items():
                if kind in present:
                    self.unless.setdefault(n, {})[text] = kind
                    embedded.add(kind)
        terms = [(n, rx) for n, rx in terms if n not in embedded]
        self.allowed = {n for n, _ in terms} - tables.IGNORE
        self.match = re.compile("|".join(f"(?P<{n}>{rx})" for n, rx in terms)).match


class LalrParser:
    """Parses texts of the grammar whose tables are the module ``tables``, calling ``callbacks``
    (an object with a method for each rule name the grammar reduces) as lark's LALR parser does
    with a transformer. ``max_stack``: a text whose nesting needs more parser states is
    refused with :class:`NestedTooDeep` (the stack holds a few states per level of nesting)."""

    def __init__(self, tables: ModuleType, callbacks: Any, max_stack: int = 1 << 62) -> None:
        self.tables = tables
        self.max_stack = max_stack
        self.reductions = [(origin, size, _reduction(name, expand1, shape, callbacks))
                           for origin, size, name, expand1, shape in tables.RULES]
        self.root = _Scanner(tables, None)
        self.by_state: dict[int, _Scanner] = {}
        self.by_terminals: dict[frozenset[str], _Scanner] = {}

    def _state_scanner(self, state: int) -> _Scanner:
        """The scanner of one parser state (its terminals and the ignored ones), made once."""
        sc = self.by_state.get(state)
        if sc is None:
            names = frozenset(s for s in self.tables.STATES[state] if s.isupper()) | self.tables.IGNORE
            sc = self.by_terminals.get(names)
            if sc is None:
                sc = self.by_terminals[names] = _Scanner(self.tables, names)
            self.by_state[state] = sc
        return sc

    def parse(self, text: str) -> Any:
        """What the callbacks make of ``text``; raises :class:`UnexpectedInput` subclasses."""
        tables = self.tables
        states = tables.STATES
        ignore = tables.IGNORE
        end_state = tables.END_STATE
        max_stack = self.max_stack
        reductions = self.reductions
        root = self.root
        match = root.match
        unless = root.unless
        state_stack = [tables.START_STATE]
        value_stack: list = []
        pos = 0
        line = 1
        line_start = 0
        n = len(text)
        last: Token | None = None
        while True:
            # ---- the next token, lexed in the context of the parser's state
            token = None
            while pos < n:
                state = state_stack[-1]
                m = match(text, pos)
                if m is None:                 # nothing of the language: the state's error
                    value, kind = self._lex_in_state(text, pos, line, pos - line_start + 1, state)
                else:
                    value = m.group()
                    kind = m.lastgroup or ""  # (every alternative is a named group)
                    if kind not in ignore:
                        actions = states[state]
                        keywords = unless.get(kind)
                        taken = kind in actions
                        if keywords is not None:
                            k = keywords.get(value)
                            if k is not None and k in actions:
                                kind = k
                                taken = True
                        if not taken:         # not this state's: ask its own scanner
                            value, kind = self._lex_in_state(text, pos, line, pos - line_start + 1, state)
                column = pos - line_start + 1
                newlines = value.count("\n")
                line_start_next = pos + value.rindex("\n") + 1 if newlines else line_start
                pos += len(value)
                if kind in ignore:
                    line += newlines
                    line_start = line_start_next
                    continue
                token = Token(kind, value, line, column)
                line += newlines
                line_start = line_start_next
                break
            if token is None:
                token = (Token("$END", "", last.line, last.column) if last is not None
                         else Token("$END", "", 1, 1))
            else:
                last = token
            # ---- the parser takes it: reduce as long as the state says so, then shift
            kind = token.type
            while True:
                actions = states[state_stack[-1]]
                act = actions.get(kind)
                if act is None:
                    raise UnexpectedToken(token, {s for s in actions if s.isupper()})
                if act >= 0:
                    state_stack.append(act)
                    value_stack.append(token)
                    if len(state_stack) > max_stack:
                        raise NestedTooDeep(token, max_stack)
                    break
                origin, size, reduce = reductions[~act]
                if size:
                    children = value_stack[-size:]
                    del state_stack[-size:]
                    del value_stack[-size:]
                else:
                    children = []
                value_stack.append(reduce(children))
                goto = states[state_stack[-1]][origin]
                state_stack.append(goto)
                if kind == "$END" and goto == end_state:
                    return value_stack[-1]

    def _lex_in_state(self, text: str, pos: int, line: int, column: int, state: int) -> tuple[str, str]:
        """The token at ``pos`` as the scanner of ``state`` alone finds it (text, terminal); when
        it finds none, the error lark's contextual lexer gives."""
        sc = self._state_scanner(state)
        m = sc.match(text, pos)
        if m is None:
            found = self.root.match(text, pos)
            if found is None:
                raise UnexpectedCharacters(text, pos, line, column, sc.allowed)
            kind = found.lastgroup or ""
            kind = self.root.unless.get(kind, {}).get(found.group(), kind)
            raise UnexpectedToken(Token(kind, found.group(), line, column), sc.allowed)
        kind = m.lastgroup or ""
        keywords = sc.unless.get(kind)
        if keywords is not None:
            kind = keywords.get(m.group(), kind)
        return m.group(), kind


def _reduction(name: str | None, expand1: bool, shape: tuple | None,
               callbacks: Any) -> Callable[[list], Any]:
    """What reducing one rule makes of the values of its symbols: the children lark's tree
    builder would keep (a ``None`` for each missing ``[optional]``, inlined rules spliced), then
    the only child of a ``?rule``, else the rule's callback."""
    if name is None:
        make: Callable[[list], Any] = _Inlined
    else:
        make = getattr(callbacks, name, None) or _no_callback(name)
    if shape is None:
        if not expand1:
            return make

        def single(children: list) -> Any:
            return children[0] if len(children) == 1 else make(children)
        return single
    include, append_none = shape

    def reduce(children: list) -> Any:
        kept: list = []
        for i, splice, nones in include:
            if nones:
                kept.extend([None] * nones)
            if splice:
                kept.extend(children[i])
            else:
                kept.append(children[i])
        if append_none:
            kept.extend([None] * append_none)
        if expand1 and len(kept) == 1:
            return kept[0]
        return make(kept)
    return reduce


def _no_callback(name: str) -> Callable[[list], Any]:
    """The callback of a rule the callbacks object lacks: a ``?rule`` that always has one child
    never calls it; any other use is a fault of the grammar's callbacks."""
    def missing(children: list) -> Any:
        raise TypeError(f"no callback for grammar rule {name!r} ({len(children)} children)")
    return missing
