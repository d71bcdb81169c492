"""A lone agent's start imports no ``dataclasses`` (nor ``inspect``, which it imports); the
records on that path, written without the decorator, keep what it gave them."""

from __future__ import annotations

import pickle
import subprocess
import sys

import pytest

from rason.asl import AgentOptions, Message, parse_source
from rason.asl.df import ProviderNotice, Registration
from rason.asl.intentions import ActionResult, AskWait, Fork, ForkBranch, Intention
from rason.asl.parser import AgentSource


def test_a_lone_agent_starts_without_dataclasses_or_inspect(tmp_path) -> None:
    agent = tmp_path / "lone.asl"
    agent.write_text("!start.\n+!start <- .print(done).\n", encoding="utf-8")
    # the modules the interpreter's own start imported (a site .pth may import anything) are
    # left out: only what rason's start adds counts
    code = ("import sys\nbefore = set(sys.modules)\nfrom rason.asl.cli import main\n"
            "code = main(['run', sys.argv[1], '--timeout', '30'])\n"
            "added = set(sys.modules) - before\n"
            "print(code, sorted(added & {'dataclasses', 'inspect'}))")
    done = subprocess.run([sys.executable, "-c", code, str(agent)],
                          capture_output=True, text=True, timeout=60, check=False)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[-2:] == ["0", "[]"], done.stdout


def test_messages_get_fresh_ids_compare_by_value_and_are_not_hashable() -> None:
    a = Message("bob", "alice", "tell", "hello")
    b = Message("bob", "alice", "tell", "hello")
    assert a.msg_id != b.msg_id and a.in_reply_to is None
    assert a != b
    b.msg_id = a.msg_id
    assert a == b
    assert Message("bob", "alice", "tell", "hello", msg_id="m1", in_reply_to="m0").msg_id == "m1"
    with pytest.raises(TypeError):
        hash(a)
    assert repr(a).startswith("Message(sender='bob', receiver='alice', performative='tell'")


def test_immutable_records_refuse_changes_and_hash_by_value() -> None:
    options = AgentOptions(max_intention_depth=40)
    assert options == AgentOptions(True, 40) and options.tro
    assert AgentOptions.from_options({"tro": "false"}, options) == AgentOptions(False, 40)
    with pytest.raises(AttributeError):
        options.tro = False  # type: ignore[misc]
    assert len({Registration("a", "s"), Registration("a", "s"), Registration("b", "s")}) == 2
    assert str(ProviderNotice("c", "a", "s").content()) == 'provider(a,"s")'
    result = ActionResult(3, False, reason="blocked")
    assert (result.action_id, result.ok, result.reason, result.message, result.annots) == (
        3, False, "blocked", "", None)


def test_mutable_records_start_empty_and_compare_by_value() -> None:
    fork = Fork(True)
    assert fork.branches == [] and fork.to_finish == 0 and fork.branches is not Fork(True).branches
    assert fork == Fork(True) and fork != Fork(False)
    assert ForkBranch(fork, 2) == ForkBranch(Fork(True), 2) != ForkBranch(fork, 3)
    waiting = Intention()
    wait = AskWait(waiting, "X", "askOne", None)
    assert wait.answers == [] and wait == AskWait(waiting, "X", "askOne", None)
    source = AgentSource()
    assert (source.beliefs, source.goals, source.plans, source.filename) == ([], [], [], "<string>")
    assert AgentSource(filename="a.asl") == AgentSource(filename="a.asl") != source


def test_plans_compare_by_identity_and_survive_pickling() -> None:
    plan = parse_source("+!g(X) : true <- .print(X); !h.\n").plans[0]
    again = parse_source("+!g(X) : true <- .print(X); !h.\n").plans[0]
    assert plan != again and plan == plan
    assert plan.context is None   # a ``true`` context is no context
    assert plan.rev_body == tuple(reversed(plan.body))
    copied = pickle.loads(pickle.dumps(plan))
    assert str(copied) == str(plan) and len(copied.body) == len(plan.body) == 2
    assert copied.rev_body == tuple(reversed(copied.body))   # derived anew when unpickled
    assert repr(plan).startswith("Plan(label=")
