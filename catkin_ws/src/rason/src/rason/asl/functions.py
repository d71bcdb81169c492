"""Jason's arithmetic functions (``math.*``, ``jason.functions``) over Python floats.

No term here: :mod:`.unify` evaluates terms with these tables.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterator
from random import Random
from typing import Any, Protocol


class ArithError(Exception):
    """An arithmetic expression could not be evaluated (e.g. unbound or non-numeric)."""


def _java_round(x: float) -> float:
    return float(math.floor(x + 0.5))


ARITH_FUNCTIONS: dict[str, Any] = {
    "math.abs": lambda a: abs(a),
    "math.sqrt": lambda a: math.sqrt(a) if a >= 0 else math.nan,
    "math.round": _java_round,
    "math.floor": lambda a: float(math.floor(a)),
    "math.ceil": lambda a: float(math.ceil(a)),
    "math.max": lambda a, b: max(a, b),
    "math.min": lambda a, b: min(a, b),
    "math.sin": math.sin,
    "math.cos": math.cos,
    "math.tan": math.tan,
    "math.asin": math.asin,
    "math.acos": math.acos,
    "math.atan": math.atan,
    "math.log": lambda a: math.log(a) if a > 0 else (-math.inf if a == 0 else math.nan),
    "math.pi": lambda: math.pi,
    "math.e": lambda: math.e,
}
# (Jason 3.3.2 registers no math.pow/exp/trunc/signum: those stay plain literals)

def _list_only(*args: Any) -> float:
    raise TypeError("needs a list")


def _mean(xs: list) -> float:
    return sum(xs, 0.0) / len(xs) if xs else math.nan


def _median(xs: list, n_items: int) -> float:
    if len(xs) != n_items or not xs:
        raise TypeError("math.median needs a non-empty list of numbers")
    xs = sorted(xs)
    k = len(xs)
    return (xs[k // 2 - 1] + xs[k // 2]) / 2 if k % 2 == 0 else xs[k // 2]


def _std_dev(xs: list) -> float:
    n = len(xs)
    mean = _mean(xs)
    sq = sum(((x - mean) * (x - mean) for x in xs), 0.0)
    return math.sqrt(divide(sq, float(n - 1))) if n != 1 else (math.nan if sq == 0 else math.inf)


#: Jason functions over one list (``jason.functions``): math.max/min of a list start from
#: Java's Double.MIN_VALUE/MAX_VALUE, non-numbers are skipped.
LIST_FUNCTIONS: dict[str, Any] = {
    "math.sum": lambda xs, n: sum(xs, 0.0),
    "math.average": lambda xs, n: _mean(xs),
    "math.mean": lambda xs, n: _mean(xs),
    "math.median": _median,
    "math.std_dev": lambda xs, n: _std_dev(xs),
    "math.max": lambda xs, n: max([5e-324, *xs]),
    "math.min": lambda xs, n: min([1.7976931348623157e308, *xs]),
}
for _name in LIST_FUNCTIONS:
    ARITH_FUNCTIONS.setdefault(_name, _list_only)

class FunctionHost(Protocol):
    """The agent as the agent-dependent functions see it (Jason binds them to their agent):
    ``math.random`` draws from its generator, ``.count(Q)`` counts the solutions of Q, a
    function registered with a rule asks the agent's belief base."""

    @property
    def random(self) -> Random: ...

    def count_solutions(self, query: Any) -> int: ...

    def solve(self, f: Any, s: dict, intention: Any = None) -> Iterator[dict]:
        """Every substitution extending ``s`` under which ``f`` follows from the agent's state."""
        ...

    def clock_millis(self) -> float:
        """``system.time``: milliseconds of the agent's clock (as ``.time(T)``)."""
        ...


def power(a: float, b: float) -> float:
    try:
        r = a ** b
    except ZeroDivisionError:
        return math.inf
    except OverflowError:
        return math.inf
    if isinstance(r, complex):
        return math.nan
    return float(r)


def divide(a: float, b: float) -> float:
    if b == 0:
        if a == 0 or a != a:
            return math.nan
        return math.copysign(math.inf, a) * math.copysign(1.0, b)
    return a / b


def _java_int(x: float) -> int:
    """Java's ``(int) x``: toward zero, NaN is 0, clamped to 32 bits."""
    if x != x:
        return 0
    if x >= 2147483647:
        return 2147483647
    if x <= -2147483648:
        return -2147483648
    return int(x)


def java_int_div(a: float, b: float) -> float:
    # Jason (ArithExpr intdiv): (int) x / (int) y, truncating toward zero
    ia, ib = _java_int(a), _java_int(b)
    if ib == 0:
        raise ArithError("division by zero")
    q = abs(ia) // abs(ib)
    return float(q if (ia >= 0) == (ib >= 0) else -q)


def java_mod(a: float, b: float) -> float:
    # Jason: Java's double remainder (x % y), the sign follows the dividend
    if b == 0 or a != a or b != b or a in (math.inf, -math.inf):
        return math.nan
    return math.fmod(a, b)


#: Functors that evaluate to a number (``math.random`` needs the agent's generator; ``.length``
#: and ``.count`` only with one argument, else they are the internal actions); the functions
#: of :func:`register_function` join them.
ARITH_NAMES: set[str] = set(ARITH_FUNCTIONS) | {"math.random", ".length", ".count", "system.time"}


class UserFunction:
    """A function registered by name (Jason's ``register_function``): ``arity`` arguments,
    computed by the Python ``compute(agent, args)`` or, without it, by the rule (literal,
    internal action) named ``rule``, whose last argument is the result."""

    __slots__ = ("arity", "compute", "rule")

    def __init__(self, arity: int, compute: Callable[[Any, list], float] | None = None,
                 rule: str | None = None) -> None:
        self.arity = arity
        self.compute = compute
        self.rule = rule


#: the registered functions, by name (one registry for the process)
USER_FUNCTIONS: dict[str, UserFunction] = {}


def register_function(name: str, arity: int, compute: Callable[[Any, list], float] | None = None,
                      rule: str | None = None) -> None:
    """Make ``name(A1..An)`` (n = ``arity``) an arithmetic function of every agent of this
    process: ``compute(agent, args)`` gives its value from the arguments (terms, numbers as
    floats), or the first solution of ``rule(A1..An, Result)`` does (Jason's
    ``{ register_function("name", n, "rule") }``). As in Jason, the name has a ``.`` that is
    not its first character and is not one of Jason's own functions; registering a name again
    replaces it. Raises ValueError otherwise."""
    if (compute is None) == (rule is None):
        raise ValueError("register_function: give either a Python function or a rule name")
    if "." not in name:
        raise ValueError(f"The function {name} was not registered! A function must have a '.' "
                         "in its name.")
    if name.startswith("."):
        raise ValueError(f"The function {name} was not registered! An user function name can "
                         "not start with '.'.")
    if name in ARITH_NAMES and name not in USER_FUNCTIONS:
        raise ValueError(f"Can not register the function {name}  twice!")
    if arity < 0:
        raise ValueError(f"register_function {name}: the arity must be 0 or more")
    USER_FUNCTIONS[name] = UserFunction(arity, compute, rule)
    ARITH_NAMES.add(name)
