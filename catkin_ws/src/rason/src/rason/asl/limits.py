"""How deep and how long a text every reader of terms accepts (the one home of these limits).

Messages and perceptions come from anyone on the ROS graph. A term nested 100,000 deep
(about 300 kB of text) once crashed an agent node (SIGSEGV: the compiled plain-term reader
recursed on the C stack), and every later step that walks a term (printing, unifying,
checking numbers) recurses too. So every reader refuses, with an :class:`AslSyntaxError`
(the node logs a warning and goes on):

* a term's text longer than :data:`MAX_TERM_CHARS` (a message's content, one percept),
* a program's text longer than :data:`MAX_SOURCE_CHARS` (an ``.asl`` file, a told plan),
* a term nested deeper than :data:`MAX_TERM_DEPTH` (arguments, list elements, list tails,
  operands and annotations each count one level).

The depth is far beyond what programs write and leaves room under Python's default recursion
limit (1000 frames) for the modules that walk terms when they run as plain Python
(``RASON_NATIVE=0``).
"""

from __future__ import annotations

from typing import Any

from .terms import ArithExpr, ListTerm, Literal, LogExpr, NsLit, RelExpr, Rule

#: The deepest term any reader accepts (levels of nesting).
MAX_TERM_DEPTH = 200
#: The longest text of one term (characters): a message's content, a percept.
MAX_TERM_CHARS = 1_000_000
#: The longest program text (characters): an ``.asl`` file, a plan sent as text.
MAX_SOURCE_CHARS = 10_000_000
#: The LALR parser's deepest state stack: one level of nesting pushes at most 8 states (a plan
#: term's body), so every text within MAX_TERM_DEPTH fits; what fits is then measured exactly.
MAX_PARSE_STACK = 8 * MAX_TERM_DEPTH + 64

_EXPRESSIONS = (ArithExpr, RelExpr, LogExpr)


def deeper_than(term: Any, limit: int = MAX_TERM_DEPTH) -> bool:
    """True when ``term`` nests deeper than ``limit`` levels (walked without recursion)."""
    stack: list[tuple[Any, int]] = [(term, 0)]
    while stack:
        t, depth = stack.pop()
        if depth > limit:
            return True
        tt = type(t)
        below = depth + 1
        if tt is Literal:
            stack.extend((a, below) for a in t.args)
            stack.extend((a, below) for a in t.annots)
            if t.tail is not None:
                stack.append((t.tail, below))
        elif tt is ListTerm:
            stack.extend((a, below) for a in t.items)
            if t.tail is not None:
                stack.append((t.tail, below))
        elif tt in _EXPRESSIONS:
            stack.append((t.left, below))
            if t.right is not None:
                stack.append((t.right, below))
        elif tt is Rule:
            stack.append((t.head, below))
            stack.append((t.body, below))
        elif tt is NsLit:
            stack.append((t.lit, below))
    return False


def too_deep(what: str = "term") -> str:
    """The error message of a text nested deeper than the limit."""
    return f"{what} nested deeper than {MAX_TERM_DEPTH} levels (rason.asl.limits.MAX_TERM_DEPTH)"


def too_long(length: int, limit: int, what: str) -> str:
    """The error message of a text longer than ``limit``."""
    return f"{what} of {length} characters, longer than the limit of {limit}"
