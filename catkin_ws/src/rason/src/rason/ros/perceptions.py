"""The perception table of an agent (thesis 5.2), without rospy.

Synthesizers publish ``Perception(source, [literal, ...])``: each message is the complete current
list of that source. In ``replace`` mode (the thesis' filtering) a message replaces its source's
list and the agent's percepts are the union over sources; only the newest message per source is
ever parsed. In ``queue`` mode (the thesis' unfiltered baseline, Table 5.1) every message is
kept until the agent perceives, and each one is parsed and applied in turn.

Malformed perception strings (and numbers that are not finite: ``NaN``, ``Infinity``) are dropped
and the rest of the message still counts; they are logged once per source and text, at most once
a second per source, shortened, with bounded memory (:class:`~rosnode_kit.badinput.BadInputLog`).
An agent may also declare which functors and sources it wants.

A source may have a time to live (TTL): when it has been silent for longer than that, its list
is cleared as if it had published ``[]`` (:meth:`PerceptionTable.expire`), so a dead camera or
synthesizer never leaves an old ``robot(...)`` belief behind. Times are whatever clock the
caller passes (ROS time in the agent node).
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from typing import Generic, TypeVar

from rason.asl import Literal, parse_literal
from rason.asl.terms import non_finite_part
from rason.ros.feedback import split_top_level
from rosnode_kit.badinput import BadInputLog, shorten

L = TypeVar("L")

REPLACE = "replace"
QUEUE = "queue"


#: perception strings longer than this are parsed every time, never cached
MAX_CACHED_TEXT = 1024


def parse_percept(text: str) -> Literal:
    """One perception string as a ground-number-safe literal; ValueError (or the parser's
    syntax error) for malformed text or a number that is not finite."""
    lit = parse_literal(text)
    bad = non_finite_part(lit)
    if bad is not None:
        raise ValueError(f"{bad} is not a finite number")
    return lit


@dataclass
class PerceptionFilter:
    """Which percepts an agent wants: functors (``robot`` or ``robot/4``) and sources.

    Empty sets mean everything.
    """

    functors: frozenset[str] = frozenset()
    sources: frozenset[str] = frozenset()

    @classmethod
    def from_lists(cls, functors: Iterable[str] = (), sources: Iterable[str] = ()) -> PerceptionFilter:
        return cls(frozenset(f.strip() for f in functors if f.strip()),
                   frozenset(s.strip() for s in sources if s.strip()))

    def wants_source(self, source: str) -> bool:
        return not self.sources or source in self.sources

    def wants_text(self, text: str) -> bool:
        """Cheap pre-parse check on the literal's text: its functor (and arity when given)."""
        if not self.functors:
            return True
        name = text.lstrip().lstrip("~")
        cut = len(name)
        for i, ch in enumerate(name):
            if ch in "([ ":
                cut = i
                break
        functor = name[:cut]
        if functor in self.functors:
            return True
        return f"{functor}/{_arity(name[cut:])}" in self.functors


def _arity(rest: str) -> int:
    """Number of top-level arguments in ``(a, f(b, c), "x,y")...``; 0 if no parentheses."""
    rest = rest.lstrip()
    if not rest.startswith("("):
        return 0
    args, _, _ = split_top_level(rest[1:])
    return 0 if args == [""] else len(args)


@dataclass
class PerceptionStats:
    """Counters for the perception benchmark and the mind service."""

    messages: int = 0
    filtered_messages: int = 0
    parsed: int = 0
    malformed: int = 0
    filtered_literals: int = 0


@dataclass
class SourceClock:
    """A perception source with a time to live, and when it was last heard (seconds)."""

    ttl: float
    last: float


@dataclass
class PerceptionTable(Generic[L]):
    """Per-source perception lists, fed from ROS callbacks, read by the agent's perceive().

    Args:
        parse: turns one perception string into a literal; raises ValueError (or a subclass,
            such as the interpreter's syntax error) for malformed text.
        warn: where warnings about malformed perception strings go (rate-limited: see
            :class:`~rosnode_kit.badinput.BadInputLog`).
        mode: ``replace`` (per-source replacement) or ``queue`` (every message is applied).
        ttl: a source's time to live in seconds (``0`` = its list stands until replaced);
            asked with each message of the source, so it must be cheap.
        now: the clock of the warnings' rate limit (ROS time in a node).
    """

    parse: Callable[[str], L]
    warn: Callable[[str], None] = print
    mode: str = REPLACE
    now: Callable[[], float] = time.monotonic
    filter: PerceptionFilter = field(default_factory=PerceptionFilter)
    stats: PerceptionStats = field(default_factory=PerceptionStats)
    ttl: Callable[[str], float] = lambda _source: 0.0

    def __post_init__(self) -> None:
        if self.mode not in (REPLACE, QUEUE):
            raise ValueError(f"perception mode must be {REPLACE!r} or {QUEUE!r}, not {self.mode!r}")
        self._lock = threading.Lock()
        self._raw: dict[str, Sequence[str]] = {}      # newest unparsed list per source
        self._texts: dict[str, list[str]] = {}        # the list in effect per source (replace)
        self._queue: list[tuple[str, Sequence[str]]] = []
        self._parsed: dict[str, list[L]] = {}         # current parsed list per source
        self.bad_input = BadInputLog(self.warn, self.now)
        self._changed = False
        self._cache: dict[str, L | None] = {}
        self._heard: dict[str, SourceClock] = {}     # sources with a TTL: when last heard
        self._bad_ttl: set[str] = set()               # sources whose TTL was unusable (warned)
        self._expired: set[str] = set()               # cleared, not yet seen by percepts()

    def update(self, source: str, perceptions: Sequence[str], now: float | None = None) -> bool:
        """Store one message (thread-safe) received at time `now` (needed for TTLs).

        Returns False when the agent has nothing new: the filter drops the whole source, or (in
        ``replace`` mode) the list is the one already in effect for the source (a synthesizer
        repeating itself at 20 Hz costs the agent no reasoning cycle).
        """
        self.stats.messages += 1
        if not self.filter.wants_source(source):
            self.stats.filtered_messages += 1
            return False
        ttl = self._ttl_of(source) if now is not None else 0.0
        with self._lock:
            if ttl > 0 and now is not None:
                self._heard[source] = SourceClock(ttl, now)
            if self.mode == REPLACE:
                texts = list(perceptions)
                if self._texts.get(source) == texts:
                    return False
                self._texts[source] = texts
                self._raw[source] = perceptions
            else:
                self._queue.append((source, perceptions))
            self._changed = True
        return True

    def watches_silence(self) -> bool:
        """True while a source with a time to live holds a list (:meth:`expire` has work)."""
        return bool(self._heard)

    def _ttl_of(self, source: str) -> float:
        try:
            ttl = float(self.ttl(source))
            if not math.isfinite(ttl) or ttl < 0:
                raise ValueError(f"{ttl} is not a number of seconds >= 0")
        except (TypeError, ValueError) as err:
            if source not in self._bad_ttl:
                self._bad_ttl.add(source)
                self.warn(f"perception source '{source}': unusable time to live ({err}); "
                          "its list stands until replaced")
            return 0.0
        return ttl

    def expire(self, now: float) -> list[str]:
        """Clear the lists of sources silent for longer than their TTL; return those sources.

        A cleared source counts as a change, so the next :meth:`percepts` call gives the union
        without it (the agent gets the usual ``-`` events). A clock that jumped backwards
        (simulation restarted) restarts the source's silence at `now`.
        """
        expired: list[str] = []
        with self._lock:
            for source, heard in list(self._heard.items()):
                if now < heard.last:
                    heard.last = now
                elif now - heard.last > heard.ttl:
                    expired.append(source)
                    del self._heard[source]
                    self._raw.pop(source, None)
                    self._texts.pop(source, None)
                    self._queue = [(s, texts) for s, texts in self._queue if s != source]
                    self._expired.add(source)
                    self._changed = True
        return expired

    def changed(self) -> bool:
        """True if a message arrived since the last :meth:`percepts` call."""
        return self._changed

    def percepts(self) -> list[L] | None:
        """The union of all sources' current lists, or None if nothing changed since last call."""
        with self._lock:
            if not self._changed:
                return None
            self._changed = False
            raw, self._raw = self._raw, {}
            queue, self._queue = self._queue, []
            expired, self._expired = self._expired, set()
        for source in expired:
            self._parsed.pop(source, None)
        for source, texts in queue:
            self._parsed[source] = self._parse_list(source, texts)
        for source, texts in raw.items():
            self._parsed[source] = self._parse_list(source, texts)
        union: list[L] = []
        seen: set[L] = set()
        for literals in self._parsed.values():
            for literal in literals:
                if literal not in seen:
                    seen.add(literal)
                    union.append(literal)
        return union

    def sources(self) -> dict[str, int]:
        """Known sources and how many percepts each currently holds."""
        return {source: len(lits) for source, lits in self._parsed.items()}

    def _parse_list(self, source: str, texts: Sequence[str]) -> list[L]:
        out: list[L] = []
        for text in texts:
            if not self.filter.wants_text(text):
                self.stats.filtered_literals += 1
                continue
            literal = self._parse_one(source, text)
            if literal is not None:
                out.append(literal)
        return out

    def _parse_one(self, source: str, text: str) -> L | None:
        if text in self._cache:
            literal = self._cache[text]
        else:
            self.stats.parsed += 1
            try:
                literal = self.parse(text)
            except Exception as err:
                literal = None
                self._note_malformed(source, text, err)
            if len(text) <= MAX_CACHED_TEXT:
                if len(self._cache) > 4096:
                    self._cache.clear()
                self._cache[text] = literal
        if literal is None:
            self.stats.malformed += 1
            self._note_malformed(source, text, None)
        return literal

    def _note_malformed(self, source: str, text: str, err: Exception | None) -> None:
        reason = f": {shorten(str(err))}" if err else ""
        self.bad_input.warn(source, text, f"dropped malformed perception from source "
                                          f"'{shorten(source, 80)}': {shorten(repr(text))}{reason}")
