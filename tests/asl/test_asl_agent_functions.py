"""``.count`` and ``math.random`` use the agent they are evaluated for, passed explicitly."""

from __future__ import annotations

import threading

from asl_helpers import RecordingArch, run_until_idle

from rason.asl import Agent
from rason.asl.parser import parse_term
from rason.asl.unify import resolve


def _counting_agent(name: str, n_beliefs: int) -> tuple[Agent, RecordingArch]:
    beliefs = "".join(f"b({k}). " for k in range(n_beliefs))
    arch = RecordingArch()
    src = beliefs + "!go.\n+!go <- for (.range(_, 1, 200)) { .print(.count(b(_))) }."
    return Agent(name, src, arch), arch


def test_count_in_agents_stepped_by_threads_counts_each_agents_own_beliefs() -> None:
    agents = [_counting_agent("a", 3), _counting_agent("b", 7)]
    barrier = threading.Barrier(2)

    def run(ag: Agent) -> None:
        barrier.wait()
        run_until_idle(ag)

    threads = [threading.Thread(target=run, args=(ag,)) for ag, _ in agents]
    for t in threads:
        t.start()
    for t in threads:
        t.join(30)
    assert set(agents[0][1].out) == {"3"} and len(agents[0][1].out) == 200
    assert set(agents[1][1].out) == {"7"} and len(agents[1][1].out) == 200


def test_math_random_draws_from_the_agents_own_seeded_generator() -> None:
    src = "!go.\n+!go <- X = math.random(1000); Y = math.random; .print(X, \" \", Y)."
    outs = []
    for seed in (1, 1, 2):
        arch = RecordingArch()
        run_until_idle(Agent("r", src, arch, seed=seed))
        outs.append(arch.out)
    assert outs[0] == outs[1] and outs[0] != outs[2]
    x, y = (float(v) for v in outs[0][0].split())
    assert 0 <= x < 1000 and 0 <= y < 1


def test_agent_functions_without_an_agent_stay_terms() -> None:
    term = parse_term("f(math.random(5), .count(b), 1+2)")
    out = resolve(term, {})
    assert str(out.args[0]) == "math.random(5)" and str(out.args[1]) == ".count(b)"
    assert out.args[2] == 3.0
