"""The two water jugs (5 and 3 litres) of Jason's ``examples/water-jugs``, in Python."""

from __future__ import annotations

from rason.asl.environment import Environment
from rason.asl.terms import Literal

#: the jugs' capacities in litres
CAPACITIES = (5, 3)


class Jugs(Environment):
    """The agent perceives ``jug(Capacity, Litres)`` for each jug and can ``fill(J)``,
    ``empty(J)`` and ``pour(From, To)`` (into the other jug, until it is full)."""

    def init(self, args: list[str]) -> None:
        self.water = dict.fromkeys(CAPACITIES, 0)
        self._show()

    def execute_action(self, agent: str, action: Literal) -> bool:
        self.log(f"doing {action}")
        try:
            jug = int(action.args[0])
        except (IndexError, TypeError, ValueError):
            return False
        if jug not in self.water:
            return False
        if action.functor == "fill":
            self.water[jug] = jug
        elif action.functor == "empty":
            self.water[jug] = 0
        elif action.functor == "pour":
            other = next(j for j in CAPACITIES if j != jug)
            litres = min(self.water[jug], other - self.water[other])
            self.water[jug] -= litres
            self.water[other] += litres
        else:
            return False
        self._show()
        self.inform_agents_changed()
        return True

    def _show(self) -> None:
        self.clear_percepts()
        for jug in CAPACITIES:
            self.add_percept(f"jug({jug},{self.water[jug]})")
