"""Reasoning-cycle semantics of rason.asl: failures, actions, percepts, messages, threads."""

from __future__ import annotations

import math
import threading
import time

from asl_helpers import RecordingArch, lines, run_source, run_until_idle
from polling import wait_until

from rason.asl import Agent, AgentArch, LocalMas, Message, VirtualClock, WallClock, parse_literal
from rason.asl.inspection import mind_text
from rason.asl.terms import term_str


def beliefs(ag: Agent) -> list[str]:
    return mind_text(ag)["beliefs"]


# ------------------------------------------------------------------ failure annotations
def test_failure_annotations_and_lines() -> None:
    out = run_source("""!m.
+!m <- !f.
+!f <- X = 1;
       X > 5.
-!f[error(E), error_msg(M), code(C), code_line(L), code_src(S)] <- .print(E, "|", C, "|", L, "|", S).
""")
    assert lines(out) == ['constraint_failed|(1 > 5)|4|file:main.asl']


def test_no_handler_drops_intention_agent_lives_on() -> None:
    out = run_source("!a. !b.\n+!a <- .fail.\n+!b <- .print(1); .print(2).")
    assert lines(out)[0].startswith("No failure event was generated for +!a[code(.fail)")
    assert lines(out)[1:] == ["1", "2"]


def test_errors_in_internal_actions_never_crash() -> None:
    # jason.stdlib.nth throws a plain JasonException (error kind internal_action)
    out = run_source('!a.\n+!a <- .nth(10, [1], X); .print(X).\n-!a[error(E)] <- .print("caught ", E).')
    assert lines(out) == ["caught internal_action"]
    # jason.stdlib.sort checks its first argument (createWrongArgument)
    out = run_source('!a.\n+!a <- .sort(3, X).\n-!a[error(E)] <- .print("caught ", E).')
    assert lines(out) == ["caught wrong_arguments"]
    # as2j.literal(): an unknown .ia is only a warning and runs as an (environment) action
    out = run_source('!a.\n+!a <- .no_such_ia(1).\n-!a[error(E)] <- .print("caught ", E).')
    assert lines(out) == ["caught action_failed"]


def test_unknown_internal_action_is_reported_when_the_agent_loads(capsys) -> None:
    out = run_source('!a.\n+!a <- .print(x);\n  if (true) { .no_such_ia(1) }.\n', timeout=2.0)
    assert lines(out)[0] == "x"
    assert "main.asl:3: warning: unknown internal action .no_such_ia/1" in capsys.readouterr().err


# ------------------------------------------------------------------ actions through the arch
ACT_SRC = """
!go. !other.
+!go <- move(1); .print("moved"); move(2); .print("never").
-!go[error(R), error_msg(M), code(C), code_line(L)] <- .print("failed ", R, " ", M, " ", C, " ", L).
+!other <- .print("o1"); .print("o2").
"""


def test_action_suspends_only_its_intention_and_resumes() -> None:
    arch = RecordingArch()
    ag = Agent("r", ACT_SRC, arch)
    run_until_idle(ag)
    assert arch.actions == [(1, "move(1)")]
    assert arch.out == ["o1", "o2"]  # the other intention ran while move(1) was pending
    assert ag.is_idle() and ag.circ.has_pending()
    assert mind_text(ag)["pending_actions"] == ["1: move(1)"]
    ag.action_feedback(1, True)
    run_until_idle(ag)
    assert arch.out[-1] == "moved" and arch.actions[-1] == (2, "move(2)")
    ag.action_feedback(2, False, "no_progress", "wheels stuck")
    run_until_idle(ag)
    assert arch.out[-1] == 'failed no_progress wheels stuck move(2) 3'
    assert not ag.circ.has_pending()


def test_action_failure_without_reason() -> None:
    arch = RecordingArch()
    ag = Agent("r", ACT_SRC, arch)
    run_until_idle(ag)
    ag.action_feedback(1, False)
    run_until_idle(ag)
    assert arch.out[-1].startswith("failed action_failed")


def test_default_arch_fails_actions_with_no_environment() -> None:
    # jason.infra.local.LocalAgArch.act: error(action_failed), its message and the noenv reason
    out = run_source(ACT_SRC, "r")
    assert "failed action_failed no environment configured!" in out


# ------------------------------------------------------------------ percepts
PERC_SRC = """
+pos(X)[source(percept)] <- .print("+pos ", X).
-pos(X)[source(percept)] <- .print("-pos ", X).
+pos(X)[source(self)] <- .print("self ", X).
"""


def test_percept_diffing() -> None:
    arch = RecordingArch()
    ag = Agent("p", PERC_SRC, arch)
    arch.percepts = [parse_literal("pos(1)"), parse_literal("pos(2)")]
    run_until_idle(ag)
    assert sorted(arch.out) == ["+pos 1", "+pos 2"]
    arch.out.clear()
    arch.percepts = None  # unchanged: nothing happens
    assert not ag.step()
    arch.percepts = [parse_literal("pos(2)"), parse_literal("pos(3)")]
    run_until_idle(ag)
    assert sorted(arch.out) == ["+pos 3", "-pos 1"]
    assert sorted(beliefs(ag)) == ["pos(2)[source(percept)]", "pos(3)[source(percept)]"]


def test_a_perceive_given_to_the_architecture_instance_is_asked() -> None:
    # perceive set on an instance, not overridden in a subclass (a cycle skips sensing only
    # when nothing can give percepts)
    arch = AgentArch(VirtualClock())
    given = [[parse_literal("pos(7)")]]
    arch.perceive = lambda: given.pop() if given else None      # type: ignore[method-assign]
    ag = Agent("p", PERC_SRC, arch)
    run_until_idle(ag)
    assert beliefs(ag) == ["pos(7)[source(percept)]"]


# ------------------------------------------------------------------ messages / inbox
def test_inbox_is_thread_safe() -> None:
    arch = RecordingArch()
    ag = Agent("m", "+n(X)[source(S)] <- .print(X).", arch)

    def sender(k: int) -> None:
        for j in range(50):
            ag.receive(Message(f"s{k}", "m", "tell", parse_literal(f"n({k * 100 + j})")))
    threads = [threading.Thread(target=sender, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    run_until_idle(ag, 100000)
    assert len(arch.out) == 200


def test_run_loop_wakes_on_receive_and_stops() -> None:
    arch = RecordingArch()
    arch.clock = WallClock()
    ag = Agent("m", "+!hi[source(S)] <- .print(hi, S).", arch)
    stop = threading.Event()
    th = threading.Thread(target=ag.run, args=(stop,), daemon=True)
    th.start()
    # asleep with no deadline: only a wake-up (the receive) can make it print
    wait_until(lambda: ag.runner.asleep_until == math.inf and not ag.runner.turn.locked(),
               "the runner asleep with no deadline", period=0.002)
    ag.receive(Message("bob", "m", "achieve", parse_literal("hi")))
    wait_until(lambda: arch.out, "the runner's line", period=0.002)
    assert arch.out == ["hibob"]
    stop.set()
    th.join(2)
    assert not th.is_alive()


def test_wait_uses_the_clock() -> None:
    clock = VirtualClock()
    arch = RecordingArch()
    arch.clock = clock
    ag = Agent("w", "!g.\n+!g <- .time(T0); .wait(4000); .time(T1); .print(T1 - T0).", arch)
    run_until_idle(ag)
    assert ag.circ.next_deadline() == 4.0 and arch.out == []
    clock.advance(4.0)
    run_until_idle(ag)
    assert arch.out == ["4000"]


def test_nano_time_reads_the_same_clock_in_nanoseconds() -> None:
    clock = VirtualClock(start=10.0)
    arch = RecordingArch()
    arch.clock = clock
    ag = Agent("w", "!g.\n+!g <- .nano_time(T0); .wait(1500); .nano_time(T1); .print(T0, \" \", T1 - T0).",
               arch)
    run_until_idle(ag)
    clock.advance(1.5)
    run_until_idle(ag)
    assert arch.out == ["10000000000 1500000000"]


def test_ask_one_and_send_to_unknown() -> None:
    out_mas = LocalMas(clock=VirtualClock())
    import io
    buf = io.StringIO()
    out_mas.out = buf
    out_mas.add_agent("a", """!s.
+!s <- .send(b, askOne, v(X), A); .print(A); .send(b, askOne, w(_), B); .print(B);
       .send(nobody, tell, x).
-!s[error(E)] <- .print("send failed ", E).""")
    out_mas.add_agent("b", "v(7).")
    assert out_mas.run(timeout=5)
    assert lines(buf.getvalue(), "a") == ["v(7)[source(b)]", "false", "send failed ia_failed"]


def test_mind_snapshot() -> None:
    arch = RecordingArch()
    ag = Agent("x", "b(1).\n!g.\n+!g <- act.", arch)
    run_until_idle(ag)
    m = mind_text(ag)
    assert "b(1)[source(self)]" in m["beliefs"]
    assert any("+!g" in i for i in m["intentions"]) and m["pending_actions"] == ["1: act"]


class _Arch(AgentArch):
    pass


def test_base_arch_defaults() -> None:
    ag = Agent("d", '!g.\n+!g <- .my_name(N); .all_names(L); .print(N, L).', _Arch(VirtualClock()))
    printed = []
    ag.arch.console = lambda n, t: printed.append(t)  # type: ignore[method-assign]
    run_until_idle(ag)
    assert printed == ["d[d]"]
    assert term_str(parse_literal("a")) == "a"


def test_run_loop_sleeps_until_wait_deadline_and_feedback_from_thread() -> None:
    arch = RecordingArch()
    arch.clock = WallClock()
    ag = Agent("t", '!g.\n+!g <- .wait(80); .print(waited); act(1); .print(acted).', arch)
    stop = threading.Event()
    th = threading.Thread(target=ag.run, args=(stop,), daemon=True)
    t0 = time.monotonic()
    th.start()
    wait_until(lambda: arch.actions, "the action after .wait(80)", period=0.005)
    assert arch.out == ["waited"] and time.monotonic() - t0 >= 0.08
    assert ag.is_idle() and ag.circ.has_pending()
    threading.Timer(0.02, lambda: ag.action_feedback(arch.actions[0][0], True)).start()
    wait_until(lambda: len(arch.out) >= 2, "the line after the feedback", period=0.005)
    assert arch.out == ["waited", "acted"]
    stop.set()
    th.join(2)
    assert not th.is_alive()
