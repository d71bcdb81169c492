"""The st-claus latency benchmark (benchmarks/stclaus_latency.py): what it reads from a run's
stamped lines, how it gives every agent of a project the delaying architecture, and that
architecture (benchmarks/_latency_arch.py) on a real local MAS."""

from __future__ import annotations

import io
from collections import Counter

import pytest
from asl_helpers import load_benchmark

from rason.asl import LocalMas

bench = load_benchmark("stclaus_latency")
_latency_arch = load_benchmark("_latency_arch")


def test_a_round_runs_from_working_to_finished_and_its_hops_end_at_the_members_lines() -> None:
    run = bench.Stamped([
        (0.000, "santa", "Working with elfs: [e1,e2] (0)"),
        (0.001, "santa", "waiting to proceed with [e3,e4]"),
        (0.002, "e2", "Ho!"),
        (0.003, "e1", "Ho!"),
        (0.004, "e3", "Ho!"),                      # not of the group: not a hop
        (0.005, "santa", "Group [e1,e2] of elfs has finished"),
        (0.006, "santa", "Working with elfs: [e3,e4] (1)"),
        (0.007, "santa", "waiting to proceed with [e1,e2]"),
    ])
    seen = bench.figures("rason", run, ["e"])
    assert (seen.waiting, seen.working) == (2, 2)
    assert seen.round_ms == [pytest.approx(5.0)]            # the second round never finished
    assert seen.hop_ms == [pytest.approx(2.0), pytest.approx(2.0)]
    # the lines the permutation test compares: numbers made #, the copies e1..e4 one agent
    assert seen.lines["e#"] == Counter({"Ho!": 3})
    assert seen.lines["santa"]["waiting to proceed with [e#,e#]"] == 2


def test_every_agent_of_the_project_gets_the_delaying_architecture() -> None:
    mas = ("MAS m {\n  agents:\n    boss;\n"
           '    helper worker.asl [beliefs="k(1)"]  #3;\n    clerk clerk.asl;\n}\n')
    text = bench.with_latency(mas, 1.5)
    assert text.count('agentArchClass _latency_arch.delayed("1.500")') == 3
    assert 'helper worker.asl [beliefs="k(1)"] agentArchClass _latency_arch.delayed("1.500") #3;' in text
    assert "boss agentArchClass" in text


def test_delayed_messages_all_arrive_in_order_before_the_run_ends() -> None:
    # the receiver has nothing else to do while the messages are on their way: the run goes
    # on until they arrive (the sender's keep-alive timer), and a fixed delay keeps the order
    out = io.StringIO()
    mas = LocalMas(out=out)
    sender = mas.add_agent("sender", "!go.\n+!go <- .send(rec, tell, n(1)); "
                           ".send(rec, tell, n(2)); .send(rec, achieve, last).\n", "sender.asl")
    mas.add_agent("rec", "+n(X) <- .print(got(X)).\n+!last <- .print(last).\n", "rec.asl")
    _latency_arch.delayed(sender, "30")
    assert mas.run(timeout=20)
    assert [ln for ln in out.getvalue().splitlines() if ln.startswith("[rec]")] == [
        "[rec] got(1)", "[rec] got(2)", "[rec] last"]
