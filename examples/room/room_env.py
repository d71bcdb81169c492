"""The room of Jason's ``examples/room``, in Python: a door the porter locks and unlocks."""

from __future__ import annotations

from rason.asl.environment import Environment
from rason.asl.terms import Literal

LOCKED = "locked(door)"
UNLOCKED = "~locked(door)"


class RoomEnv(Environment):
    """Everyone perceives whether the door is locked; ``lock`` and ``unlock`` change it."""

    def init(self, args: list[str]) -> None:
        self.locked = True
        self.add_percept(LOCKED)

    def execute_action(self, agent: str, action: Literal) -> bool:
        print(f"Agent {agent} is doing {action}", flush=True)
        if action.functor == "lock":
            self.locked = True
        elif action.functor == "unlock":
            self.locked = False
        self.clear_percepts()
        self.add_percept(LOCKED if self.locked else UNLOCKED)
        self.inform_agents_changed()
        return True
