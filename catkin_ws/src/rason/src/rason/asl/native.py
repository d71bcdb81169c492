"""The reasoning cycle's modules compiled to C with mypyc (made by ``setup.sh``; optional).

The modules of :data:`COMPILED` stay plain, typed Python; ``python -m rason.asl native build``
compiles them, as one mypyc group, into a folder named after a checksum of their sources and of
the Python version. ``rason.asl`` puts that folder first on its ``__path__`` only when it matches
the sources on disk, so an edited module runs as Python (never as a stale compiled copy) until
the next build, which ``./run.sh`` makes on its way. ``RASON_NATIVE=0`` runs everything as Python.

What compiled code asks of these modules (docs/benchmarks.md: "The compiled reasoning cycle"): annotations
that hold at run time (mypyc checks them), no subclass of a builtin container, no class
attribute read as a default value, no method alias in a class body, ``__reduce__`` for every
class that is pickled, and no interpreted subclass of a compiled class.
"""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time
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
_COMPLETE = "COMPLETE"


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
    return [folder] if os.path.isfile(os.path.join(folder, _COMPLETE)) else []


def in_use() -> bool:
    """True when this process runs the compiled modules."""
    from . import agent

    return not (agent.__file__ or "").endswith(".py")


def build(force: bool = False, log: str | None = None) -> str:
    """Compile :data:`COMPILED` for the sources on disk unless already done; remove older
    builds. Returns the build's folder. Raises ``RuntimeError`` (with the compiler's last
    lines) when mypyc or the C compiler fails."""
    folder = build_folder()
    if os.path.isfile(os.path.join(folder, _COMPLETE)) and not force:
        return folder
    os.makedirs(BUILDS, exist_ok=True)
    package_root = os.path.dirname(os.path.dirname(_HERE))     # the folder holding rason/
    with tempfile.TemporaryDirectory(prefix="rason-native-") as tmp:
        log_path = log or os.path.join(tmp, "build.log")
        with open(log_path, "w", encoding="utf-8") as out:
            done = subprocess.run([sys.executable, "-c", _COMPILE, tmp],
                                  cwd=package_root, stdout=out, stderr=subprocess.STDOUT,
                                  env={**os.environ, SWITCH: "0"}, check=False)
        if done.returncode != 0:
            with open(log_path, encoding="utf-8", errors="replace") as f:
                tail = "".join(f.readlines()[-25:])
            raise RuntimeError(f"mypyc build failed (exit {done.returncode}):\n{tail}")
        built = os.path.join(tmp, "lib", *GROUP.split(".")[:-1])
        staging = folder + f".{os.getpid()}.tmp"
        shutil.rmtree(staging, ignore_errors=True)
        os.makedirs(staging)
        for so in glob.glob(os.path.join(built, "*.so")):
            shutil.copy2(so, staging)
        with open(os.path.join(staging, _COMPLETE), "w", encoding="utf-8") as f:
            f.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')} {' '.join(COMPILED)}\n")
        shutil.rmtree(folder, ignore_errors=True)
        os.replace(staging, folder)
    for old in glob.glob(os.path.join(BUILDS, "*")):
        if os.path.abspath(old) != os.path.abspath(folder):
            shutil.rmtree(old, ignore_errors=True)
    return folder


_COMPILE = "import sys; from rason.asl.native import compile_into; compile_into(sys.argv[1])"


def compile_into(tmp: str) -> None:
    """In a child process whose working folder holds ``rason/``: mypyc, then the C compiler."""
    from mypyc.build import mypycify
    from setuptools import setup

    paths = [os.path.join("rason", "asl", name + ".py") for name in COMPILED]
    # --config-file= : no mypy configuration but these options (the project's is for linting)
    extensions = mypycify(["--config-file=", "--ignore-missing-imports", *paths], group_name=GROUP,
                          target_dir=os.path.join(tmp, "c"))
    setup(name="rason_asl_native", ext_modules=extensions,
          script_args=["build_ext", "--build-lib", os.path.join(tmp, "lib"),
                       "--build-temp", os.path.join(tmp, "obj"), "--parallel",
                       str(os.cpu_count() or 1)])
