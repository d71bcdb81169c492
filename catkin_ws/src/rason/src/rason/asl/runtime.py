"""Local (centralised) MAS runner: all agents in one process, messages routed in memory."""

from __future__ import annotations

import copy
import gc
import itertools
import os
import sys
import threading
from collections import deque
from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING

from .agent import Agent, AgentOptions, load_agent_source
from .arch import AgentArch, Clock, Message, UnknownReceiver, WallClock, verbosity
from .beliefs import BeliefBase
from .df import DF_NAME, ProviderNotice, ServiceDirectory
from .intentions import Event, Intention
from .plans import ADD, BELIEF, PlanLibrary, Trigger
from .terms import Literal, Rule

if TYPE_CHECKING:
    from .environment import Environment
    from .mas2j import MasProject


class LocalArch(AgentArch):
    """Architecture of an agent run by :class:`LocalMas` (no environment)."""

    def __init__(self, mas: LocalMas, clock: Clock) -> None:
        super().__init__(clock)
        self.mas = mas

    def send(self, agent: Agent, message: Message) -> None:
        target = self.mas.agents.get(message.receiver)
        if target is None:
            raise UnknownReceiver(f"unknown receiver {message.receiver}")
        target.receive(message)
        self.mas.notify()

    def agent_names(self) -> list[str]:
        return list(self.mas.agents)

    def create_agent(self, creator: Agent, name: str | None, source: str | None) -> str:
        """``.create_agent``: a new agent of this MAS (its file found as the project's are)."""
        return self.mas.create_agent(name, source, creator)

    def clone_agent(self, creator: Agent, name: str) -> str:
        """``.clone``: a new agent with a copy of ``creator``'s beliefs, plans, pending events
        and the intentions waiting their turn (not the one running ``.clone``)."""
        final = self.mas.create_agent(name, None, creator)
        clone = self.mas.agents[final]
        clone.filename = creator.filename
        clone.bb = BeliefBase()
        for b in creator.bb:
            if isinstance(b, Rule):
                clone.bb.add_rule(b)
            else:
                clone.bb.add(b)
        clone.pl = PlanLibrary()
        for p in creator.pl.plans:
            clone.pl.add(p)
        # Jason's Circumstance.clone: the queued events and the intentions waiting their turn
        # (not the one running .clone, nor the suspended ones)
        copies: dict[int, Intention] = {}
        for i in creator.circ.running:
            if i is not creator.circ.current and i.fork is None and i.reply is None:
                try:
                    copies[i.id] = copy.deepcopy(i)
                except TypeError:   # compiled (mypyc) intentions cannot be copied so: left out
                    continue
        clone.circ.running = deque(copies.values())
        clone.circ.events = deque(
            Event(ev.trigger, None if ev.intention is None else copies.get(ev.intention.id))
            for ev in creator.circ.events if ev.intention is None or ev.intention.id in copies)
        self.mas.notify()
        return final

    def kill_agent(self, name: str) -> bool:
        return self.mas.kill_agent(name)

    def stop_mas(self, ms: float) -> None:
        """``.stopMAS(T)``: ``+jag_shutting_down(T)`` for every agent, the stop T ms later."""
        self.mas.stop_in(ms)

    def service_directory(self) -> ServiceDirectory:
        return self.mas.df

    def console(self, agent_name: str, text: str) -> None:
        self.mas.console(agent_name, text)

    def output(self, text: str) -> None:
        self.mas.output(text)


ArchFactory = Callable[["LocalMas", str], AgentArch]


class LocalMas:
    """Runs agents round-robin (one reasoning cycle each) in the calling thread.

    ``arch_factory(mas, name)`` may supply a custom architecture per agent (tests, simulators);
    it should route ``send`` through ``mas.agents`` like :class:`LocalArch`.
    """

    def __init__(self, clock: Clock | None = None, arch_factory: ArchFactory | None = None,
                 out=None) -> None:
        self.clock = clock or WallClock()
        self.agents: dict[str, Agent] = {}
        #: when ``.stopMAS(T)`` stops the run (clock seconds), None: not asked
        self.stop_at: float | None = None
        #: the agents in the order they run, a new tuple whenever one is added or killed
        #: (a round iterates the one it started with)
        self._roster: tuple[Agent, ...] = ()
        self.arch_factory = arch_factory
        self.out = out
        self._wake = threading.Event()
        self.notes: list[str] = []
        self.options = AgentOptions()   # for agents added without options of their own
        #: the project's ``aslSourcePath`` (included files, agents made by ``.create_agent``)
        self.source_path: list[str] = []
        #: the directory facilitator of this MAS (``.df_register`` ...)
        self.df = ServiceDirectory(self._tell_provider)
        #: the project's environment (``environment:`` in ``.mas2j``), or None
        self.environment: Environment | None = None
        #: called once when the run ends (:meth:`stop`)
        self.at_stop: list[Callable[[], None]] = []
        #: the intentions' ids, one count for all the agents of this MAS (Jason numbers the
        #: intentions of all the agents of its run from one counter: ``.intention``'s ids,
        #: ``wait(Id)`` reasons and the order ``.resume`` takes suspended intentions in)
        self.intention_ids = itertools.count(1)

    # ------------------------------------------------------------ setup
    def console(self, agent_name: str, text: str) -> None:
        out = self.out or sys.stdout
        out.write(f"[{agent_name}] {text}\n")
        out.flush()

    def output(self, text: str) -> None:
        """Bare text, as an agent with ``verbose=0`` prints."""
        out = self.out or sys.stdout
        out.write(text)
        out.flush()

    def notify(self) -> None:
        self._wake.set()

    def _tell_provider(self, notice: ProviderNotice) -> None:
        """The directory facilitator tells a subscriber of a provider."""
        target = self.agents.get(notice.subscriber)
        if target is not None:
            target.receive(Message(DF_NAME, notice.subscriber, "tell", notice.content()))
            self.notify()

    def make_arch(self, name: str) -> AgentArch:
        if self.arch_factory is not None:
            return self.arch_factory(self, name)
        if self.environment is not None:
            from .environment import EnvArch  # imports this module: only with an environment

            return EnvArch(self, self.clock, self.environment, name)
        return LocalArch(self, self.clock)

    def set_environment(self, env: Environment) -> None:
        """Agents added from now on perceive and act on ``env``; it wakes them, prints with
        them and knows their names through this MAS."""
        self.environment = env
        env._inform = self._environment_changed
        env._console = self.console
        env._names = lambda: list(self.agents)

    def _environment_changed(self, names: tuple[str, ...]) -> None:
        for name in names or tuple(self.agents):
            ag = self.agents.get(name)
            if ag is not None:
                ag.wake()
        self.notify()

    def stop(self) -> None:
        """The MAS ends: what the agents' classes do then (TextPersistentBB writes its file),
        then the environment's ``stop()``; once."""
        at_stop, self.at_stop = self.at_stop, []
        for fn in at_stop:
            fn()
        env, self.environment = self.environment, None
        if env is not None:
            env.stop()

    def add_agent(self, name: str, source: str, filename: str = "<string>", seed: int | None = None,
                  src_name: str | None = None, options: AgentOptions | None = None,
                  belief_base: BeliefBase | None = None) -> Agent:
        ag = Agent(name, source, self.make_arch(name), filename, seed=seed, src_name=src_name,
                   options=options if options is not None else self.options,
                   source_path=self.source_path, belief_base=belief_base)
        ag.circ.intention_ids = self.intention_ids
        ag.runner.on_wake = self.notify
        self.agents[name] = ag
        self._roster = tuple(self.agents.values())
        return ag

    def load_project(self, proj: MasProject, seed: int | None = None) -> None:
        """Add the agents of a ``.mas2j`` project with their options and their classes
        (:mod:`.hooks`; raises :class:`.HookLoadError` for a class that does not import)."""
        from .hooks import load_hooks  # imports the environment module, which imports this one

        base = os.path.dirname(os.path.abspath(proj.path))
        self.source_path = [*proj.source_path, base]
        if proj.environment and self.arch_factory is None:
            from .environment import load_environment

            self.set_environment(load_environment(proj.environment, base))
        for k, spec in enumerate(proj.agents):
            hooks = load_hooks(spec, proj.path)
            src = load_agent_source(spec.asl_path)
            rel = os.path.relpath(spec.asl_path, base)
            opts = AgentOptions.from_options(spec.options, self.options)
            ag = self.add_agent(spec.name, src, spec.asl_path, None if seed is None else seed + k,
                                src_name=rel, options=opts, belief_base=hooks.make_belief_base())
            ag.add_initial(spec.options.get("beliefs"), spec.options.get("goals"))
            ag.arch.verbose = verbosity(spec.options)
            hooks.customise(ag)
            if hooks.stoppers:
                self.at_stop.append(partial(hooks.stop, ag))
            self.notes.extend(hooks.notes)
        self.notes.extend(proj.notes)

    def find_source(self, source: str, near: str | None = None) -> str:
        """The path of an agent's ``.asl`` file: as given, then in the creator's folder and
        the project's source path."""
        folders = [os.path.dirname(os.path.abspath(near))] if near and not near.startswith("<") else []
        folders += [*self.source_path, os.getcwd()]
        if os.path.isabs(source) and os.path.isfile(source):
            return source
        for d in folders:
            for cand in (os.path.join(d, source), os.path.join(d, os.path.basename(source))):
                if os.path.isfile(cand):
                    return cand
        if os.path.isfile(source):
            return os.path.abspath(source)
        raise FileNotFoundError(source)

    def create_agent(self, name: str | None, source: str | None, creator: Agent | None = None) -> str:
        """Add an agent while the MAS runs (``.create_agent``); a taken name gets a suffix."""
        base = name or "agent"
        final = base
        k = 1
        while final in self.agents:
            final = f"{base}_{k}"
            k += 1
        if source is None:
            path, text = "<string>", ""
        else:
            path = self.find_source(source, creator.filename if creator else None)
            text = load_agent_source(path)
        self.add_agent(final, text, path, src_name=source)
        self.notify()
        return final

    def kill_agent(self, name: str) -> bool:
        ag = self.agents.pop(name, None)
        if ag is None:
            return False
        self._roster = tuple(self.agents.values())
        self.df.forget_agent(name)
        ag.request_stop()
        self.notify()
        return True

    def stop_in(self, ms: float) -> None:
        """Jason's ``stopAgs(deadline)``: each agent gets the event ``+jag_shutting_down(ms)``
        (kept only where a plan wants it), and the run stops ``ms`` milliseconds from now."""
        trig = Trigger(ADD, BELIEF, Literal("jag_shutting_down", (ms,)))
        for ag in self.agents.values():
            ag.post_external(Event(trig))
        when = self.clock.now() + ms / 1000.0
        self.stop_at = when if self.stop_at is None else min(self.stop_at, when)
        self.notify()

    # ------------------------------------------------------------ run
    def step_all(self) -> bool:
        did = False
        for ag in self._roster:
            if ag.step():
                did = True
        return did

    def finished(self) -> bool:
        return all(ag.is_idle() for ag in self.agents.values())

    def run(self, timeout: float | None = None, stop: threading.Event | None = None,
            max_cycles: int | None = None, idle_hook: Callable[[], bool] | None = None) -> bool:
        """Run until every agent is idle with nothing that can still happen (True), or until the
        timeout (clock seconds) / ``max_cycles`` rounds (False).

        ``idle_hook`` is called when every agent is idle; returning True means "something
        happened" (e.g. a simulated environment finished an action) and the run goes on.
        Otherwise, with actions pending, the runner blocks until an agent is woken."""
        clock = self.clock
        t_end = None if timeout is None else clock.now() + timeout
        rounds = 0
        busy = False
        while True:
            rounds += 1
            if max_cycles is not None and rounds > max_cycles:
                return False
            if stop is not None and stop.is_set():
                return False
            roster = self._roster
            for ag in roster:
                if ag.stop_requested:
                    return True
            if self.stop_at is not None and clock.now() >= self.stop_at:
                return True
            if not busy:
                # a wake-up during a busy round stays set: the wait below returns at once then
                self._wake.clear()
            busy = False
            for ag in roster:    # step_all, inlined: this loop runs once per reasoning cycle
                if ag.step():
                    busy = True
            if busy:
                if t_end is not None and clock.now() >= t_end:
                    return False
                continue
            if not self.finished() and any(ag.runner.has_input() for ag in self.agents.values()):
                continue
            if idle_hook is not None and idle_hook():
                continue
            deadlines = [d for d in (ag.circ.next_deadline() for ag in self.agents.values()) if d is not None]
            if self.stop_at is not None:
                deadlines.append(self.stop_at)
            pending = any(ag.circ.pending_actions for ag in self.agents.values())
            if not deadlines and not pending:
                return True
            deadline = min(deadlines) if deadlines else None
            if t_end is not None:
                if clock.now() >= t_end:
                    return False
                deadline = t_end if deadline is None else min(deadline, t_end)
            clock.wait(self._wake, deadline)


def run_file(path: str, timeout: float | None = None, seed: int | None = None,
             clock: Clock | None = None, options: AgentOptions | None = None,
             source_path: list[str] | None = None) -> tuple[LocalMas, bool]:
    """Load a ``.mas2j`` or ``.asl`` file and run it locally (``options``: the agents' defaults,
    a ``.mas2j`` agent's own options win; ``source_path``: more folders for the project's
    agents, searched first); the project's environment and agents stop when the run ends."""
    mas = LocalMas(clock)
    if options is not None:
        mas.options = options
    # loading makes many objects that live as long as the run (parser tables, plans, terms):
    # the garbage collector would only walk them meanwhile (about 3% of an empty agent's start)
    collecting = gc.isenabled()
    gc.disable()
    try:
        if path.endswith(".mas2j"):
            # imported here: the project reader needs lark, which a lone agent does without
            from .mas2j import load_mas2j

            mas.load_project(load_mas2j(path, source_path), seed)
        else:
            name = os.path.splitext(os.path.basename(path))[0]
            mas.add_agent(name, load_agent_source(path), path, seed)
    finally:
        if collecting:
            gc.enable()
    for n in mas.notes:
        print(f"note: {n}", file=sys.stderr)
    try:
        ok = mas.run(timeout)
    finally:
        mas.stop()
    return mas, ok
