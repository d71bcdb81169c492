"""The belief base (Jason's ``DefaultBeliefBase``): beliefs and rules indexed by functor/arity."""

from __future__ import annotations

from collections import deque
from typing import Any

from .terms import Literal, Rule, merge_annots, sort_key
from .unify import unify


class BeliefBase:
    """Ordered beliefs and rules per (functor, arity, negation) key.

    A belief is stored once per ``(functor, args, negation)`` with all its annotations merged
    (e.g. several ``source(...)``). Each key keeps its entries in a deque (adding at either end
    is O(1)) and its beliefs by arguments (finding one is O(1)), so adding n beliefs is linear.
    The beliefs of a key are also kept by their first argument (:func:`first_arg_key`), in the
    same order, so a query whose first argument is a constant looks at those only.
    """

    def __init__(self) -> None:
        #: the beliefs and rules of each key, in order (read directly, never changed, by
        #: compiled contexts: see :meth:`live`)
        self.by_key: dict[tuple, deque] = {}
        self._by_args: dict[tuple, dict[tuple, Literal]] = {}
        self._by_first: dict[tuple, dict[Any, list]] = {}    # lists: most hold one belief
        #: per key, how many entries the first-argument index cannot hold (rules, beliefs whose
        #: first argument is a structure): while any, queries of that key look at all entries
        self._unindexed: dict[tuple, int] = {}
        self._snapshots: dict[tuple, tuple] = {}
        self._percepts: dict[Literal, Literal] = {}

    # ------------------------------------------------------------ access
    def candidates(self, key: tuple) -> tuple:
        """Beliefs and rules with this key, in order: a snapshot, unchanged by later updates."""
        snap = self._snapshots.get(key)
        if snap is None:
            entries = self.by_key.get(key)
            if not entries:
                return ()
            snap = self._snapshots[key] = tuple(entries)
        return snap

    def live(self, key: tuple) -> deque | tuple:
        """The beliefs and rules of ``key`` themselves, not a snapshot: only for a reader that
        changes no belief while it iterates (it may change them once it stopped)."""
        return self.by_key.get(key) or ()

    def candidates_by_first(self, key: tuple, first: Any) -> tuple:
        """:meth:`candidates` narrowed to the beliefs whose first argument may unify with
        ``first`` (the query's first argument, its bindings followed): all of them unless
        ``first`` is a constant the index holds."""
        fk = first_arg_key(first)
        if fk is None or self._unindexed.get(key):
            return self.candidates(key)
        by_first = self._by_first.get(key)
        bucket = None if by_first is None else by_first.get(fk)
        return tuple(bucket) if bucket else ()

    def __iter__(self):
        for key in list(self.by_key):
            yield from self.candidates(key)

    def beliefs(self) -> list[Literal]:
        return [b for b in self if isinstance(b, Literal)]

    def rules(self) -> list[Rule]:
        return [b for b in self if isinstance(b, Rule)]

    def find(self, lit: Literal) -> Literal | None:
        """The stored belief with the same functor/args/negation as ``lit`` (annotations ignored)."""
        return self._by_args.get(lit.key, {}).get(lit.args)

    def size(self) -> int:
        return sum(len(v) for v in self.by_key.values())

    # ------------------------------------------------------------ update
    def namespaces(self) -> list[str]:
        """The namespaces of the beliefs (and ``default``, ``kqml``), in the order Jason's map of
        namespace atoms gives them (an atom's hash adds its namespace's)."""
        out = ["default", "kqml"]
        for b in self:
            head = b.head if isinstance(b, Rule) else b
            if isinstance(head, Literal) and "::" in head.functor:
                ns = head.functor.split("::", 1)[0]
                if ns not in out:
                    out.append(ns)
        n = 16
        while len(out) > n * 3 // 4:
            n *= 2
        default_hash = _java_hash("default")

        def bucket(ns: str) -> int:
            h = default_hash if ns == "default" else (_java_hash(ns) + default_hash) & 0xFFFFFFFF
            return ((h ^ (h >> 16)) & 0x7FFFFFFF) & (n - 1)
        return sorted(out, key=bucket)

    def _entries(self, key: tuple) -> deque:
        """The live entries of ``key`` (created if needed), about to change."""
        self._snapshots.pop(key, None)
        entries = self.by_key.get(key)
        if entries is None:
            entries = self.by_key[key] = deque()
            self._by_args[key] = {}
            self._by_first[key] = {}
        return entries

    def _index_first(self, key: tuple, b: Literal, front: bool) -> None:
        """Put belief ``b`` (new in ``key``) in the first-argument index."""
        if b.args:
            fk = b.args[0]
            if type(fk) is not float or fk != fk:   # a number is its own key (first_arg_key)
                fk = first_arg_key(fk)
        else:
            fk = None
        if fk is None:
            self._unindexed[key] = self._unindexed.get(key, 0) + 1
            return
        bucket = self._by_first[key].get(fk)
        if bucket is None:
            self._by_first[key][fk] = [b]
        elif front:
            bucket.insert(0, b)
        else:
            bucket.append(b)

    def _replace_first(self, key: tuple, old: Literal, new: Literal | None) -> None:
        """Put ``new`` where ``old`` is in the first-argument index (None: remove it)."""
        if old.args:
            fk = old.args[0]
            if type(fk) is not float or fk != fk:   # a number is its own key (first_arg_key)
                fk = first_arg_key(fk)
        else:
            fk = None
        if fk is None:
            if new is None:
                self._unindexed[key] -= 1
            return
        by_first = self._by_first[key]
        bucket = by_first[fk]
        if new is None and len(bucket) == 1:    # (old is that one)
            del by_first[fk]
            return
        pos = _position(bucket, old)
        if new is not None:
            bucket[pos] = new
        else:
            del bucket[pos]

    def _reindex_first(self, key: tuple) -> None:
        """Make the first-argument index of ``key`` anew from its entries."""
        self._by_first[key] = {}
        self._unindexed[key] = 0
        for e in self.by_key.get(key, ()):
            if type(e) is Literal:
                self._index_first(key, e, front=False)
            else:
                self._unindexed[key] += 1

    def _replace(self, key: tuple, old: Literal, new: Literal | None) -> None:
        """Put ``new`` where belief ``old`` is (None: remove it)."""
        entries = self._entries(key)
        pos = _position(entries, old)
        self._replace_first(key, old, new)
        if new is None:
            del entries[pos]
            del self._by_args[key][old.args]   # (an emptied key stays: it is likely reused)
        else:
            entries[pos] = new
            self._by_args[key][new.args] = new

    def add(self, lit: Literal, front: bool = True) -> Literal | None:
        """Add a ground belief; returns the literal for the ``+b`` event, or None if nothing new.

        When the belief is already held, only new annotations are added and the event carries
        just those annotations (Jason's behaviour).
        """
        key = (lit.functor, len(lit.args), lit.neg)
        held = self._by_args.get(key)
        if held is None:
            self.by_key[key] = deque((lit,))
            self._by_args[key] = {lit.args: lit}
            self._by_first[key] = {}
            self._index_first(key, lit, front)
            return lit
        b = held.get(lit.args)
        if b is not None:
            new = [a for a in lit.annots if a not in b.annots]
            if not new:
                return None
            self._replace(key, b, b.add_annots(new))
            return lit
        if self._snapshots:
            self._snapshots.pop(key, None)
        if front:
            self.by_key[key].appendleft(lit)
        else:
            self.by_key[key].append(lit)
        held[lit.args] = lit
        fk = lit.args[0] if lit.args else None
        if type(fk) is float and fk == fk:   # inlined _index_first: a number, new in its bucket
            by_first = self._by_first[key]
            if fk not in by_first:
                by_first[fk] = [lit]
                return lit
        self._index_first(key, lit, front)
        return lit

    def add_rule(self, rule: Rule, front: bool = False) -> None:
        entries = self._entries(rule.head.key)
        if front:
            entries.appendleft(rule)
        else:
            entries.append(rule)
        self._unindexed[rule.head.key] = self._unindexed.get(rule.head.key, 0) + 1

    def remove_rule(self, rule: Rule) -> None:
        key = rule.head.key
        self._snapshots.pop(key, None)
        lst = [r for r in self.by_key.get(key, ()) if r is not rule]
        if lst:
            self.by_key[key] = deque(lst)
            self._reindex_first(key)
        else:
            self.by_key.pop(key, None)
            self._by_args.pop(key, None)     # no beliefs either: the key is gone
            self._by_first.pop(key, None)
            self._unindexed.pop(key, None)

    def remove(self, lit: Literal) -> Literal | None:
        """Remove ``lit``'s annotations from the stored belief (whole belief when no source is
        left). Returns the literal for the ``-b`` event or None if nothing was removed."""
        key = (lit.functor, len(lit.args), lit.neg)
        held = self._by_args.get(key)
        b = held.get(lit.args) if held else None
        if b is None or held is None:
            return None
        if b.annots == lit.annots:  # fast path: the whole belief goes
            return self._drop(key, held, b)
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
        if remaining and any(isinstance(a, Literal) and a.functor == "source" for a in remaining):
            self._replace(key, b, b.with_annots(remaining))
        else:
            self._replace(key, b, None)
        if len(removed_annots) > 1:
            removed_annots = tuple(sorted(removed_annots, key=sort_key))
        return b.with_annots(removed_annots)

    def _drop(self, key: tuple, held: dict, b: Literal) -> Literal:
        """Remove the stored belief ``b`` of ``key`` (``held``: its beliefs by arguments) whole;
        returns it."""
        if self._snapshots:
            self._snapshots.pop(key, None)
        entries = self.by_key[key]
        if entries[0] is b:
            entries.popleft()
        else:
            del entries[_position(entries, b)]
        fk = b.args[0] if b.args else None
        if type(fk) is float and fk == fk:   # inlined _replace_first for a number's bucket
            by_first = self._by_first[key]
            bucket = by_first[fk]
            if len(bucket) == 1:
                del by_first[fk]
            else:
                del bucket[_position(bucket, b)]
        else:
            self._replace_first(key, b, None)
        del held[b.args]
        return b

    def remove_first_holding(self, lit: Literal) -> Literal | None:
        """``-+b``'s removal: the first belief of ``lit``'s key (functor, arity, negation) whose
        annotations include all of ``lit``'s loses them (a whole belief when they are all it
        has). Returns the literal for the ``-b`` event, or None when no belief matched."""
        key = (lit.functor, len(lit.args), lit.neg)
        entries = self.by_key.get(key)
        if not entries:
            return None
        annots = lit.annots
        for b in entries:   # the loop ends at the first change
            if type(b) is Literal:
                held_annots = b.annots
                if held_annots == annots:
                    return self._drop(key, self._by_args[key], b)
                if all(a in held_annots for a in annots):
                    return self.remove(b.with_annots(annots))
        return None

    def replace_first_holding(self, lit: Literal) -> tuple[Literal | None, Literal | None]:
        """``-+b`` on the belief base: :meth:`remove_first_holding` then :meth:`add` (at the
        front), returning what each of them returns. In the common case (the belief removed is
        its key's first entry and no other belief has ``lit``'s arguments) ``lit`` takes its
        place in every index, which leaves them as the two steps would."""
        key = (lit.functor, len(lit.args), lit.neg)
        entries = self.by_key.get(key)
        b = entries[0] if entries else None
        if entries is None or type(b) is not Literal or b.annots != lit.annots:
            return self.remove_first_holding(lit), self.add(lit, front=True)
        held = self._by_args[key]
        args = lit.args
        other = held.get(args)
        if other is not None and other is not b:
            return self.remove_first_holding(lit), self.add(lit, front=True)
        if self._snapshots:
            self._snapshots.pop(key, None)
        entries[0] = lit
        del held[b.args]
        held[args] = lit
        old_fk = b.args[0] if b.args else None
        new_fk = args[0] if args else None
        by_first = self._by_first[key]
        if (type(old_fk) is float and old_fk == old_fk and type(new_fk) is float and new_fk == new_fk
                and new_fk not in by_first and len(by_first[old_fk]) == 1):
            del by_first[old_fk]   # both numbers, each alone in its bucket (the common case)
            by_first[new_fk] = [lit]
        else:
            self._replace_first(key, b, None)
            self._index_first(key, lit, front=True)
        return b, lit

    def abolish(self, pattern: Literal) -> list[Literal]:
        """Remove every belief unifying with ``pattern`` (any annotations)."""
        key = pattern.key
        if key not in self.by_key:
            return []
        keep, gone = [], []
        plain = pattern.no_annots()
        for b in self.by_key[key]:
            if isinstance(b, Literal) and unify(plain, b, {}):
                gone.append(b)
            else:
                keep.append(b)
        entries = self._entries(key)
        entries.clear()
        entries.extend(keep)
        for b in gone:
            del self._by_args[key][b.args]
        self._reindex_first(key)
        return gone

    def clear(self) -> None:
        self.by_key.clear()
        self._by_args.clear()
        self._by_first.clear()
        self._unindexed.clear()
        self._snapshots.clear()


def _java_hash(text: str) -> int:
    """Java's ``String.hashCode`` (as an unsigned 32-bit number)."""
    h = 0
    for ch in text:
        h = (31 * h + ord(ch)) & 0xFFFFFFFF
    return h


def first_arg_key(t: Any) -> Any:
    """How a belief's first argument is kept in the first-argument index: a number or a string
    is its own key, a plain atom is ``("atom", name)``; None (not kept) for a variable, a
    structure, a list, an annotated or negated atom, NaN. Two such terms unify exactly when
    their keys are equal."""
    kind = type(t)
    if kind is float or kind is int:
        return t if t == t else None
    if kind is str:
        return t
    if kind is Literal and not t.args and not t.annots and t.tail is None and not t.neg:
        return ("atom", t.functor)
    return None


def _position(entries: deque | list, b: Literal) -> int:
    """Where the very object ``b`` is in ``entries``."""
    for pos, e in enumerate(entries):
        if e is b:
            return pos
    raise ValueError(f"belief {b} not stored")


def with_source(lit: Literal, src: Any) -> Literal:
    return Literal(lit.functor, lit.args, merge_annots(lit.annots, [src]), lit.tail, lit.neg)
