"""Node parameters declared once: read, checked, and documented from one dataclass.

Every node of the workspace states its private parameters as a frozen dataclass whose fields
carry the default and the one line of documentation::

    @dataclass(frozen=True)
    class BeepParams:
        volume: float = param(0.5, "loudness from 0 to 1", minimum=0.0, maximum=1.0)
        sound: str = required("name of the sound to play")

    params = load(BeepParams)              # reads ~volume, ~sound; ParamError if invalid
    print(help_text(BeepParams, "rosrun my_pkg beep"))   # what --help prints

:func:`load` reads ``~name`` for every field (the default when it is not set), converts it to the
field's type, and rejects what does not fit (wrong type, non-finite numbers, out of range) with a
:class:`ParamError` naming the parameter. :func:`help_text` prints the table that the nodes'
``--help`` shows and that README links to, so each parameter's doc lives in one place.
"""

from __future__ import annotations

import copy
import dataclasses
import difflib
import math
import re
import sys
import types
import typing
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import Any, TypeVar

import rospy
import yaml

from rosnode_kit.rosout import cache_rosout_setting
from rosnode_kit.signals import init_node

T = TypeVar("T")

_REQUIRED = object()


class ParamError(ValueError):
    """A private parameter is missing, of the wrong type, or out of range; ``name`` (without
    ``~``) is the parameter at fault when one is."""

    def __init__(self, message: str, name: str | None = None) -> None:
        super().__init__(message)
        self.name = name


def param(default: Any, doc: str, *, minimum: float | None = None,
          maximum: float | None = None) -> Any:
    """A parameter with a default; numbers must be finite and within [minimum, maximum]."""
    metadata = {"doc": doc, "minimum": minimum, "maximum": maximum}
    if isinstance(default, (list, dict)):       # mutable: a fresh copy per instance
        return dataclasses.field(default_factory=lambda: copy.copy(default), metadata=metadata)
    return dataclasses.field(default=default, metadata=metadata)


def required(doc: str) -> Any:
    """A parameter the node cannot start without."""
    return dataclasses.field(default=_REQUIRED, metadata={"doc": doc, "minimum": None,
                                                           "maximum": None})


#: The types a parameter may have, by the name its annotation gives them.
_NAMED_KINDS: dict[str, type] = {"bool": bool, "int": int, "float": float, "str": str,
                                 "list": list, "List": list, "dict": dict, "Dict": dict,
                                 "None": type(None)}
#: ``int | None`` and ``list[str]`` at run time (3.10+; absent on the robots' Python 3.8).
_UNION_TYPES = (typing.Union, getattr(types, "UnionType", typing.Union))


def _kinds(hint: Any) -> tuple[tuple[type, ...], bool]:
    """The accepted Python types of a field's annotation (a type, or its text as
    ``from __future__ import annotations`` leaves it), and whether None is allowed.

    The text is read here rather than evaluated (``typing.get_type_hints``), so that
    ``float | None`` and ``list[str]`` work on Python 3.8 (the robots' Noetic) as on 3.11."""
    if isinstance(hint, str):
        return _kinds_of_text(hint)
    args = typing.get_args(hint) if typing.get_origin(hint) in _UNION_TYPES else (hint,)
    kinds = tuple(typing.get_origin(a) or a for a in args if a is not type(None))
    return kinds, type(None) in args


def _kinds_of_text(text: str) -> tuple[tuple[type, ...], bool]:
    optional = re.fullmatch(r"\s*(?:typing\.)?Optional\[(.*)\]\s*", text)
    parts = [optional.group(1), "None"] if optional else re.split(r"\|(?![^\[]*\])", text)
    names = [re.sub(r"^(?:typing\.)?(\w+).*$", r"\1", part.strip(), flags=re.S)
             for part in parts]
    unknown = [name for name in names if name not in _NAMED_KINDS]
    if unknown:
        raise ParamError(f"unsupported parameter type {text!r}")
    kinds = tuple(_NAMED_KINDS[name] for name in names if name != "None")
    return kinds, "None" in names


def _convert(name: str, value: Any, hint: Any, spec: dataclasses.Field) -> Any:
    kinds, optional = _kinds(hint)
    if value is None:
        if optional:
            return None
        raise ParamError(f"~{name}: a value is required", name)
    if bool in kinds:
        if isinstance(value, bool):
            return value
        raise ParamError(f"~{name}: expected true or false, got {value!r}", name)
    if float in kinds or int in kinds:
        if isinstance(value, str):      # YAML reads 1e9 or nan as text: take them as numbers
            try:
                value = float(value)
            except ValueError:
                raise ParamError(f"~{name}: expected a number, got {value!r}", name) from None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParamError(f"~{name}: expected a number, got {value!r}", name)
        if not math.isfinite(value):
            raise ParamError(f"~{name}: must be finite, got {value!r}", name)
        if int in kinds and float not in kinds:
            if value != int(value):
                raise ParamError(f"~{name}: expected a whole number, got {value!r}", name)
            value = int(value)
        else:
            value = float(value)
        low, high = spec.metadata["minimum"], spec.metadata["maximum"]
        if low is not None and value < low:
            raise ParamError(f"~{name}: must be at least {low}, got {value}", name)
        if high is not None and value > high:
            raise ParamError(f"~{name}: must be at most {high}, got {value}", name)
        return value
    if dict in kinds:
        if isinstance(value, str):
            try:
                value = yaml.safe_load(value) if value.strip() else {}
            except yaml.YAMLError as err:
                raise ParamError(f"~{name}: not a map: {value!r} ({err})", name) from err
        if not isinstance(value, dict):
            raise ParamError(f"~{name}: expected a map, got {value!r}", name)
        return {str(k): v for k, v in value.items()}
    if list in kinds:
        if isinstance(value, str):
            value = [v.strip() for v in value.strip("[]").split(",") if v.strip()]
        if not isinstance(value, list):
            raise ParamError(f"~{name}: expected a list, got {value!r}", name)
        return [str(v) for v in value]
    if str in kinds:
        return str(value)
    raise ParamError(f"~{name}: unsupported parameter type {hint!r}", name)


def parse(cls: type[T], given: dict[str, Any]) -> T:
    """The parameters of ``cls`` from a ``{name: value}`` mapping (names without ``~``)."""
    values: dict[str, Any] = {}
    for spec in dataclasses.fields(cls):  # type: ignore[arg-type]
        if spec.name in given:
            values[spec.name] = _convert(spec.name, given[spec.name], spec.type, spec)
        elif spec.default is _REQUIRED:
            raise ParamError(f"~{spec.name} is required: {spec.metadata['doc']}", spec.name)
    return cls(**values)


def with_value(params: T, name: str, text: str, allowed: Iterable[str] | None = None) -> T:
    """A copy of ``params`` (a parameter dataclass) with ``name`` set from ``text`` (YAML, as
    ``_name:=text`` on a rosrun line), checked as :func:`load` checks it; ParamError (and
    ``params`` unchanged) for an unknown name, one outside ``allowed``, or a bad value."""
    specs = {spec.name: spec for spec in dataclasses.fields(params)}  # type: ignore[arg-type]
    if name not in specs or (allowed is not None and name not in set(allowed)):
        known = sorted(allowed) if allowed is not None else sorted(specs)
        raise ParamError(f"~{name} cannot be set here; these can: {', '.join(known)}", name)
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        value = text
    spec = specs[name]
    return dataclasses.replace(params, **{name: _convert(name, value, spec.type, spec)})  # type: ignore[type-var]


def unknown_names(cls: type, names: Iterable[str]) -> list[str]:
    """A warning for each of ``names`` (private parameters set for the node) that ``cls`` does
    not declare, naming the closest declared one: a typo is otherwise silently ignored."""
    known = [spec.name for spec in dataclasses.fields(cls)]
    warnings = []
    for name in sorted(set(names) - set(known)):
        close = difflib.get_close_matches(name, known, n=1)
        hint = (f"did you mean ~{close[0]}?" if close
                else f"this node's are: {', '.join('~' + k for k in known) or 'none'}")
        warnings.append(f"unknown private parameter ~{name} (ignored); {hint}")
    return warnings


def _private_names() -> set[str]:
    """The names (without ``~``) of the private parameters set for this node."""
    prefix = rospy.get_name().rstrip("/") + "/"
    return {name[len(prefix):].split("/")[0] for name in rospy.get_param_names()
            if name.startswith(prefix)}


def load(cls: type[T]) -> T:
    """The node's private parameters of ``cls`` from the parameter server; a private parameter
    that ``cls`` does not declare is warned about (see :func:`unknown_names`)."""
    for warning in unknown_names(cls, _private_names()):
        rospy.logwarn("%s: %s", rospy.get_name(), warning)
    given = {spec.name: rospy.get_param(f"~{spec.name}")
             for spec in dataclasses.fields(cls)  # type: ignore[arg-type]
             if rospy.has_param(f"~{spec.name}")}
    return parse(cls, given)


def forget(error: ParamError) -> str:
    """Delete the parameter at fault from the parameter server, so that the corrected command
    (which may leave the parameter out) does not read the same bad value again; what to add to
    the error message about it."""
    if error.name is None:
        return ("(private parameters stay on the parameter server after the node exits: "
                f"clear one with rosparam delete {rospy.get_name()}/NAME)")
    key = f"{rospy.get_name()}/{error.name}"
    try:
        if not rospy.has_param(key):         # a required parameter left out: nothing to clear
            return ""
        rospy.delete_param(key)
    except (KeyError, OSError) as err:   # already gone, or the master is unreachable
        return f"(could not clear it: {err}; run rosparam delete {key})"
    return f"({key} was deleted from the parameter server)"


def _default_text(spec: dataclasses.Field) -> str:
    if spec.default is _REQUIRED:
        return "required"
    if spec.default is not dataclasses.MISSING:
        return repr(spec.default)
    return repr(spec.default_factory())  # type: ignore[operator]


def rows(cls: type) -> list[tuple[str, str, str]]:
    """``(~name, default, doc)`` for every parameter of ``cls``."""
    return [(f"~{spec.name}", _default_text(spec), spec.metadata["doc"])
            for spec in dataclasses.fields(cls)]


def table_text(cls: type) -> str:
    """The parameter table of ``cls`` as plain text (an argparse epilog, a --help page)."""
    table = rows(cls)
    if not table:
        return "private parameters: none"
    width = max(len(name) for name, _, _ in table) + 2
    dwidth = max(len(default) for _, default, _ in table) + 2
    lines = ["private parameters (_name:=value on the rosrun line):"]
    lines += [f"  {name:<{width}}{default:<{dwidth}}{doc}" for name, default, doc in table]
    return "\n".join(lines)


def help_text(cls: type, usage: str, summary: str = "") -> str:
    """What the node's ``--help`` prints: usage, summary, and the parameter table."""
    lines = [f"usage: {usage}", ""]
    if summary:
        lines += [summary.strip(), ""]
    return "\n".join(lines) + table_text(cls)


def exit_on_help(argv: Sequence[str], cls: type, usage: str, summary: str = "") -> None:
    """Print :func:`help_text` and exit 0 when ``argv`` asks for ``-h``/``--help``."""
    if "-h" in argv[1:] or "--help" in argv[1:]:
        print(help_text(cls, usage, summary))
        raise SystemExit(0)


def load_or_exit(cls: type[T], node: str) -> T:
    """:func:`load`, or a clear one-line error and exit status 2 for a bad parameter."""
    try:
        return load(cls)
    except ParamError as error:
        exit_rejected(error, node)


def exit_rejected(error: ParamError, node: str) -> typing.NoReturn:
    """Report a rejected parameter on one line (clearing it, see :func:`forget`); exit 2."""
    message = f"{node}: {error} {forget(error)}".rstrip()
    rospy.logfatal(message)
    print(message, file=sys.stderr)
    raise SystemExit(2) from None


def start_node(build: Callable[[], T], params: type, node_name: str, argv: Sequence[str],
               usage: str | None, summary: str) -> T | None:
    """The common start of a node: ``--help`` prints the parameter table of ``params`` and exits;
    otherwise ``rospy.init_node(node_name)`` and ``build()``. Returns None (after a clear
    message) when ``build`` rejects its parameters with a ValueError: the caller exits 2."""
    exit_on_help(argv, params, usage or f"{Path(argv[0]).name} [__ns:=/robot] [_name:=value ...]",
                 summary)
    init_node(node_name, argv=list(argv))
    cache_rosout_setting()
    try:
        return build()
    except ValueError as err:            # parameters that do not fit together
        message = f"{node_name}: {err} {forget(ParamError(str(err)))}"
        rospy.logfatal(message)
        print(message, file=sys.stderr)
        return None
