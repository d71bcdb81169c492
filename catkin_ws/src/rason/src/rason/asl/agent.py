"""The agent proper (Jason's ``Agent``): belief base, plan library, options, loading, percepts,
and the public thread-safe API; its circumstance, goal operations, communication and runner are
collaborators it owns (:mod:`.circumstance`, :mod:`.goal_ops`, :mod:`.communication`, :mod:`.runner`)."""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Callable, Iterator
from typing import Any, NamedTuple

from . import reasoning
from .arch import AgentArch, JavaRandom, Message
from .beliefs import BeliefBase
from .circumstance import Circumstance
from .communication import Communication, strip_sources
from .goal_ops import GoalOps
from .ia import is_registered
from .intentions import (
    ActionResult,
    Event,
    IntendedMeans,
    Intention,
    PendingAction,
    Suspension,
)
from .kqml import kqml_plans
from .logic import query_bb, solve
from .parser import AgentSource, AslSyntaxError, parse_source, parse_term, path_include_resolver
from .plans import ACHIEVE, ADD, BELIEF, DEL, K_INTERNAL, PlanLibrary, Trigger, body_deeds
from .runner import Runner
from .selection import Selection
from .terms import (
    SOURCE_PERCEPT,
    Literal,
    Rule,
    is_ground,
    merge_annots,
)
from .unify import unify


class AgentOptions(NamedTuple):
    """Per-agent settings (Jason's agent options in ``.mas2j``).

    ``tro``: tail-recursion optimisation (Jason's ``tro``, on by default): a goal whose plan
    ends by posting the same goal again replaces its intended means instead of growing the
    intention, so ``+!loop <- ...; !loop.`` runs in constant memory.
    ``max_intention_depth``: an intention deeper than this (intended means on its stack)
    fails with ``error(intention_too_deep)`` instead of eating memory.
    """

    tro: bool = True
    max_intention_depth: int = 10_000

    @classmethod
    def from_options(cls, options: dict, default: AgentOptions | None = None) -> AgentOptions:
        """From ``.mas2j``-style options (``tro=false``, ``max_intention_depth=500``); the
        ones not given are those of ``default``."""
        base = default if default is not None else cls()
        tro = options.get("tro", base.tro)
        depth = options.get("max_intention_depth", base.max_intention_depth)
        return cls(tro=str(tro).strip().strip('"').lower() not in ("false", "off", "no", "0"),
                   max_intention_depth=int(float(str(depth).strip().strip('"'))))



class Agent:
    """A Jason agent: belief base, plan library, circumstance and reasoning cycle.

    ``receive``, ``action_feedback`` and ``wake`` may be called from any thread; everything else
    runs in the thread that calls ``step``/``run``. An inspector reads the mind through
    :mod:`.inspection` (``mind_state``, ``mind_text``, ``MindReader``).
    """

    def __init__(self, name: str, source: str, arch: AgentArch, filename: str = "<string>",
                 seed: int | None = None, src_name: str | None = None,
                 options: AgentOptions | None = None, source_path: list[str] | None = None,
                 selection: Selection | None = None,
                 belief_update: Callable[[Agent, list], bool] | None = None,
                 accept_message: Callable[[Agent, Message], bool] | None = None,
                 belief_base: BeliefBase | None = None) -> None:
        self.name = name
        #: the event, option and intention selection functions (see :mod:`.selection`)
        self.selection = selection if selection is not None else Selection()
        #: Jason's ``buf``: ``fn(agent, percepts) -> changed`` instead of :meth:`update_percepts`
        #: (which it may call with the percepts it keeps)
        self.belief_update = belief_update
        #: Jason's ``socAcc``: ``fn(agent, message) -> bool``; a message it refuses is dropped
        #: (answers to this agent's asks are always taken, as in Jason)
        self.accept_message = accept_message
        self.options = options if options is not None else AgentOptions()
        #: folders where included files (and agents created by this one) are looked for
        self.source_path = list(source_path or [])
        self.arch = arch
        #: the architecture has percepts to give (it overrides ``perceive``, in its class or on
        #: the instance): each cycle asks
        self.perceives = (type(arch).perceive is not AgentArch.perceive
                           or "perceive" in getattr(arch, "__dict__", {}))
        self.filename = filename
        if src_name is None:
            src_name = os.path.basename(filename) if filename != "<string>" else filename
        parsed = parse_source(source, filename, src="file:" + src_name,
                              include=path_include_resolver(self.source_path))
        #: the belief base (``belief_base``: one made for this agent, e.g. filled from a file)
        self.bb = belief_base if belief_base is not None else BeliefBase()
        #: ``.namespace_set_prop``'s properties: namespace -> key -> (key term, value term)
        self.namespace_props: dict[str, dict[str, tuple]] = {}
        self.pl = PlanLibrary()
        #: the events, intentions, pending actions, waits and timers (Jason's ``C``)
        self.circ = Circumstance(self)
        #: the goal operations (drop, succeed, fail, suspend, resume goals; deadlines)
        self.goals = GoalOps(self)
        #: the messages: in, out, and the asks waiting for answers
        self.comm = Communication(self)
        self.random = JavaRandom(seed)
        #: the threads and turns that run the reasoning cycle
        self.runner = Runner(self)
        self._percepts: set = set()
        #: set by :meth:`request_stop` (``.stopMAS``, a killed agent): its runner stops
        self.stop_requested = False
        self.load(parsed)
        arch.attach(self)

    # ================================================================ loading
    def load(self, parsed: AgentSource) -> None:
        """Take the program: plans (then Jason's KQML plans), initial beliefs and goals."""
        self._warn_unknown_actions(parsed)
        for p in parsed.plans + kqml_plans():
            self.pl.add(p)
        self._add_initial_state(parsed)

    def include(self, parsed: AgentSource) -> None:
        """Add an included program (``.include``): its plans after this agent's, its beliefs
        and goals as initial ones (Jason's ``importComponents`` and what follows it)."""
        self._warn_unknown_actions(parsed)
        for p in parsed.plans:
            self.pl.add(p)
        self._add_initial_state(parsed)

    def _warn_unknown_actions(self, parsed: AgentSource) -> None:
        for p in parsed.plans:
            for d in body_deeds(p.body):
                if d.kind == K_INTERNAL and not is_registered(d.term.functor):
                    # as Jason's parser: a warning at load; running it fails with action_failed
                    self.log(f"{self.filename}:{d.line}: warning: unknown internal action "
                             f"{d.term.functor}/{len(d.term.args)}")

    def _add_initial_state(self, parsed: AgentSource) -> None:
        for b in reversed(parsed.beliefs):
            if isinstance(b, Rule):
                self.bb.add_rule(b, front=True)
            else:
                lit = b.with_self_source()
                if not is_ground(lit):
                    self.bb.add(lit, front=True)
                    continue
                self.add_belief(lit, front=True)
        for g in parsed.goals:
            lit = g.with_self_source()
            self.circ.events.append(Event(Trigger(ADD, ACHIEVE, lit)))
            if self.pl.goal_state_plans:
                self.circ.goal_state(self.circ.events[-1].trigger, "pending")

    def add_initial(self, beliefs: str | None = None, goals: str | None = None) -> None:
        """The ``beliefs="..."`` and ``goals="..."`` options of a ``.mas2j`` agent: comma
        separated literals added as initial beliefs / goals."""
        for text, is_goal in ((beliefs, False), (goals, True)):
            if not text:
                continue
            items = parse_term("[" + text + "]")
            for lit in getattr(items, "items", ()):
                if not isinstance(lit, Literal):
                    continue
                lit = lit.with_self_source()
                if is_goal:
                    self.circ.events.append(Event(Trigger(ADD, ACHIEVE, lit)))
                else:
                    self.add_belief(lit, front=False)

    # ================================================================ public API
    def receive(self, message: Message, run_here: bool = False) -> None:
        """Thread-safe: queue an incoming message and wake the agent; with ``run_here`` a
        caller that finds the agent's runner asleep reasons on it itself
        (:meth:`.Runner.take_turns`)."""
        self.runner.receive(message, run_here)

    def action_feedback(self, action_id: int, ok: bool, reason: str | None = None, message: str = "",
                        annots: list | None = None, run_here: bool = False) -> None:
        """Thread-safe: the environment finished action ``action_id`` (ok or failed with reason;
        ``annots``: more annotations for the failure event, like Jason's failure reason term;
        ``run_here``: as for :meth:`receive`)."""
        self.runner.action_feedback(ActionResult(action_id, ok, reason, message, annots), run_here)

    def wake(self) -> None:
        """Thread-safe: something changed (e.g. new percepts); run a cycle soon."""
        self.runner.wake()

    def step(self) -> bool:
        """One reasoning cycle; True if it did anything."""
        return self.runner.step()

    def run(self, stop: threading.Event) -> None:
        """Reason until ``stop`` is set; block (no polling) while idle."""
        self.runner.run(stop)

    def is_idle(self) -> bool:
        """No events, no runnable intention, nothing in the inbox."""
        return self.runner.is_idle()

    def post_external(self, ev: Event) -> None:
        """An external event from the host (Jason's ``addExternalEv``); a sleeping agent wakes
        after it (``+jag_awaking`` comes after the event)."""
        self.circ.add_event(ev)
        if self.runner.sleeping:
            self.runner.wake_up()

    def solve(self, f: Any, s: dict, intention: Intention | None = None) -> Iterator[dict]:
        """Every substitution extending ``s`` under which ``f`` follows from this agent's state
        (Jason's logical consequence)."""
        return solve(self, f, s, intention)

    def query_beliefs(self, lit: Literal, s: dict) -> Iterator[dict]:
        """Every substitution extending ``s`` under which ``lit`` matches a belief or a rule."""
        return query_bb(self, lit, s)

    def count_solutions(self, query: Any) -> int:
        """``.count(Q)``: how many solutions Q has in the current mental state."""
        return sum(1 for _ in solve(self, query, {}))

    def clock_millis(self) -> float:
        """``system.time`` and ``.time(T)``: whole milliseconds of the agent's clock."""
        return float(int(self.arch.clock.now() * 1000))

    def request_stop(self) -> None:
        self.stop_requested = True

    # ================================================================ console
    def console(self, text: str) -> None:
        self.arch.console(self.name, text)

    def warn(self, text: str) -> None:
        self.arch.console(self.name, text)

    def log(self, text: str) -> None:
        print(f"[{self.name}] {text}", file=sys.stderr, flush=True)

    def warn_drop(self, i: Intention, text: str, trig: Any, relevant_msg: str | None = None) -> None:
        """Jason's warning for an intention dropped because its failure was not handled."""
        if relevant_msg:
            self.warn(text)
            self.warn("\n" + i.dump())
            self.warn(relevant_msg)
        else:
            self.warn(text + "\n" + i.dump())

    # ================================================================ sense
    def sense(self) -> bool:
        """Perceive (belief update from the percepts), take mail and feedback, fire timers."""
        percepts = self.arch.perceive()
        if percepts is None:
            did = False
        elif self.belief_update is None:
            did = self.update_percepts(percepts)
        else:
            did = bool(self.belief_update(self, percepts))
        runner = self.runner
        if runner.inbox or runner.mail:
            did = runner.take_input() or did
        if self.circ.timers:
            did = self.circ.check_timers() or did
        return did

    def update_percepts(self, ps: list) -> bool:
        """Belief update from percepts: add new ones, remove vanished ones (source(percept))."""
        new = set()
        order = []
        for p in ps:
            if isinstance(p, Literal):
                key = strip_sources(p)
                if key not in new:
                    new.add(key)
                    order.append(key)
        old = self._percepts
        if new == old:
            return False
        for p in old - new:
            self.remove_belief(p.add_annots([SOURCE_PERCEPT]))
        for p in order:
            if p not in old:
                self.add_belief(p.add_annots([SOURCE_PERCEPT]), front=True)
        self._percepts = new
        return True

    # ================================================================ intentions
    # ================================================================ beliefs
    def add_belief(self, lit: Literal, front: bool = True, focus: Intention | None = None) -> bool:
        """Add a belief (with its source annotations) and post the ``+b`` event if it is new.

        With ``focus`` (a plan body's ``+b``), the event is internal to that intention and is
        always queued; returns True when such an event was posted (the intention must wait).
        """
        added = self.bb.add(lit, front=front)
        return added is not None and self._belief_changed(ADD, added, focus)

    def remove_belief(self, lit: Literal, focus: Intention | None = None) -> bool:
        """Remove a belief; with ``focus`` the ``-b`` event is internal (see :meth:`add_belief`)."""
        removed = self.bb.remove(lit)
        return removed is not None and self._belief_changed(DEL, removed, focus)

    def replace_belief(self, lit: Literal, focus: Intention) -> tuple[bool, Literal | None]:
        """``-+b`` in ``focus``'s plan body: remove the first belief ``b(...)`` holding all of
        ``lit``'s annotations (its ``-b`` event is external), then add ``lit`` (its ``+b``
        event belongs to ``focus``, as for :meth:`add_belief`). Returns whether that ``+b``
        event was posted (the intention must wait for it), and the belief removed."""
        c = self.circ
        bb = self.bb
        if c.event_waits:   # a .wait condition is checked after the removal and after the addition
            removed = bb.remove_first_holding(lit)
            if removed is not None:
                self._belief_changed(DEL, removed, None)
            added = bb.add(lit, front=True)
            return added is not None and self._belief_changed(ADD, added, focus), removed
        removed, added = bb.replace_first_holding(lit)
        if removed is not None and ((DEL, BELIEF, removed.functor, len(removed.args), removed.neg)
                                    in self.pl.by_key or self.pl.var_plans):
            self._belief_changed(DEL, removed, None)   # (not called when no plan would see it)
        if added is None or self._own_event_unseen(ADD, added, focus):
            return False, removed
        c.events.append(Event(Trigger(ADD, BELIEF, added), focus))   # (_belief_changed inlined)
        return True, removed

    def _own_event_unseen(self, op: str, lit: Literal, focus: Intention) -> bool:
        """True when the ``+b``/``-b`` event of a belief change in ``focus``'s plan body need
        not be posted, because posting it changes nothing the program can see: no plan is
        relevant for it, and the next cycle's deliberation would select it first (no other
        event is queued, nothing will be sensed before: no percepts, mail, feedback or timers)
        only to put ``focus`` back at the end of the running queue (Jason's Rel2 rule for an
        internal belief event), and the deed that cycle runs is plain (:attr:`Deed.plain`): it
        cannot see that selected event (``.intend`` and the like list its intention). The
        intention goes to the end of the queue at once instead: the same order, less work."""
        c = self.circ
        pl = self.pl
        if (c.events or c.event_waits or self.perceives or self.runner.inbox or self.runner.mail
                or c.timers or c.action_results or c.atomic_used or pl.var_plans
                or pl.goal_condition_plans or pl.goal_state_plans
                or (op, BELIEF, lit.functor, len(lit.args), lit.neg) in pl.by_key):
            return False
        ims = (c.running[0] if c.running else focus).ims
        if not ims:
            return False
        stack = ims[-1].stack
        return bool(stack) and stack[-1].plain

    def _belief_changed(self, op: str, lit: Literal, focus: Intention | None) -> bool:
        """Post the ``+b``/``-b`` event of a belief change (see :meth:`add_belief`)."""
        c = self.circ
        if focus is not None:
            if self._own_event_unseen(op, lit, focus):
                return False
            ev = Event(Trigger(op, BELIEF, lit), focus)
            if not c.event_waits:   # the common case: nobody waits for events
                c.events.append(ev)
                return True
            c.check_event_waits(ev)
            c.events.append(ev)
            if c.event_waits:
                c.check_cond_waits()
            return True
        if not c.event_waits and not self.pl.has_key((op, BELIEF, lit.functor, len(lit.args), lit.neg)):
            return True  # fast path: nobody would see the event
        c.add_event(Event(Trigger(op, BELIEF, lit)))
        if c.event_waits:
            c.check_cond_waits()
        return True

    def abolish(self, pattern: Any, s: dict | None = None) -> None:
        """``.abolish(P)`` (Jason's ``Agent.abolish``): every belief P unifies with (P's
        annotations a subset of the belief's, e.g. ``b(_)[source(ag1)]``) goes, all of it;
        a variable P (``_[source(a)]``) looks at every belief."""
        cands = list(self.bb.candidates(pattern.key)) if type(pattern) is Literal else list(self.bb)
        for b in cands:
            if isinstance(b, Literal) and unify(pattern, b, dict(s or {})):
                removed = self.bb.remove(b)
                if removed is not None:
                    self.circ.add_event(Event(Trigger(DEL, BELIEF, removed)))

    # ================================================================ actions
    def start_action(self, i: Intention, im: IntendedMeans, deed: Any, action: Literal) -> int:
        aid = next(self.circ.action_ids)
        self.circ.pending_actions[aid] = PendingAction(i, im, action, deed)
        self.circ.suspend(i, Suspension.ACTION)
        try:
            self.arch.act(self, action, aid)
        except Exception as e:
            self.action_feedback(aid, False, "action_failed", f"{type(e).__name__}: {e}")
        return aid

    def process_feedback(self, result: ActionResult) -> None:
        entry = self.circ.pending_actions.pop(result.action_id, None)
        if entry is None:
            return
        i, im = entry.intention, entry.means
        if i.dropped or i.id not in self.circ.suspended:
            return
        if not self.circ.resume(i) or result.ok:
            return
        self.circ.running.remove(i)
        kind = result.reason or "action_failed"
        annots = reasoning.error_annots(self, im, entry.deed, kind, result.message or "",
                                        code=entry.action, extra=result.annots)
        reasoning.fail_intention(self, i, annots=annots)




def load_agent_source(path: str | os.PathLike) -> str:
    """Read an ``.asl`` file (UTF-8); text that is not UTF-8 raises :class:`AslSyntaxError`
    at the first bad byte (``file:line:col: ...``)."""
    with open(path, "rb") as f:
        data = f.read()
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line = data.count(b"\n", 0, e.start) + 1
        col = e.start - (data.rfind(b"\n", 0, e.start) + 1) + 1
        raise AslSyntaxError(str(path), line, col,
                             f"not UTF-8 text (byte 0x{data[e.start]:02x}); save the file as UTF-8") from None


__all__ = ["Agent", "AgentOptions", "load_agent_source", "merge_annots"]
