"""Command line: ``python -m rason.asl run FILE.mas2j|FILE.asl [--timeout S] [--seed N] [--no-tro]
[--max-intention-depth N] [--internal-actions MODULE] [--source-path DIR]``; ``python -m rason.asl native
build|status`` (the compiled modules, :mod:`.native`)."""

from __future__ import annotations

import argparse
import sys

from . import native
from .agent import AgentOptions
from .classdef import ClassLoadError
from .ia import ModuleLoadError, load_modules
from .parser import AslSyntaxError
from .runtime import run_file


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="rason.asl", description="Jason-compatible AgentSpeak interpreter")
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run", help="run a .mas2j project or a single .asl agent locally")
    r.add_argument("file")
    r.add_argument("--timeout", type=float, default=None, help="give up after S seconds (exit 1)")
    r.add_argument("--seed", type=int, default=None, help="seed for .random / math.random")
    r.add_argument("--no-tro", dest="tro", action="store_false",
                   help="turn tail-recursion optimisation off (Jason's tro=false)")
    r.add_argument("--max-intention-depth", type=int, default=AgentOptions().max_intention_depth,
                   metavar="N", help="fail an intention deeper than N intended means "
                   f"(default {AgentOptions().max_intention_depth})")
    r.add_argument("--internal-actions", metavar="MODULE", action="append", default=[],
                   help="import this Python module first: its @internal_action functions "
                        "become internal actions of every agent (repeatable)")
    r.add_argument("--source-path", metavar="DIR", action="append", default=[],
                   help="look for the project's agent files in DIR first (repeatable), e.g. "
                        "a Jason source tree's example folder")
    n = sub.add_parser("native", help="compile the reasoning cycle's modules with mypyc, or say "
                       "whether they are in use")
    n.add_argument("action", choices=("build", "status"))
    n.add_argument("--force", action="store_true", help="build even if the current build exists")
    n.add_argument("--log", help="keep the compiler's output in this file")
    args = ap.parse_args(argv)
    if args.cmd == "native":
        return _native(args.action, args.force, args.log)
    try:
        load_modules(args.internal_actions)
    except ModuleLoadError as e:
        print(str(e), file=sys.stderr)
        return 2
    sys.setrecursionlimit(max(sys.getrecursionlimit(), 20000))
    try:
        options = AgentOptions(tro=args.tro, max_intention_depth=args.max_intention_depth)
        _, ok = run_file(args.file, args.timeout, args.seed, options=options,
                         source_path=args.source_path)
    except (AslSyntaxError, ClassLoadError) as e:   # ClassLoadError: environment, agent classes
        print(str(e), file=sys.stderr)
        return 2
    except OSError as e:
        print(f"{args.file}: {e.strerror or e}", file=sys.stderr)
        return 2
    except UnicodeDecodeError as e:   # a project file that is not UTF-8
        print(f"{args.file}: not UTF-8 text (byte {e.start}); save the file as UTF-8", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    if not ok:
        print(f"timeout after {args.timeout} s: agents still busy", file=sys.stderr)
        return 1
    return 0


def _native(action: str, force: bool, log: str | None) -> int:
    if action == "status":
        print(f"compiled modules {'in use' if native.in_use() else 'not in use'} "
              f"(build for these sources: {native.build_folder()})")
        return 0
    # (imported here: running an agent needs none of the build's tools)
    from . import native_build

    try:
        print(native_build.build(force=force, log=log))
    except RuntimeError as e:
        print(str(e), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
