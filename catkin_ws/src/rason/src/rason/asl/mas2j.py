"""Reader for Jason ``.mas2j`` project files, parsed with a lark grammar of Jason 3.3's MAS
language: ``infrastructure``, ``environment``, ``executionControl`` (with ``at``), ``agents``
(file, options, ``agentArchClass``, ``agentClass``, ``beliefBaseClass``, ``#N``, ``at``),
``directives``, ``classpath`` and ``aslSourcePath``.

What has no meaning in a local or ROS run (infrastructures, Java classes, hosts) is parsed and
reported once in :attr:`MasProject.notes`. ``environment:`` names a Python class for a local run
(:mod:`.environment`).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Any

from lark import Lark, Transformer, v_args
from lark.exceptions import LarkError, UnexpectedInput

from .parser import LEXICON, AslSyntaxError, cached_lark, describe_syntax_error, jason_jar_places


@dataclass
class AgentSpec:
    """One agent of a project: its name and its ``.asl`` file."""

    name: str
    asl_path: str
    arch_class: str | None = None
    options: dict = field(default_factory=dict)
    agent_class: str | None = None
    bb_class: str | None = None
    host: str | None = None
    #: the line of the project file that declares the agent
    line: int = 0


@dataclass
class MasProject:
    name: str
    agents: list[AgentSpec]
    path: str
    infrastructure: str | None = None
    environment: str | None = None
    notes: list[str] = field(default_factory=list)
    source_path: list[str] = field(default_factory=list)
    directives: dict[str, str] = field(default_factory=dict)
    classpath: list[str] = field(default_factory=list)
    execution_control: str | None = None


MAS2J_GRAMMAR = r"""
start: "MAS" ID "{" section* "}"
?section: infra | env | control | agents | directives | classpath | sourcepath
infra: "infrastructure" ":" class_def
env: "environment" ":" class_def [at]
control: "executionControl" ":" class_def [at]
agents: "agents" ":" agent*
agent: ID [file_name] [options] agent_extra* ";"
?agent_extra: "agentArchClass" class_def  -> arch_class
            | "agentClass" class_def      -> agent_class
            | "beliefBaseClass" class_def -> bb_class
            | "#" NUMBER                  -> count
            | at
at: "at" STRING
file_name: [PATH] ID ["." ID]
options: "[" option ("," option)* "]"
option: ID "=" opt_value
?opt_value: STRING | ID | NUMBER | opt_list | ID "/" NUMBER -> opt_indicator
opt_list: "[" [opt_value ("," opt_value)*] "]"
directives: "directives" ":" (ID "=" class_def ";")+
classpath: "classpath" ":" (STRING ";")+
sourcepath: "aslSourcePath" ":" (STRING ";")+
class_def: dotted [class_params]
dotted: ID ("." ID)*
class_params: "(" [param ("," param)*] ")"
?param: class_def | NUMBER | STRING | param_list
param_list: "[" param ("," param)* "]"

PATH: /(\.\/|\/|\\|[A-Za-z]:)([A-Za-z0-9_\-.]*[\/\\])*/
ID: /[A-Za-z_][A-Za-z0-9_]*/
""" + LEXICON

_lark: Lark | None = None


def _get_lark() -> Lark:
    global _lark
    if _lark is None:
        _lark = cached_lark(MAS2J_GRAMMAR)
    return _lark


def _unquote(s: str) -> str:
    return s[1:-1].replace('\\"', '"') if s.startswith('"') else s


@v_args(meta=True)
class _ToProject(Transformer):
    def dotted(self, meta: Any, c: list) -> str:
        return ".".join(str(x) for x in c)

    def class_params(self, meta: Any, c: list) -> str:
        return "(" + ", ".join(str(x) for x in c if x is not None) + ")"

    def class_def(self, meta: Any, c: list) -> str:
        return c[0] + (c[1] or "")

    def param_list(self, meta: Any, c: list) -> str:
        return "[" + ", ".join(str(x) for x in c) + "]"

    def opt_list(self, meta: Any, c: list) -> str:
        return "[" + ", ".join(_unquote(str(x)) for x in c if x is not None) + "]"

    def opt_indicator(self, meta: Any, c: list) -> str:
        return f"{c[0]}/{c[1]}"

    def option(self, meta: Any, c: list) -> tuple:
        return (str(c[0]), _unquote(str(c[1])))

    def options(self, meta: Any, c: list) -> dict:
        return dict(c)

    def file_name(self, meta: Any, c: list) -> str:
        path, name, ext = c
        return (str(path) if path else "") + str(name) + "." + (str(ext) if ext else "asl")

    def at(self, meta: Any, c: list) -> tuple:
        return ("at", _unquote(str(c[0])))

    def arch_class(self, meta: Any, c: list) -> tuple:
        return ("arch", c[0])

    def agent_class(self, meta: Any, c: list) -> tuple:
        return ("agent_class", c[0])

    def bb_class(self, meta: Any, c: list) -> tuple:
        return ("bb_class", c[0])

    def count(self, meta: Any, c: list) -> tuple:
        return ("count", int(float(str(c[0]))))

    def agent(self, meta: Any, c: list) -> tuple:
        return ("agent", (str(c[0]), c[1], c[2] or {}, c[3:], meta))

    def agents(self, meta: Any, c: list) -> tuple:
        return ("agents", c)

    def infra(self, meta: Any, c: list) -> tuple:
        return ("infrastructure", c[0])

    def env(self, meta: Any, c: list) -> tuple:
        return ("environment", (c[0], c[1]))

    def control(self, meta: Any, c: list) -> tuple:
        return ("control", (c[0], c[1]))

    def directives(self, meta: Any, c: list) -> tuple:
        return ("directives", {str(c[k]): c[k + 1] for k in range(0, len(c), 2)})

    def classpath(self, meta: Any, c: list) -> tuple:
        return ("classpath", [_unquote(str(x)) for x in c])

    def sourcepath(self, meta: Any, c: list) -> tuple:
        return ("sourcepath", [_unquote(str(x)) for x in c])

    def start(self, meta: Any, c: list) -> tuple:
        return (str(c[0]), c[1:])


def _fix_path(p: str, base_dir: str) -> list[str]:
    """A source-path entry: a relative one is looked up from the project's folder, then from
    the current folder (Jason runs projects from either)."""
    if os.path.isabs(p):
        return [p]
    return [os.path.join(base_dir, p), os.path.abspath(p)]


def parse_mas2j(text: str, path: str = "<mas2j>", source_path: list[str] | None = None) -> MasProject:
    """Parse the text of a ``.mas2j`` file; raises :class:`AslSyntaxError`. ``source_path``:
    folders searched for agents' files before the project's ``aslSourcePath``."""
    try:
        tree = _get_lark().parse(text)
        name, sections = _ToProject().transform(tree)
    except UnexpectedInput as e:
        line = getattr(e, "line", -1)
        col = getattr(e, "column", -1)
        if line is None or line < 1:
            line, col = text.count("\n") + 1, len(text) - (text.rfind("\n") + 1) + 1
        raise AslSyntaxError(path, line, col, describe_syntax_error(e)) from None
    except LarkError as e:
        raise AslSyntaxError(path, 1, 1, str(e).splitlines()[0] if str(e) else "invalid project") from None
    base_dir = os.path.dirname(os.path.abspath(path)) if path != "<mas2j>" else os.getcwd()
    proj = MasProject(name, [], path)
    proj.source_path.extend(os.path.abspath(d) for d in source_path or ())
    decls: list = []
    for kind, value in sections:
        if kind == "infrastructure":
            proj.infrastructure = value
            proj.notes.append(f"infrastructure '{value}' ignored: agents run locally")
        elif kind == "environment":
            proj.environment = value[0]
            proj.notes.append(f"environment '{value[0]}' is a Python class for local runs "
                              "(rason.asl.environment); the ROS host does not load it")
            if value[1]:
                proj.notes.append(f"environment 'at \"{value[1][1]}\"' ignored: it runs in this process")
        elif kind == "control":
            proj.execution_control = value[0]
            proj.notes.append(f"executionControl '{value[0]}' ignored: agents run asynchronously")
        elif kind == "directives":
            proj.directives.update(value)
            proj.notes.append(f"user directives {sorted(value)} ignored: Java directive classes "
                              "cannot be loaded")
        elif kind == "classpath":
            proj.classpath.extend(value)
            proj.notes.append("classpath ignored: no Java classes are loaded")
        elif kind == "sourcepath":
            for p in value:
                if p.startswith("$"):   # inside Jason's jar: its folders in a Jason tree, if named
                    proj.source_path.extend(d for d in jason_jar_places(p)
                                            if os.path.isdir(d) and d not in proj.source_path)
                    continue
                proj.source_path.extend(d for d in _fix_path(p, base_dir) if d not in proj.source_path)
        elif kind == "agents":
            decls.extend(v for _, v in value)
    search = [*proj.source_path, base_dir]
    for agname, fname, opts, extras, meta in decls:
        asl_file = fname or agname + ".asl"
        spec_kw: dict = {"line": getattr(meta, "line", 0)}
        n = 1
        for ek, ev in extras:
            if ek == "count":
                n = ev
            elif ek == "arch":
                spec_kw["arch_class"] = ev
            elif ek == "agent_class":
                spec_kw["agent_class"] = ev   # loaded by a local run (rason.asl.hooks)
            elif ek == "bb_class":
                spec_kw["bb_class"] = ev      # loaded by a local run (rason.asl.hooks)
            elif ek == "at":
                spec_kw["host"] = ev
                proj.notes.append(f"agent {agname}: 'at \"{ev}\"' ignored: agents run in this process")
        for opt in opts:
            if opt in _UNUSED_OPTIONS:
                proj.notes.append(f"agent {agname}: option {opt}={opts[opt]} has no effect here")
            elif opt == "verbose" and str(opts[opt]).strip('"') == "2":
                proj.notes.append(f"agent {agname}: verbose=2 shows what verbose=1 shows "
                                  "(Jason's debugging logs are not reproduced)")
        asl_path = next((os.path.normpath(os.path.join(d, asl_file)) for d in search
                         if os.path.isfile(os.path.join(d, asl_file))), None)
        if asl_path is None:
            asl_path = asl_file if os.path.isabs(asl_file) else os.path.join(search[0], asl_file)
        names = [agname] if n == 1 else [f"{agname}{k}" for k in range(1, n + 1)]
        for nm in names:
            proj.agents.append(AgentSpec(nm, asl_path, options=dict(opts), **spec_kw))
    return proj


#: Jason agent options that rason does not implement (it behaves as their defaults)
_UNUSED_OPTIONS = frozenset({"events", "intBels", "nrcbp", "synchronised", "queries",
                             "mindinspector"})


def load_mas2j(path: str, source_path: list[str] | None = None) -> MasProject:
    """Read and parse a ``.mas2j`` file (``source_path``: as for :func:`parse_mas2j`)."""
    with open(path, encoding="utf-8") as f:
        return parse_mas2j(f.read(), str(path), source_path)
