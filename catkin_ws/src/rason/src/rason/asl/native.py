"""The reasoning cycle's modules compiled to C with mypyc (made by ``setup.sh``; optional).

The modules of :data:`COMPILED` stay plain, typed Python; ``python -m rason.asl native build``
compiles them, as one mypyc group, into a folder named after a checksum of their sources and of
the Python version. ``rason.asl`` puts that folder first on its ``__path__`` only when it matches
the sources on disk, so an edited module runs as Python (never as a stale compiled copy) until
the next build, which ``./run.sh`` makes on its way. ``RASON_NATIVE=0`` runs everything as Python.

The build itself (mypyc, the C compiler, their standard-library helpers) is in
:mod:`.native_build`, imported only to build: every agent imports this module at start-up.

What compiled code asks of these modules (docs/benchmarks.md: "The compiled reasoning cycle"): annotations
that hold at run time (mypyc checks them), no subclass of a builtin container, no class
attribute read as a default value, no method alias in a class body, ``__reduce__`` for every
class that is pickled, and no interpreted subclass of a compiled class.
"""

from __future__ import annotations

import os
import sys
import zlib

#: the modules compiled, in the order of their imports (the rest of rason.asl stays Python)
COMPILED = ("functions", "terms", "plain", "unify", "ia", "logic", "beliefs", "plans", "intentions",
            "selection", "reasoning", "circumstance", "goal_ops", "communication", "runner", "agent")
#: the mypyc group: its shared library is ``rason.asl._native__mypyc``
GROUP = "rason.asl._native"
#: environment variable: "0" runs the Python modules even when a build is there
SWITCH = "RASON_NATIVE"

_HERE = os.path.dirname(os.path.abspath(__file__))
#: where builds go: ``catkin_ws/src/rason/native/<stamp>`` (git ignores it)
BUILDS = os.path.normpath(os.path.join(_HERE, "..", "..", "..", "native"))
#: written last by a build: a folder without it is a build that did not finish
COMPLETE = "COMPLETE"


def source_stamp() -> str:
    """A checksum of the compiled modules' sources and of this Python's version."""
    crc = zlib.crc32(sys.implementation.cache_tag.encode("utf-8"))
    for name in COMPILED:
        with open(os.path.join(_HERE, name + ".py"), "rb") as f:
            crc = zlib.crc32(f.read(), crc)
    return f"{crc:08x}"


def build_folder() -> str:
    """The folder of the build for the sources on disk (it may not exist)."""
    return os.path.join(BUILDS, source_stamp())


def native_path() -> list[str]:
    """The folders to put before ``rason.asl``'s own: the current build, when there is one and
    ``RASON_NATIVE`` is not "0"."""
    if os.environ.get(SWITCH, "1") == "0":
        return []
    folder = build_folder()
    return [folder] if os.path.isfile(os.path.join(folder, COMPLETE)) else []


def in_use() -> bool:
    """True when this process runs the compiled modules."""
    from . import agent

    return not (agent.__file__ or "").endswith(".py")
