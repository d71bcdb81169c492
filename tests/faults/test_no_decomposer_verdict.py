"""Faulty with no decomposer ends unknown, saying why, once (#39, docs/thesis-fixes.md F13).

The case study's Faulty (``agents/diagnosis/faulty.asl`` as shipped) runs as an agent node in a
namespace where no motion decomposer runs: its first ``move(1)`` fails ``no_decomposer``. That
reason is not one ``!diagnoseAlone`` reads; the thesis' failure plan passed it on anyway and,
failing again, ran itself for ever (a million lines in 300 s, no verdict). Now the run ends
with ``diagnosis(unknown)`` and ``unknownBecause(no_decomposer)``, printed once.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from agent_nodes import mind

from rason.process.harness import RosHarness

pytestmark = pytest.mark.ros

FAULTY = Path(__file__).resolve().parents[2] / "agents" / "diagnosis" / "faulty.asl"


def test_faulty_without_a_decomposer_ends_unknown_with_the_reason_once(ros: RosHarness):
    faulty = ros.rosrun("rason", "agent", "faulty", str(FAULTY), ns="/nodec",
                        params={"ack_timeout": 2.0})
    # +!start waits 4 s, then move(1) waits ack_timeout for a decomposer
    faulty.wait_for_line(r"\[faulty\] the fault is unknown: no_decomposer", timeout=60)
    beliefs = mind(ros, "/nodec", "faulty")["beliefs"]
    assert any(b.startswith("diagnosis(unknown)") for b in beliefs), beliefs
    assert any(b.startswith("unknownBecause(no_decomposer)") for b in beliefs), beliefs
    out = faulty.output()
    assert out.count("something went wrong") == 1, out[-2000:]
    assert "no_applicable" not in out, out[-2000:]
