"""An agent's communication: KQML messages taken (Jason's ``applyProcMsg``), sent, and the
answers to its asks (Jason's ``jason.stdlib.send`` with ``askOne``/``askAll``/``askHow``)."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from . import reasoning
from .arch import Message
from .ia import IAError
from .intentions import AskWait, Event, IntendedMeans, Intention, Suspension, TimerKind
from .kqml import KQML_SRC, plans_answered_by
from .plans import ACHIEVE, ADD, BELIEF, Trigger
from .terms import (
    FALSE,
    SOURCE_SELF,
    ListTerm,
    Literal,
    is_ground,
    make_list,
    source,
    term_str,
    with_nested_source,
)
from .unify import rename_vars, resolve, unify

if TYPE_CHECKING:  # pragma: no cover
    from .agent import Agent

#: the event of a message handled by (default or user) plans
_KQML_RECEIVED = Trigger(ADD, ACHIEVE, Literal("kqml_received", (Literal("s"), Literal("p"),
                                                                  Literal("c"), Literal("m"))))


def strip_sources(t: Any) -> Any:
    """``t`` without its ``source(...)`` annotations."""
    if isinstance(t, Literal) and t.annots:
        return t.with_annots(tuple(a for a in t.annots
                                   if not (isinstance(a, Literal) and a.functor == "source")), t.tail)
    return t


class Communication:
    """The messages of the agent ``ag``: in, out, and the asks it waits answers for."""

    def __init__(self, ag: Agent) -> None:
        self.ag = ag

    def send_message(self, msg: Message) -> None:
        """Send ``msg`` through the architecture (to itself: straight to its mailbox)."""
        ag = self.ag
        if msg.receiver == ag.name:
            ag.receive(msg)
            return
        try:
            ag.arch.send(ag, msg)
        except Exception as e:
            raise IAError(f"cannot send to {msg.receiver}: {e}") from None

    def process_message(self, m: Message) -> None:
        """One message (Jason's ``TransitionSystem.applyProcMsg``): an answer resumes the
        intention that asked; a literal told/achieved/signalled is handled directly unless the
        program has its own ``kqml_received`` plans; anything else is a ``+!kqml_received``."""
        ag = self.ag
        c = ag.circ
        src = SOURCE_SELF if m.sender == ag.name else source(m.sender)
        content = m.content
        if m.in_reply_to is not None and m.in_reply_to in c.ask_waits:
            self._ask_answer(m)
            return
        if m.in_reply_to is not None and m.in_reply_to.startswith("samid"):
            return  # an answer after the ask's timeout is ignored
        if ag.accept_message is not None and not ag.accept_message(ag, m):
            return  # Jason's socAcc refused it
        perf = m.performative
        if (perf in ("tell", "achieve", "signal") and type(content) is Literal
                and not self._user_kqml_plans()):
            # TransitionSystem.applyProcMsg: the content's sources are nested in the sender's
            lit = with_nested_source(content, src.args[0])
            if perf == "tell":
                ag.add_belief(lit, front=True)
            elif perf == "achieve":
                c.add_event(Event(Trigger(ADD, ACHIEVE, lit)))
            else:
                c.add_event(Event(Trigger(ADD, BELIEF, lit)))
            return
        if perf == "tell" and type(content) is ListTerm and not self._user_kqml_plans():
            self._tell_all(content, src)
            return
        sender = Literal("self") if m.sender == ag.name else Literal(m.sender)
        received = Literal("kqml_received", (sender, Literal(perf), content, Literal(m.msg_id)))
        c.add_event(Event(Trigger(ADD, ACHIEVE, received)))

    def _tell_all(self, content: ListTerm, src: Literal) -> None:
        """A ``tell`` of a list, as the default plans do it (each ground literal is added with
        the sender's source, the rest is skipped) but in one pass: linear in the list's length."""
        items: Any = content
        while type(items) is ListTerm:
            for item in items.items:
                if type(item) is Literal and (item.known_ground or is_ground(item)):
                    self.ag.add_belief(item.add_annots([src]), front=True)
            items = items.tail

    def _user_kqml_plans(self) -> bool:
        """Jason's ``PlanLibrary.hasUserKqmlReceivedPlans``."""
        return any(p.src != KQML_SRC for p in self.ag.pl.relevant(_KQML_RECEIVED))

    def intention_finished(self, i: Intention, last: IntendedMeans) -> None:
        """``i`` ended; when it answered an ``achieve`` asked with a reply, the answer goes."""
        if i.reply is not None:
            q: Message = i.reply
            ag = self.ag
            ans = strip_sources(reasoning.means_answer(ag, last))
            self.send_message(Message(ag.name, q.sender, "tell", ans, in_reply_to=q.msg_id))

    # ---------------------------------------------------------------- asks
    def register_ask(self, msg_id: str, i: Intention | None, answer: Any, deadline: float | None,
                     perf: str = "askOne", n: int | None = None) -> None:
        """An intention waits for the answer to ask ``msg_id`` (``n``: number of receivers when
        they were given as a list, then the answer is the list of their answers)."""
        if i is None:
            return
        c = self.ag.circ
        c.suspend(i, Suspension.ASK)
        i.pi_key = msg_id
        c.ask_waits[msg_id] = AskWait(i, answer, perf, n)
        if deadline is not None:
            c.push_timer(deadline, TimerKind.ASK_TIMEOUT, i, msg_id)

    def ask_timed_out(self, i: Intention, msg_id: str | None) -> bool:
        """The ask ``msg_id`` of ``i`` timed out: the answer is ``timeout``, or the answers so
        far for a list of receivers (jason.stdlib.send). True when ``i`` was waiting for it."""
        c = self.ag.circ
        w = c.ask_waits.pop(msg_id, None) if msg_id is not None else None
        if w is None:
            return False
        c.resume(i)
        im = i.top()
        assert im is not None   # the .send that asked is on top
        s2 = dict(im.u)
        got = Literal("timeout") if w.receivers is None else make_list(w.answers)
        if unify(w.answer, got, s2, self.ag):
            im.u = s2
        return True

    def _ask_answer(self, m: Message) -> None:
        """The answer to a ``.send(R, askOne|askAll, C, A)`` that suspended an intention: an
        untell of an askOne is ``false``, a literal (each literal of an askAll list) gets the
        sender's source; with a list of receivers ``A`` is the list of all the answers."""
        mid = m.in_reply_to
        assert mid is not None      # only answers (in_reply_to set) come here
        c = self.ag.circ
        wait = c.ask_waits[mid]
        i, ans, perf, n, got = wait.intention, wait.answer, wait.performative, wait.receivers, wait.answers
        sender = Literal(m.sender)
        # the answer's variables are not the asker's (Jason's messages are copied as text)
        content = rename_vars(m.content, {})
        if m.performative == "untell" and perf == "askOne":
            content = FALSE
        elif isinstance(content, Literal) or (perf == "askAll" and isinstance(content, ListTerm)):
            # TransitionSystem: the answer's sources are nested in source(Sender)
            content = with_nested_source(content, sender)
        elif perf == "askHow" and isinstance(content, ListTerm):
            content = plans_answered_by(content, m.sender)   # labelled source(Sender)
        if n is not None:
            got.append(content)
            if len(got) < n:
                return
            content = make_list(got)
        del c.ask_waits[mid]
        self._resume_ask(i, ans, content)

    def _resume_ask(self, i: Intention, ans: Any, content: Any) -> None:
        """Unify the answer with the ``.send``'s fourth argument and resume the intention;
        when they do not unify the intention fails with ``ask_failed`` (resumeSyncAskIntention)."""
        ag = self.ag
        c = ag.circ
        im = i.top()
        if i.dropped or i.id not in c.suspended or im is None:
            return
        s2 = dict(im.u)
        if unify(ans, content, s2, ag):
            im.u = s2
            c.resume(i)
        elif c.resume(i):
            c.running.remove(i)
            msg = (f"reply of an ask message ('{term_str(content)}') does not unify with fourth "
                   f"argument of .send ('{term_str(resolve(ans, im.u, ag))}')")
            reasoning.fail_intention(ag, i, annots=reasoning.error_annots(
                ag, im, im.current, "ask_failed", msg))
