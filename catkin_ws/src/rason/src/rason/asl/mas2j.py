"""Reader for Jason ``.mas2j`` project files (agents, ``#N`` copies, ``aslSourcePath``...)."""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field

from .parser import AslSyntaxError


@dataclass
class AgentSpec:
    """One agent of a project: its name and its ``.asl`` file."""

    name: str
    asl_path: str
    arch_class: str | None = None
    options: dict = field(default_factory=dict)


@dataclass
class MasProject:
    name: str
    agents: list[AgentSpec]
    path: str
    infrastructure: str | None = None
    environment: str | None = None
    notes: list[str] = field(default_factory=list)


_COMMENT = re.compile(r"//[^\n]*|/\*.*?\*/", re.S)


def _line_col(text: str, pos: int) -> tuple[int, int]:
    line = text.count("\n", 0, pos) + 1
    col = pos - (text.rfind("\n", 0, pos) + 1) + 1
    return line, col


def parse_mas2j(text: str, path: str = "<mas2j>") -> MasProject:
    """Parse the text of a ``.mas2j`` file; raises :class:`AslSyntaxError`."""
    clean = _COMMENT.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)
    m = re.search(r"\bMAS\s+([A-Za-z_][\w.-]*)\s*\{", clean)
    if not m:
        raise AslSyntaxError(path, 1, 1, "expected 'MAS name {'")
    name = m.group(1)
    end = clean.rfind("}")
    if end < m.end():
        ln, col = _line_col(text, len(text))
        raise AslSyntaxError(path, ln, col, "missing '}'")
    body = clean[m.end():end]
    base = m.end()
    base_dir = os.path.dirname(os.path.abspath(path)) if path != "<mas2j>" else os.getcwd()
    proj = MasProject(name, [], path)
    src_paths = [base_dir]
    sp = re.search(r"\baslSourcePath\s*:\s*([^;]*);", body)
    if sp:
        src_paths = []
        for s in re.findall(r'"([^"]*)"', sp.group(1)):
            src_paths.append(s if os.path.isabs(s) else os.path.join(base_dir, s))
        src_paths.append(base_dir)
    inf = re.search(r"\binfrastructure\s*:\s*([^\n;]*)", body)
    if inf:
        proj.infrastructure = inf.group(1).strip()
        proj.notes.append(f"infrastructure '{proj.infrastructure}' ignored: agents run locally")
    env = re.search(r"\benvironment\s*:\s*([^\n;]*)", body)
    if env:
        proj.environment = env.group(1).strip()
        proj.notes.append(f"environment '{proj.environment}' ignored: no environment in local runs")
    ag = re.search(r"\bagents\s*:", body)
    if not ag:
        return proj
    # the agents section runs until the next known section keyword or the end
    rest_start = ag.end()
    nxt = re.search(r"\b(aslSourcePath|environment|infrastructure|executionControl|classpath|directives)\s*:",
                    body[rest_start:])
    section = body[rest_start: rest_start + nxt.start() if nxt else len(body)]
    offset = base + rest_start
    for decl in re.finditer(r"[^;]+", section):
        raw = decl.group(0)
        txt = raw.strip()
        if not txt:
            continue
        pos = offset + decl.start() + (len(raw) - len(raw.lstrip()))
        dm = re.match(r"([a-z][\w]*)\s*(.*)$", txt, re.S)
        if not dm:
            ln, col = _line_col(text, pos)
            raise AslSyntaxError(path, ln, col, f"invalid agent declaration {txt.split()[0]!r}")
        agname, tail = dm.group(1), dm.group(2)
        file_m = re.match(r"([\w./-]+\.asl)\b", tail)
        asl_file = file_m.group(1) if file_m else agname + ".asl"
        arch_m = re.search(r"\bagentArchClass\s+([\w.$]+)", tail)
        count_m = re.search(r"#\s*(\d+)", tail)
        n = int(count_m.group(1)) if count_m else 1
        asl_path = None
        for d in src_paths:
            cand = os.path.join(d, asl_file)
            if os.path.isfile(cand):
                asl_path = cand
                break
        if asl_path is None:
            asl_path = os.path.join(src_paths[0], asl_file)
        arch = arch_m.group(1) if arch_m else None
        if n == 1:
            proj.agents.append(AgentSpec(agname, asl_path, arch))
        else:
            for k in range(1, n + 1):
                proj.agents.append(AgentSpec(f"{agname}{k}", asl_path, arch))
    return proj


def load_mas2j(path: str) -> MasProject:
    """Read and parse a ``.mas2j`` file."""
    with open(path, encoding="utf-8") as f:
        return parse_mas2j(f.read(), path)
