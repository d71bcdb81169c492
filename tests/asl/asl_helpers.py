"""Helpers shared by the rason.asl tests (no ROS needed)."""

from __future__ import annotations

import importlib.util
import io
import os
import sys
import threading
from types import ModuleType
from typing import Any

from rason.asl import Agent, AgentArch, LocalMas, Message, VirtualClock

HERE = os.path.dirname(os.path.abspath(__file__))
CONFORMANCE = os.path.join(HERE, "conformance")
BENCHMARKS = os.path.join(HERE, os.pardir, os.pardir, "benchmarks")


def load_benchmark(name: str) -> ModuleType:
    """``benchmarks/NAME.py`` as a module, with ``benchmarks/`` on the path (a benchmark
    imports its neighbours, e.g. Jason's logging set-up from jason_demos)."""
    if BENCHMARKS not in sys.path:
        sys.path.insert(0, BENCHMARKS)
    spec = importlib.util.spec_from_file_location(name, os.path.join(BENCHMARKS, f"{name}.py"))
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[name] = mod   # (a dataclass of the module looks the module up there)
    spec.loader.exec_module(mod)
    return mod


def load_compare():
    """The suite's own compare.py (copied next to the cases)."""
    spec = importlib.util.spec_from_file_location("asl_compare", os.path.join(CONFORMANCE, "compare.py"))
    mod = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(mod)
    return mod


def run_source(source: str, name: str = "main", timeout: float = 10.0, **kw: Any) -> str:
    """Run one agent in a LocalMas with a virtual clock; return its console output."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent(name, source, f"{name}.asl", **kw)
    mas.run(timeout=timeout)
    return out.getvalue()


def run_agents(sources: dict[str, str], timeout: float = 10.0) -> str:
    """Run several agents (name: source) in one LocalMas with a virtual clock; their output."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    for name, src in sources.items():
        mas.add_agent(name, src, f"{name}.asl")
    mas.run(timeout=timeout)
    return out.getvalue()


def lines(text: str, agent: str = "main") -> list[str]:
    prefix = f"[{agent}] "
    return [ln[len(prefix):] for ln in text.splitlines() if ln.startswith(prefix)]


class RecordingArch(AgentArch):
    """A test architecture: records actions/console, percepts settable from the test."""

    def __init__(self) -> None:
        super().__init__(VirtualClock())
        self.actions: list[tuple[int, str]] = []
        self.out: list[str] = []
        self.percepts: list | None = None
        self.sent: list[Message] = []
        self.lock = threading.Lock()

    def perceive(self):
        with self.lock:
            p, self.percepts = self.percepts, None
        return p

    def act(self, agent: Agent, action, action_id: int) -> None:
        self.actions.append((action_id, str(action)))

    def send(self, agent: Agent, message: Message) -> None:
        self.sent.append(message)

    def console(self, agent_name: str, text: str) -> None:
        self.out.append(text)


def subprocess_env() -> dict:
    """Environment for ``python -m rason.asl`` subprocesses: the package must be importable."""
    import rason

    src = os.path.dirname(os.path.dirname(os.path.abspath(rason.__file__)))
    env = dict(os.environ)
    env["PYTHONPATH"] = src + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
    return env


def run_until_idle(ag: Agent, max_steps: int = 10000) -> int:
    n = 0
    while n < max_steps and ag.step():
        n += 1
    return n
