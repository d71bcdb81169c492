"""rason.asl: a Jason-3-compatible AgentSpeak interpreter in pure Python.

The package follows Jason's split: ``terms``/``parser`` (asSyntax), ``unify``/``logic``
(unification and logical consequence), ``beliefs``/``plans``/``intentions`` (belief base, plan
library, circumstance), ``reasoning`` (the transition system), ``stdlib`` (internal actions),
``arch`` (agent architecture), ``mas2j``/``runtime``/``cli`` (projects and the local runner).
"""

from typing import TYPE_CHECKING

from .native import native_path

# the compiled modules first, when they were built from these very sources (see .native)
__path__[:0] = native_path()

from .agent import Agent, AgentOptions, load_agent_source
from .arch import AgentArch, Clock, Message, UnknownReceiver, VirtualClock, WallClock
from .functions import register_function
from .ia import ModuleLoadError, internal_action, load_modules
from .parser import AslSyntaxError, parse_literal, parse_source, parse_term, parse_term_text
from .runtime import LocalArch, LocalMas, run_file
from .selection import Option, Selection
from .terms import ListTerm, Literal, Var, format_number, term_str, term_text

if TYPE_CHECKING:
    from .mas2j import MasProject, load_mas2j, parse_mas2j

#: names of the ``.mas2j`` reader, imported on first use (it needs lark; a lone agent does not)
_MAS2J_NAMES = ("MasProject", "load_mas2j", "parse_mas2j")


def __getattr__(name: str) -> object:
    if name in _MAS2J_NAMES:
        from . import mas2j

        return getattr(mas2j, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

__all__ = [
    "Agent", "AgentArch", "AgentOptions", "AslSyntaxError", "Clock", "ListTerm", "Literal",
    "LocalArch", "LocalMas", "MasProject", "Message", "ModuleLoadError", "Option", "Selection",
    "UnknownReceiver", "Var",
    "VirtualClock", "WallClock", "format_number", "internal_action", "load_agent_source",
    "load_mas2j", "load_modules", "parse_literal", "parse_mas2j", "parse_source", "parse_term",
    "parse_term_text", "register_function", "run_file", "term_str", "term_text",
]
