"""The blocks world of Jason's ``examples/blocks-world``, in Python (world 1, no window)."""

from __future__ import annotations

from itertools import pairwise

from rason.asl.environment import Environment
from rason.asl.terms import Literal

TABLE = "table"
#: the towers of each world, bottom first
WORLDS: dict[str, list[list[str]]] = {
    "1": [["c", "b", "a"], ["e", "d"], ["g", "f"]],
    "2": [],
    "3": [],
}


class BlocksWorld(Environment):
    """Towers of blocks on a table; the agent named ``agent`` perceives ``on(X, Y)`` and can
    ``move(X, Y)`` a clear block onto a clear block or the table.

    Arguments as Jason's: the world (1, 2 or 3), a delay in ms per action (ignored), and
    whether to show a window (only ``no`` here)."""

    #: the agent that perceives the blocks (as in Jason's example)
    VIEWER = "agent"

    def init(self, args: list[str]) -> None:
        world = args[0] if args else "1"
        if world not in WORLDS:
            raise ValueError(f"no world {world!r}: choose one of {sorted(WORLDS)}")
        self.stacks = [[TABLE, *tower] for tower in WORLDS[world]]
        self.clear_percepts(self.VIEWER)
        for s in self.stacks:
            for below, above in pairwise(s):
                self.add_percept(f"on({above},{below})", agent=self.VIEWER)

    def execute_action(self, agent: str, action: Literal) -> bool:
        if action.functor == "move" and len(action.args) == 2:
            block, onto = (str(a) for a in action.args)
            self._move(block, onto)
        else:
            self.log(f"executing: {action}, but it has not been implemented!")
        return True      # as Jason's example: a move that cannot be made does not fail

    def _move(self, block: str, onto: str) -> bool:
        self.log(f"Moving: {block} on top of {onto}", who="WorldModel")
        src = next((s for s in self.stacks if s[-1] == block), None)
        dst = [TABLE] if onto == TABLE else next((s for s in self.stacks if s[-1] == onto), None)
        if src is None or dst is None:
            self.log("Didn't find one of the blocks on top of a stack", who="WorldModel")
            return False
        if onto == TABLE:
            self.stacks.insert(0, dst)
        src.pop()
        self.remove_percept(f"on({block},{src[-1]})", agent=self.VIEWER)
        self.add_percept(f"on({block},{dst[-1]})", agent=self.VIEWER)
        dst.append(block)
        if src == [TABLE]:
            self.stacks.remove(src)
        return True
