"""rason.asl: a Jason-3-compatible AgentSpeak interpreter in pure Python.

The package follows Jason's split: ``terms``/``parser`` (asSyntax), ``unify``/``logic``
(unification and logical consequence), ``beliefs``/``plans``/``intentions`` (belief base, plan
library, circumstance), ``reasoning`` (the transition system), ``stdlib`` (internal actions),
``arch`` (agent architecture), ``mas2j``/``runtime``/``cli`` (projects and the local runner).
"""

from .agent import Agent, AgentOptions, load_agent_source
from .arch import AgentArch, Clock, Message, UnknownReceiver, VirtualClock, WallClock
from .mas2j import MasProject, load_mas2j, parse_mas2j
from .parser import AslSyntaxError, parse_literal, parse_source, parse_term, parse_term_text
from .runtime import LocalArch, LocalMas, run_file
from .stdlib import ModuleLoadError, internal_action, load_modules
from .terms import ListTerm, Literal, Var, format_number, term_str, term_text

__all__ = [
    "Agent", "AgentArch", "AgentOptions", "AslSyntaxError", "Clock", "ListTerm", "Literal",
    "LocalArch", "LocalMas", "MasProject", "Message", "ModuleLoadError", "UnknownReceiver", "Var",
    "VirtualClock", "WallClock", "format_number", "internal_action", "load_agent_source",
    "load_mas2j", "load_modules", "parse_literal", "parse_mas2j", "parse_source", "parse_term",
    "parse_term_text", "run_file", "term_str", "term_text",
]
