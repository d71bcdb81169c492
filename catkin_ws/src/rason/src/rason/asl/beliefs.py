"""The belief base (Jason's ``DefaultBeliefBase``): beliefs and rules indexed by functor/arity."""

from __future__ import annotations

from typing import Any

from .parser import Rule
from .terms import Literal, merge_annots, sort_key
from .unify import unify


class BeliefBase:
    """Ordered beliefs and rules per (functor, arity, negation) key.

    A belief is stored once per ``(functor, args, negation)`` with all its annotations merged
    (e.g. several ``source(...)``).
    """

    def __init__(self) -> None:
        self._index: dict[tuple, list] = {}
        self._percepts: dict[Literal, Literal] = {}

    # ------------------------------------------------------------ access
    def candidates(self, key: tuple) -> list:
        """Beliefs and rules with this key (a snapshot-safe list; do not mutate)."""
        return self._index.get(key, ())

    def __iter__(self):
        for lst in self._index.values():
            yield from lst

    def beliefs(self) -> list[Literal]:
        return [b for b in self if isinstance(b, Literal)]

    def rules(self) -> list[Rule]:
        return [b for b in self if isinstance(b, Rule)]

    def find(self, lit: Literal) -> Literal | None:
        """The stored belief with the same functor/args/negation as ``lit`` (annotations ignored)."""
        for b in self._index.get(lit.key, ()):
            if isinstance(b, Literal) and b.args == lit.args:
                return b
        return None

    def size(self) -> int:
        return sum(len(v) for v in self._index.values())

    # ------------------------------------------------------------ update
    def add(self, lit: Literal, front: bool = True) -> Literal | None:
        """Add a ground belief; returns the literal for the ``+b`` event, or None if nothing new.

        When the belief is already held, only new annotations are added and the event carries
        just those annotations (Jason's behaviour).
        """
        key = (lit.functor, len(lit.args), lit.neg)
        lst = self._index.get(key)
        if lst is None:
            self._index[key] = [lit]
            return lit
        args = lit.args
        for i, b in enumerate(lst):
            if type(b) is Literal and b.args == args:
                new = [a for a in lit.annots if a not in b.annots]
                if not new:
                    return None
                lst[i] = b.add_annots(new)
                return lit
        lst2 = list(lst)
        if front:
            lst2.insert(0, lit)
        else:
            lst2.append(lit)
        self._index[key] = lst2
        return lit

    def add_rule(self, rule: Rule, front: bool = False) -> None:
        key = rule.head.key
        lst = list(self._index.get(key, ()))
        if front:
            lst.insert(0, rule)
        else:
            lst.append(rule)
        self._index[key] = lst

    def remove(self, lit: Literal) -> Literal | None:
        """Remove ``lit``'s annotations from the stored belief (whole belief when no source is
        left). Returns the literal for the ``-b`` event or None if nothing was removed."""
        key = (lit.functor, len(lit.args), lit.neg)
        lst = self._index.get(key)
        if not lst:
            return None
        args = lit.args
        for i, b in enumerate(lst):
            if type(b) is Literal and b.args == args:
                if b.annots == lit.annots:  # fast path: the whole belief goes
                    if len(lst) == 1:
                        del self._index[key]
                    else:
                        self._index[key] = lst[:i] + lst[i + 1:]
                    return b
                if not lit.annots:
                    removed_annots: tuple = b.annots
                    remaining: tuple = ()
                else:
                    if not all(a in b.annots for a in lit.annots):
                        s: dict = {}
                        if not unify(lit, b, s):
                            return None
                    removed_annots = tuple(a for a in b.annots if a in lit.annots)
                    remaining = tuple(a for a in b.annots if a not in lit.annots)
                    if not removed_annots:
                        return None
                lst2 = list(lst)
                if remaining and any(isinstance(a, Literal) and a.functor == "source" for a in remaining):
                    lst2[i] = b.with_annots(remaining)
                else:
                    del lst2[i]
                if lst2:
                    self._index[key] = lst2
                else:
                    del self._index[key]
                if len(removed_annots) > 1:
                    removed_annots = tuple(sorted(removed_annots, key=sort_key))
                return b.with_annots(removed_annots)
        return None

    def abolish(self, pattern: Literal) -> list[Literal]:
        """Remove every belief unifying with ``pattern`` (any annotations)."""
        lst = self._index.get(pattern.key)
        if not lst:
            return []
        keep, gone = [], []
        for b in lst:
            if isinstance(b, Literal) and unify(pattern.no_annots(), b, {}):
                gone.append(b)
            else:
                keep.append(b)
        if keep:
            self._index[pattern.key] = keep
        else:
            del self._index[pattern.key]
        return gone

    def clear(self) -> None:
        self._index.clear()


def with_source(lit: Literal, src: Any) -> Literal:
    return Literal(lit.functor, lit.args, merge_annots(lit.annots, [src]), lit.tail, lit.neg)
