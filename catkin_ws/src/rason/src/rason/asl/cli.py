"""Command line: ``python -m rason.asl run FILE.mas2j|FILE.asl [--timeout S] [--seed N] [--no-tro]
[--max-intention-depth N] [--internal-actions MODULE] [--source-path DIR]``; ``python -m rason.asl native
build|status`` (the compiled modules, :mod:`.native`)."""

from __future__ import annotations

import sys
from types import SimpleNamespace
from typing import TYPE_CHECKING

from . import native
from .agent import AgentOptions
from .classdef import ClassLoadError
from .ia import ModuleLoadError, load_modules
from .parser import AslSyntaxError
from .runtime import run_file

if TYPE_CHECKING:  # pragma: no cover
    from argparse import ArgumentParser

#: the ``run`` options that take a value: name -> (attribute, conversion, repeatable)
_RUN_VALUES: dict[str, tuple[str, type, bool]] = {
    "--timeout": ("timeout", float, False), "--seed": ("seed", int, False),
    "--max-intention-depth": ("max_intention_depth", int, False),
    "--internal-actions": ("internal_actions", str, True), "--source-path": ("source_path", str, True)}


def quick_run_args(argv: list[str]) -> SimpleNamespace | None:
    """``run FILE [options]`` read as :func:`arg_parser` reads it, when every word is plain: an
    option's exact name, a value that does not start with ``-`` and converts, one file. None
    for anything else (help, an error, an abbreviation, ``native``): the parser reads it."""
    if not argv or argv[0] != "run":
        return None
    args = SimpleNamespace(cmd="run", file=None, timeout=None, seed=None, tro=True,
                           max_intention_depth=AgentOptions().max_intention_depth,
                           internal_actions=[], source_path=[])
    words = iter(argv[1:])
    for word in words:
        if word == "--no-tro":
            args.tro = False
        elif word.startswith("-"):
            name, eq, value = word.partition("=")
            spec = _RUN_VALUES.get(name)
            if spec is None:
                return None
            if not eq:
                value = next(words, "-")
                if value.startswith("-"):
                    return None
            attr, convert, repeatable = spec
            try:
                converted = convert(value)
            except ValueError:
                return None
            if repeatable:
                getattr(args, attr).append(converted)
            else:
                setattr(args, attr, converted)
        elif args.file is None:
            args.file = word
        else:
            return None
    return args if args.file is not None else None


def arg_parser() -> ArgumentParser:
    """The command line's parser (help, errors and every form :func:`quick_run_args` leaves)."""
    # imported here: argparse, gettext, locale and shutil are 3 ms of an agent's 45 ms start,
    # and a plain ``run FILE`` does without them
    from argparse import ArgumentParser

    ap = ArgumentParser(prog="rason.asl", description="Jason-compatible AgentSpeak interpreter")
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
    return ap


def main(argv: list[str] | None = None) -> int:
    words = sys.argv[1:] if argv is None else argv
    args = quick_run_args(words) or arg_parser().parse_args(words)
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
