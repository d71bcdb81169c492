#!/usr/bin/env python3
"""Random AgentSpeak programs run by real Jason and by rason.asl: the same lines, in order?

Needs a Jason jar built on this machine, given with ``--jason-jar`` as a Java classpath with
the javax.json jars (docs/jason-compatibility.md: how, and the results). Each seed makes
``--programs`` random programs (one agent each) of several intentions interleaving goals,
subgoals, new-focus goals, belief changes with and without plans, test goals, failures and
failure plans, loops, control actions and introspection (``.intend``, ``.desire``,
``.intention``, ``.count``); every deed prints where its intention is. All the programs of a
seed run as the agents of one Jason MAS (an agent's console lines do not depend on the others:
they share nothing) and one by one in rason.asl's ``LocalMas``; the lines of each agent are
compared, fresh variable names aside.

    python benchmarks/jason_differential.py --jason-jar CLASSPATH [--seeds 1 2 3] [--programs 40]
        [--kqml | --meta] [--goals]

Prints each program whose lines differ (with both outputs) and the count of equal ones; exits
1 when any differs.
"""

from __future__ import annotations

import argparse
import io
import random
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "catkin_ws" / "src" / "rason" / "src"))

from rason.asl import LocalMas, VirtualClock  # noqa: E402

#: Deeds of the random plan bodies; ``V`` becomes the deed's place (fresh variables per deed).
DEEDS = (
    "+x(1)", "-x(1)", "-+y(2)", "+z(3)", "-z(3)", "+w", "-w", ".print(p)", "!!h", "?y(_)",
    "!sub", "!deep(2)", "?q(QV)", "+z(4)", "!maybe",
    ".findall(GV, .intend(GV), LV); .print(intends, LV)",
    ".findall(DV, .desire(DV), LV); .print(desires, LV)",
    "NV = .count(.desire(_)); .print(desire_count, NV)",
    ".findall(SV, .intention(_, SV), LV); .print(states, LV)",
    "-+v(.count(.intend(_))); ?v(CV); .print(v, CV)",
    "if (.intend(sub)) { .print(in_sub) } else { .print(not_in_sub) }",
    "for (.member(MV, [1, 2])) { .print(m, MV) }", "while (x(_)) { -x(_); .print(wx) }",
    ".succeed_goal(g0)", ".drop_desire(g1)", "!!k(V)", ".fail",
    # values: arithmetic, lists, strings, rules, annotations, printed
    "AV = 7 / 2 + 3 * 2 - 10 mod 3; .print(arith, AV)", "BV = 2 ** 10 div 3; .print(pow, BV)",
    ".findall(RV, r(RV), LV); .print(rules, LV)", ".sort([c, 3, \"s\", b(1), [2], 1.5, a], LV); .print(LV)",
    ".concat(\"ab\", [1, x], \"c\", LV); .print(LV)", ".length([a, b | [c]], LV); .print(len, LV)",
    "?r(RV); .print(first_r, RV)", "+t(1)[k(V)]; ?t(TV)[k(KV)]; .print(t, TV, KV)",
    ".term2string(f(X, \"s\", [1.0, -2.5e3]), SV); .print(SV)", ".print(math.round(2.5), math.abs(-3.2))",
    ".setof(QV, .member(QV, [b, a, b]), LV); .print(LV)", ".nth(1, [a, b, c], EV); .print(EV)",
    ".substring(\"ell\", \"hello\", PV); .print(sub, PV)", "if (r(3) & not r(5)) { .print(yes) }",
    # more control: contexts, suspension, dropping, plans added at run time
    "!c", ".suspend(g1)", ".resume(g1)", ".drop_intention(g2)", ".abolish(z(_))",
    ".add_plan({+!ap <- .print(added)}); !ap", ".relevant_plans({+!c}, LV); .length(LV, NV); .print(NV)",
    "while (not x(_) & y(YV) & YV < 3) { -+y(YV + 1); .print(yv) }",
    # failures whose annotations g2's failure plan prints
    "?nothing(_)", ".nth(9, [a], _)", "!nothere(V)", "XV = 1 / 0", ".length(a, _)",
)
# Not here: .fail_goal(g2) of another intention's goal with a -!g2 plan, which Jason 3.3.2
# answers with a NullPointerException in the internal action (rason runs -!g2); a failed
# constraint in a body (3 > 4), whose error_msg Jason writes with the rest of the plan body
# and the unifier (in Java's hash order), rason with the constraint only.

#: Plans every program has besides its goals' plans.
COMMON_PLANS = """
+z(N) <- .print(z, N).
-z(N) <- .print(not_z, N).
+!h <- .print(h).
+!sub <- +x(9); .print(sub).
+!deep(0) <- .findall(G, .intend(G), L); .print(deep, L).
+!deep(N) <- !deep(N - 1); .print(up, N).
+?q(7) <- .print(asked).
+!maybe : w <- .print(maybe_w).
-!maybe <- .print(maybe_failed).
+!k(N) <- .print(k, N).
+!c : x(_) & not w <- .print(c1).
+!c : w <- .print(c2).
+!c <- .print(c3).
r(1). r(2).
r(X) :- X = 3.
r(X) :- q2(X).
q2(40).
-!g2[error(E), error_msg(M), code(C), code_line(L)] <- .print(g2_failed, E, "|", M, "|", C, "|", L).
"""

#: With ``--meta``: deeds of introspection and meta-programming besides :data:`DEEDS` (the
#: unifier of the running means, a plan body in a variable, a function registered with a
#: rule, a goal with several applicable plans).
META_DEEDS = (
    ".intention(_, _, [im(_, _, _, UV)|_], current); .print(unif, UV)",
    "BV = {.print(in_body_var); +x(2)}; BV", ".print(fn, df.add(2, 3) * 2)", "!sel(V)",
    # plan texts (statements and forks as Jason prints them), a plan-body term as a deed
    ".relevant_plans({+!ctl(_)}, LV); .print(LV)", ".plan_label(PV, ctl); .print(PV)",
    "{.print(in_block); +x(2)}; .print(after_block)",
)

#: With ``--goals``: deeds of ``.fail_goal``/``.succeed_goal`` of goals that have a caller, from
#: the goal's own intention (a subgoal's plan or the goal's own plan) and from another one,
#: besides :data:`DEEDS`; their plans are :data:`GOAL_PLANS`.
GOAL_DEEDS = ("!fg(V)", "!fs(V)", "!sg(V)", "!!fo(V)", ".fail_goal(fw(_))", ".succeed_goal(fw(_))")

#: With ``--goals``: fg's subgoal fails fg (a failure plan runs), fs fails itself (no failure
#: plan), sg's subgoal achieves sg; fo's subgoal fw is what other intentions fail or achieve.
GOAL_PLANS = """
+!fg(N) <- !fgsub(N); .print(fg_after, N).
+!fgsub(N) <- .print(fgsub, N); .fail_goal(fg(N)); .print(fgsub_after, N).
-!fg(N) <- .print(fg_failed, N).
+!fs(N) <- .print(fs, N); .fail_goal(fs(N)); .print(fs_after, N).
+!sg(N) <- !sgsub(N); .print(sg_after, N).
+!sgsub(N) <- .print(sgsub, N); .succeed_goal(sg(N)); .print(sgsub_after, N).
+!fo(N) <- !fw(N); .print(fo_after, N).
+!fw(N) <- .print(fw, N); .print(fw1, N); .print(fw2, N).
-!fw(N) <- .print(fw_failed, N).
"""

#: With ``--meta``: read first (a function is one from its directive on, as Jason reads it).
META_HEADER = """{ register_function("df.add", 2, "add3") }
add3(X, Y, Z) :- Z = X + Y.
+!sel(N) : r(R) & R > N <- .print(sel, N, R).
+!sel(N) <- .print(sel_none, N).
@ctl +!ctl(N) <- if (N > 1) { .print(a); .print(b) } elif (w) { .print(c) } else { };
    for (r(R)) { .print(R) }; while (x(_)) { -x(_) }; !h |&| {.print(d); !sub}; !h ||| (!sub |&| !h).
"""
# Not here: a select__option rule. One that refuses the plans labelled [skip] only
# (``not (P = {@L +!T : C <- B} & L =.. [_, _, As] & .member(skip, As))``) refuses, in
# Jason 3.3.2, some plans of the random programs that it accepts alone (a plan with
# ``.intention(_, _, [im(...)|_], current)`` and a ``while``), which then throws
# IndexOutOfBoundsException and clears the agent's circumstance; not explained yet.

#: The question an asker waits on after each deed: the answerer's plan for it waits long enough
#: for its reactions to end (on Jason, 100 ms of the wall's clock; on rason's virtual clock,
#: time moves only when no agent has anything to do)
SETTLED = "settled"

#: Deeds of an asker talking to its answerer ``R``. The asker has one intention and, after
#: every deed, asks :data:`SETTLED` and waits for the answer, which comes once the answerer's
#: reactions are over, so both agents' lines have one order. (A question answered at once,
#: such as ``v(_)``, is no such barrier: the answerer takes one message a cycle and runs one
#: deed of one intention a cycle, so a question can be answered before the reactions to the
#: message before it, on Jason as on rason, as the agents' turns fall: a told plan not added
#: yet, a told list half added, a branch of a session not run yet.)
KQML_DEEDS = (
    ".send(R, tell, hello(V))", ".send(R, tell, [a(V), b(V)])", ".send(R, achieve, do(V))",
    ".send(R, askOne, v(XV), AV); .print(ans, AV)", ".send(R, askOne, v(XV)[k(KV)], AV); .print(ans, AV)",
    ".send(R, askAll, v(XV), LV); .print(all, LV)", ".send(R, askOne, nothing(XV), AV); .print(none, AV)",
    ".send(R, askOne, rv(XV), AV); .print(rule, AV)", ".send(R, untell, hello(1))",
    ".send(R, askOne, hello(XV), AV); .print(told, AV)", ".send(R, askAll, hello(XV), LV); .print(LV)",
    ".send(R, tellHow, \"+!extra(N) <- .print(extra, N).\"); .send(R, askOne, " + SETTLED + ", _); "
    ".send(R, achieve, extra(V))",
    ".send(R, tellHow, \"@nest +!nest(N) <- !in(N). { +!in(M) <- .print(nest, M, N). }\"); "
    ".send(R, askOne, " + SETTLED + ", _); .send(R, achieve, nest(V))",
    ".send(R, askOne, b(XV)[source(SV)], AV); .print(src, AV)",
    ".send(R, askHow, {+!ctl(_)}, LV); .print(how, LV)",
    # a session of the answerer (a plan with inner plans for told beliefs, waiting <: false):
    # notes, flags (an inner plan whose trigger is a variable) and the close reach it through
    # branches of its intention
    ".send(R, achieve, open(1))", ".send(R, tell, note(1, V))", ".send(R, tell, flag(V))",
    ".send(R, tell, close(1)); .send(R, untell, close(1))",
)

#: The answerer: what it believes, its rules and how it reacts (it never acts on its own).
ANSWERER = """
v(1)[k(a)]. v(2).
rv(X) :- v(X) & X > 1.
+hello(N)[source(S)] <- .print(hello, N, S).
-hello(N) <- .print(untold, N).
+!do(N)[source(S)] <- .print(do, N, S).
+a(N) <- .print(a, N).
@ctl +!ctl(N) <- if (N > 1) { .print(a) } else { .print(b) }; for (v(X)) { .print(X) }; !do(N) ||| !do(1).
+!open(N) <: false <- .print(open, N).
    {
    +note(N, X) : X > 2 <- !jot(X).
    +close(N) <- .print(closed, N); .done.
    +!jot(Y) <- .print(note, N, Y).
    +X : X = flag(K)[source(_)] <- .print(flag, N, K).
    }
""" + f"+?{SETTLED} <- .wait(100).\n"

FRESH = re.compile(r"\b_\d+\w*")


@dataclass
class Difference:
    """A program whose lines differ, and both outputs."""

    agent: str
    program: str
    jason: list[str]
    rason: list[str]


def random_program(rng: random.Random, meta: bool = False, goals: bool = False) -> str:
    """One agent: 1-4 initial goals, each a plan of 1-6 deeds that print their place (with
    ``meta``, from :data:`META_DEEDS` too, after :data:`META_HEADER`; with ``goals``, from
    :data:`GOAL_DEEDS` too)."""
    deeds = DEEDS + META_DEEDS if meta else DEEDS
    if goals:
        deeds += GOAL_DEEDS
    bodies = [[rng.choice(deeds) for _ in range(rng.randint(1, 6))] for _ in range(rng.randint(1, 4))]
    plans = [f"+!g{k} <- " + "; ".join(f'{d.replace("V", str(n))}; .print("g{k}.{n}")'
                                       for n, d in enumerate(body)) + "."
             for k, body in enumerate(bodies)]
    initial = "".join(f"!g{k}. " for k in range(len(bodies)))
    header = META_HEADER if meta else ""
    extra = GOAL_PLANS if goals else ""
    return (header + "y(0).\n" + initial + "\n" + "\n".join(plans) + "\n" + COMMON_PLANS
            + extra)


def random_asker(rng: random.Random, answerer: str) -> str:
    """One intention of 1-8 KQML deeds to ``answerer``, each printing its place."""
    body = [rng.choice(KQML_DEEDS) for _ in range(rng.randint(1, 8))]
    deeds = "; ".join(f'{d.replace("V", str(n)).replace("R", answerer)}; '
                      f'.send({answerer}, askOne, {SETTLED}, _); .print("q.{n}")'
                      for n, d in enumerate(body))
    return f"!go.\n+!go <- {deeds}.\n"


def agent_lines(text: str, agent: str) -> list[str]:
    """The console lines of ``agent`` (``[agent] ...``), fresh variable names made equal."""
    prefix = f"[{agent}] "
    return [FRESH.sub("_", ln[len(prefix):]) for ln in text.splitlines() if ln.startswith(prefix)]


def run_jason(programs: dict[str, str], classpath: str, folder: Path, timeout: float) -> str:
    """All the programs as the agents of one Jason MAS (a last agent stops it); its console."""
    for name, source in programs.items():
        (folder / f"{name}.asl").write_text(source)
    (folder / "stopper.asl").write_text("!s.\n+!s <- .wait(4000); .stopMAS.\n")
    (folder / "m.mas2j").write_text("MAS m { agents: " + "; ".join([*programs, "stopper"]) + "; }\n")
    (folder / "logging.properties").write_text(   # Jason's own console format: "[agent] text"
        "handlers = java.util.logging.ConsoleHandler\n.level = INFO\n"
        "java.util.logging.ConsoleHandler.formatter = jason.runtime.MASConsoleLogFormatter\n")
    done = subprocess.run(["java", "-cp", classpath, "jason.infra.local.RunLocalMAS", "m.mas2j",
                           "--log-conf", "logging.properties"], cwd=folder, timeout=timeout,
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return done.stdout


def run_rason(programs: dict[str, str]) -> str:
    """The agents in one rason.asl ``LocalMas``; its console."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    for name, source in programs.items():
        mas.add_agent(name, source, f"{name}.asl")
    mas.run(timeout=10.0)
    return out.getvalue()


def compare(seed: int, count: int, classpath: str, timeout: float,
            kqml: bool = False, meta: bool = False, goals: bool = False) -> tuple[int, list[Difference]]:
    """``count`` programs of ``seed`` (lone agents, or with ``kqml`` askers and their answerers;
    ``meta``: see :data:`META_DEEDS`; ``goals``: see :data:`GOAL_DEEDS`)."""
    rng = random.Random(seed)
    if kqml:
        groups = [{f"s{seed}q{k}": random_asker(rng, f"s{seed}r{k}"), f"s{seed}r{k}": ANSWERER}
                  for k in range(count)]
    else:
        groups = [{f"s{seed}a{k}": random_program(rng, meta, goals)} for k in range(count)]
    everyone = {name: source for group in groups for name, source in group.items()}
    with tempfile.TemporaryDirectory() as tmp:
        jason_out = run_jason(everyone, classpath, Path(tmp), timeout)
    if not any(f"[{name}]" in jason_out for name in everyone):
        raise RuntimeError(f"Jason printed nothing of the programs:\n{jason_out[-2000:]}")
    differences = []
    for group in groups:
        rason_out = run_rason(group)
        jason = [f"{n}: {ln}" for n in group for ln in agent_lines(jason_out, n)]
        rason = [f"{n}: {ln}" for n in group for ln in agent_lines(rason_out, n)]
        if jason != rason:
            differences.append(Difference(", ".join(group), "\n".join(group.values()), jason, rason))
    return count, differences


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--jason-jar", required=True,
                        help="Java classpath: Jason's jar and the javax.json jars it needs")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3, 4, 5])
    parser.add_argument("--programs", type=int, default=40, help="programs per seed")
    parser.add_argument("--timeout", type=float, default=120.0, help="s for one Jason MAS")
    parser.add_argument("--kqml", action="store_true",
                        help="pairs of agents: one asks and tells, the other answers and reacts")
    parser.add_argument("--meta", action="store_true",
                        help="lone agents with register_function, .intention's unifiers and "
                             "plan bodies in variables too")
    parser.add_argument("--goals", action="store_true",
                        help="lone agents failing and achieving goals that have a caller too")
    args = parser.parse_args()
    total = same = 0
    for seed in args.seeds:
        count, differences = compare(seed, args.programs, args.jason_jar, args.timeout, args.kqml,
                                     args.meta, args.goals)
        for d in differences:
            print(f"=== {d.agent}\n{d.program}\njason: {d.jason}\nrason: {d.rason}\n")
        total += count
        same += count - len(differences)
        print(f"seed {seed}: {count - len(differences)}/{count} programs print the same lines")
    print(f"\n{same}/{total} random programs print the same lines in real Jason and in rason.asl")
    return 0 if same == total else 1


if __name__ == "__main__":
    sys.exit(main())
