"""Jason 3.3's mutable collection terms: sets, maps and queues (``.set.*``, ``.map.*``,
``.queue.*`` internal actions in :mod:`rason.asl.stdlib.containers`).

As in Jason they are changed in place and never copied by unification, belief addition or
``resolve``: every variable bound to one sees its changes. Sets and maps keep their members in
the standard order of terms; a queue is first-in first-out, or a binary heap in that order
(``priority``) kept exactly as Java's ``PriorityQueue`` keeps it, since its printing and
``.queue.to_list`` show the heap's array.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Iterable, Iterator
from typing import Any

from .terms import ListTerm, Literal, list_to_python, sort_key, term_str

#: how each kind of collection is written in a term's text between processes
#: (:func:`~rason.asl.terms.term_text`): a literal of this functor around a list of members
WIRE_SET, WIRE_MAP, WIRE_QUEUE, WIRE_PRIORITY_QUEUE = "$set", "$map", "$queue", "$priority_queue"


class SetTerm:
    """A set of terms in the standard order (Jason's ``SetTermImpl``), printed ``{a,b}``."""

    __slots__ = ("_members",)

    def __init__(self, items: Iterable = ()) -> None:
        self._members: dict[tuple, Any] = {}
        for t in items:
            self.add(t)

    def add(self, t: Any) -> None:
        self._members.setdefault(sort_key(t), t)

    def remove(self, t: Any) -> None:
        self._members.pop(sort_key(t), None)

    def contains(self, t: Any) -> bool:
        return sort_key(t) in self._members

    def keep_only(self, items: Iterable) -> None:
        keep = {sort_key(t) for t in items}
        for k in [k for k in self._members if k not in keep]:
            del self._members[k]

    def clear(self) -> None:
        self._members.clear()

    def copy(self) -> SetTerm:
        out = SetTerm()
        out._members = dict(self._members)
        return out

    def items(self) -> list:
        return [self._members[k] for k in sorted(self._members)]

    def __iter__(self) -> Iterator:
        return iter(self.items())

    def __len__(self) -> int:
        return len(self._members)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, SetTerm) and self._members.keys() == other._members.keys()

    def __hash__(self) -> int:
        return hash("SetTerm")   # content changes in place: a constant keeps __eq__ consistent

    def __str__(self) -> str:
        return "{" + ",".join(term_str(t) for t in self.items()) + "}"

    __repr__ = __str__

    def wire(self) -> Literal:
        """This set as a plain term, for its text between processes (:func:`from_wire`)."""
        return Literal(WIRE_SET, (ListTerm(tuple(self.items())),))


class MapTerm:
    """A map from terms to terms, keys in the standard order (Jason's ``MapTermImpl``),
    printed ``{k->v,...}``."""

    __slots__ = ("_entries",)

    def __init__(self) -> None:
        self._entries: dict[tuple, tuple[Any, Any]] = {}

    def put(self, key: Any, value: Any) -> None:
        self._entries[sort_key(key)] = (key, value)

    def get(self, key: Any) -> Any | None:
        e = self._entries.get(sort_key(key))
        return None if e is None else e[1]

    def remove(self, key: Any) -> Any | None:
        e = self._entries.pop(sort_key(key), None)
        return None if e is None else e[1]

    def clear(self) -> None:
        self._entries.clear()

    def copy(self) -> MapTerm:
        out = MapTerm()
        out._entries = dict(self._entries)
        return out

    def entries(self) -> list[tuple[Any, Any]]:
        return [self._entries[k] for k in sorted(self._entries)]

    def __len__(self) -> int:
        return len(self._entries)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, MapTerm) and self._entries.keys() == other._entries.keys() and all(
            sort_key(v) == sort_key(other._entries[k][1]) for k, (_, v) in self._entries.items())

    def __hash__(self) -> int:
        return hash("MapTerm")

    def __str__(self) -> str:
        return "{" + ",".join(f"{term_str(k)}->{term_str(v)}" for k, v in self.entries()) + "}"

    __repr__ = __str__

    def wire(self) -> Literal:
        """This map as a plain term (a list of ``[Key, Value]`` pairs), see :func:`from_wire`."""
        return Literal(WIRE_MAP, (ListTerm(tuple(ListTerm((k, v)) for k, v in self.entries())),))


class QueueTerm:
    """A queue of terms: first-in first-out, or (``priority``) a binary heap in the standard
    order with Java's ``PriorityQueue`` sift rules. Printed as Java prints a collection:
    ``[a, b]``."""

    __slots__ = ("_fifo", "_heap", "priority")

    def __init__(self, priority: bool = False) -> None:
        self.priority = priority
        self._fifo: deque = deque()
        self._heap: list[tuple[tuple, Any]] = []

    def offer(self, t: Any) -> None:
        if not self.priority:
            self._fifo.append(t)
            return
        heap = self._heap
        item = (sort_key(t), t)
        k = len(heap)
        heap.append(item)
        while k > 0:
            parent = (k - 1) >> 1
            if item[0] >= heap[parent][0]:
                break
            heap[k] = heap[parent]
            k = parent
        heap[k] = item

    def peek(self) -> Any | None:
        if not self.priority:
            return self._fifo[0] if self._fifo else None
        return self._heap[0][1] if self._heap else None

    def poll(self) -> Any | None:
        if not self.priority:
            return self._fifo.popleft() if self._fifo else None
        heap = self._heap
        if not heap:
            return None
        result = heap[0][1]
        last = heap.pop()
        n = len(heap)
        if n:
            k, half = 0, n >> 1
            while k < half:
                child = 2 * k + 1
                right = child + 1
                if right < n and heap[child][0] > heap[right][0]:
                    child = right
                if last[0] <= heap[child][0]:
                    break
                heap[k] = heap[child]
                k = child
            heap[k] = last
        return result

    def clear(self) -> None:
        self._fifo.clear()
        self._heap.clear()

    def copy(self) -> QueueTerm:
        out = QueueTerm(self.priority)
        out._fifo = deque(self._fifo)
        out._heap = list(self._heap)
        return out

    def items(self) -> list:
        return list(self._fifo) if not self.priority else [t for _, t in self._heap]

    def contains(self, t: Any) -> bool:
        return any(x == t for x in self.items())

    def __len__(self) -> int:
        return len(self._heap) if self.priority else len(self._fifo)

    def __iter__(self) -> Iterator:
        return iter(self.items())

    def __str__(self) -> str:
        return "[" + ", ".join(term_str(t) for t in self.items()) + "]"

    __repr__ = __str__

    def wire(self) -> Literal:
        """This queue as a plain term (a priority queue's members in its heap's order, so it
        reads back exactly as it was), see :func:`from_wire`."""
        return Literal(WIRE_PRIORITY_QUEUE if self.priority else WIRE_QUEUE,
                       (ListTerm(tuple(self.items())),))


def collection_items(t: Any) -> list | None:
    """The members of a list, set or queue term (Java's ``Collection`` arguments), else None."""
    if isinstance(t, (SetTerm, QueueTerm)):
        return t.items()
    if isinstance(t, ListTerm):
        return list_to_python(t)
    return None


def _wire_collection(t: Literal) -> Any:
    """The collection a wire literal (:meth:`SetTerm.wire`...) stands for, or None."""
    if len(t.args) != 1 or t.annots or t.neg:
        return None
    members = list_to_python(t.args[0])
    if members is None:
        return None
    members = [from_wire(m) for m in members]
    if t.functor == WIRE_SET:
        return SetTerm(members)
    if t.functor == WIRE_MAP:
        out = MapTerm()
        for pair in members:
            kv = list_to_python(pair)
            if kv is None or len(kv) != 2:
                return None
            out.put(kv[0], kv[1])
        return out
    queue = QueueTerm(t.functor == WIRE_PRIORITY_QUEUE)
    if queue.priority:
        queue._heap = [(sort_key(m), m) for m in members]   # the sender's heap, as it was
    else:
        queue._fifo.extend(members)
    return queue


_WIRE_FUNCTORS = frozenset({WIRE_SET, WIRE_MAP, WIRE_QUEUE, WIRE_PRIORITY_QUEUE})


def from_wire(t: Any) -> Any:
    """A term read from another process's text with its collections made again (the wire
    literals of :meth:`SetTerm.wire`, :meth:`MapTerm.wire`, :meth:`QueueTerm.wire`)."""
    if isinstance(t, Literal):
        if t.functor in _WIRE_FUNCTORS:
            made = _wire_collection(t)
            if made is not None:
                return made
        if not t.args and not t.annots:
            return t
        args = tuple(from_wire(a) for a in t.args)
        annots = tuple(from_wire(a) for a in t.annots)
        if args == t.args and annots == t.annots:
            return t
        return Literal(t.functor, args, annots, t.tail, t.neg)
    if isinstance(t, ListTerm):
        items = tuple(from_wire(a) for a in t.items)
        tail = from_wire(t.tail) if t.tail is not None else None
        return t if items == t.items and tail == t.tail else ListTerm(items, tail)
    return t
