"""Building the compiled modules of :mod:`.native` (``python -m rason.asl native build``,
run by ``setup.sh``): mypyc in a child process, then the C compiler; kept apart from
:mod:`.native` so that an agent's start-up imports none of this."""

from __future__ import annotations

import glob
import os
import shutil
import subprocess
import sys
import tempfile
import time

from .native import BUILDS, COMPILED, COMPLETE, GROUP, SWITCH, build_folder

_HERE = os.path.dirname(os.path.abspath(__file__))


def build(force: bool = False, log: str | None = None) -> str:
    """Compile :data:`COMPILED` for the sources on disk unless already done; remove older
    builds. Returns the build's folder. Raises ``RuntimeError`` (with the compiler's last
    lines) when mypyc or the C compiler fails."""
    folder = build_folder()
    if os.path.isfile(os.path.join(folder, COMPLETE)) and not force:
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
        with open(os.path.join(staging, COMPLETE), "w", encoding="utf-8") as f:
            f.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')} {' '.join(COMPILED)}\n")
        shutil.rmtree(folder, ignore_errors=True)
        os.replace(staging, folder)
    for old in glob.glob(os.path.join(BUILDS, "*")):
        if os.path.abspath(old) != os.path.abspath(folder):
            shutil.rmtree(old, ignore_errors=True)
    return folder


_COMPILE = "import sys; from rason.asl.native_build import compile_into; compile_into(sys.argv[1])"


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
