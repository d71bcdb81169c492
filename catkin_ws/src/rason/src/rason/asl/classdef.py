"""The classes a ``.mas2j`` names (``environment``, ``agentClass``, ``agentArchClass``,
``beliefBaseClass``): a dotted Python name with parameters, and the object it names."""

from __future__ import annotations

import importlib
import os
import sys
from typing import Any


class ClassLoadError(Exception):
    """A class a ``.mas2j`` names cannot be imported, built or initialised (the base of
    :class:`.environment.EnvironmentLoadError` and :class:`.hooks.HookLoadError`, so that the
    command line catches both without importing either module for a lone agent)."""


def split_class_def(text: str) -> tuple[str, list[str]]:
    """``pkg.Cls(1, "a b", x)`` -> ``("pkg.Cls", ["1", "a b", "x"])`` (a ``.mas2j`` class
    definition; quotes removed from string arguments, as Jason's ``getParametersArray``)."""
    name, _, rest = text.partition("(")
    args: list[str] = []
    if rest:
        body = rest.rstrip()[:-1]
        cur, depth, quoted = "", 0, False
        for ch in body:
            if ch == '"' and not cur.endswith("\\"):
                quoted = not quoted
            if not quoted and ch in "([":
                depth += 1
            elif not quoted and ch in ")]":
                depth -= 1
            if ch == "," and depth == 0 and not quoted:
                args.append(cur.strip())
                cur = ""
            else:
                cur += ch
        if cur.strip():
            args.append(cur.strip())
    return name.strip(), [a[1:-1] if len(a) >= 2 and a[0] == a[-1] == '"' else a for a in args]


def import_dotted(name: str, folder: str) -> Any:
    """The object ``pkg.module.attr`` names, its module imported from ``folder`` (put first on
    ``sys.path``) or ``sys.path``; ImportError when it cannot be had."""
    module_name, _, attr = name.rpartition(".")
    if not module_name:
        raise ImportError("write it as module.Name (a Python module importable from the "
                          "project's folder, and a name in it)")
    folder = os.path.abspath(folder)
    if folder not in sys.path:
        sys.path.insert(0, folder)
    module = importlib.import_module(module_name)
    if not hasattr(module, attr):
        raise ImportError(f"module '{module_name}' has no '{attr}'")
    return getattr(module, attr)


__all__ = ["import_dotted", "split_class_def"]
