"""Node parameters declared once (rosnode_kit.params): conversion, checks and the --help table."""

from __future__ import annotations

import math
import subprocess
from dataclasses import dataclass

import pytest

from rosnode_kit.params import (
    ParamError,
    _kinds,
    help_text,
    param,
    parse,
    required,
    unknown_names,
    with_value,
)


@dataclass(frozen=True)
class Example:
    path: str = required("where the thing is")
    speed: float = param(0.2, "m/s", minimum=0.0, maximum=1.0)
    count: int = param(3, "how many", minimum=1)
    rate: float | None = param(None, "Hz, default from elsewhere", minimum=0.0)
    enabled: bool = param(True, "on or off")
    names: list = param([], "who may talk")


def test_defaults_and_conversions():
    p = parse(Example, {"path": "/x", "speed": 1, "count": 4.0, "names": "[a, b]"})
    assert (p.path, p.speed, p.count, p.rate, p.enabled, p.names) == ("/x", 1.0, 4, None, True,
                                                                      ["a", "b"])
    assert isinstance(p.speed, float) and isinstance(p.count, int)
    assert parse(Example, {"path": "/x", "names": ["c"]}).names == ["c"]
    assert parse(Example, {"path": "/x"}).names == []
    assert parse(Example, {"path": "/x", "speed": "1e-1"}).speed == 0.1   # YAML's text "1e-1"


@pytest.mark.parametrize("given, message", [
    ({}, "~path is required"),
    ({"path": "/x", "speed": 1e9}, "~speed: must be at most 1.0"),
    ({"path": "/x", "speed": -0.1}, "~speed: must be at least 0.0"),
    ({"path": "/x", "speed": math.nan}, "~speed: must be finite"),
    ({"path": "/x", "speed": "nan"}, "~speed: must be finite"),
    ({"path": "/x", "rate": math.inf}, "~rate: must be finite"),
    ({"path": "/x", "speed": "fast"}, "~speed: expected a number"),
    ({"path": "/x", "count": 2.5}, "~count: expected a whole number"),
    ({"path": "/x", "enabled": "yes"}, "~enabled: expected true or false"),
    ({"path": "/x", "speed": True}, "~speed: expected a number"),
])
def test_bad_values_are_rejected_with_the_parameter_named(given, message):
    with pytest.raises(ParamError, match=message.replace("[", r"\[")):
        parse(Example, given)


def test_help_lists_every_parameter_with_default_and_doc():
    text = help_text(Example, "rosrun pkg node", "Does things.")
    assert text.startswith("usage: rosrun pkg node")
    for name, default, doc in (("~path", "required", "where the thing is"),
                               ("~speed", "0.2", "m/s"), ("~names", "[]", "who may talk")):
        line = next(line for line in text.splitlines() if line.strip().startswith(name + " "))
        assert default in line and doc in line


def test_sim_node_help_is_its_parameter_table():
    out = subprocess.run(["rosrun", "turtlebot_sim", "sim", "--help"], capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "~world" in out.stdout and "case_study.yaml" in out.stdout
    assert "~real_time_factor" in out.stdout


@pytest.mark.parametrize("annotation, kinds", [
    ("float | None", ((float,), True)), ("list[str]", ((list,), False)),
    ("Optional[int]", ((int,), True)), ("typing.Optional[str]", ((str,), True)),
    ("dict[str, list[str]] | None", ((dict,), True)), (float, ((float,), False)),
    (int | None, ((int,), True)), (list[str], ((list,), False)),
])
def test_annotations_are_read_as_text_without_evaluating_them(annotation, kinds):
    """``from __future__ import annotations`` leaves text that Python 3.8 (the robots' Noetic)
    cannot evaluate (``float | None``): the parameter types are read from it instead."""
    assert _kinds(annotation) == kinds


def test_an_unknown_parameter_type_is_a_clear_error():
    @dataclass(frozen=True)
    class Odd:
        where: complex = param(1j, "a complex number")

    with pytest.raises(ParamError, match=r"unsupported parameter type 'complex'"):
        parse(Odd, {"where": 1})


def test_unknown_names_suggest_the_closest_declared_parameter():
    warnings = unknown_names(Example, ["path", "sped", "zzz"])
    assert warnings == [
        "unknown private parameter ~sped (ignored); did you mean ~speed?",
        "unknown private parameter ~zzz (ignored); "
        "this node's are: ~path, ~speed, ~count, ~rate, ~enabled, ~names"]
    assert unknown_names(Example, ["path", "speed"]) == []


def test_with_value_sets_one_checked_parameter_from_text():
    p = parse(Example, {"path": "/x"})
    assert with_value(p, "speed", "0.5").speed == 0.5
    assert with_value(p, "enabled", "false").enabled is False
    assert with_value(p, "path", "/y", allowed=["path"]).path == "/y"
    with pytest.raises(ParamError, match=r"~speed: must be at most 1\.0"):
        with_value(p, "speed", "2")
    with pytest.raises(ParamError, match="cannot be set here; these can: speed"):
        with_value(p, "count", "2", allowed=["speed"])
    with pytest.raises(ParamError, match="~sped cannot be set here"):
        with_value(p, "sped", "0.1")
    assert p.speed == 0.2                       # the original is unchanged
