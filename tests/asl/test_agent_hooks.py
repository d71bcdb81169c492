"""The agent's customisation points without subclassing (docs/agent-hooks.md): event, option
and intention selection, the belief update function and the message acceptance function."""

from __future__ import annotations

import contextlib
import io
import os
import re
import subprocess
import sys
from pathlib import Path

from asl_helpers import RecordingArch, lines, run_until_idle

from rason.asl import Agent, Literal, LocalMas, Option, Selection, VirtualClock
from rason.asl.intentions import Event, Intention
from rason.asl.plans import ADD


def run(source: str, **hooks: object) -> list[str]:
    """Run one agent with the given hooks set as attributes; its printed lines."""
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    ag = mas.add_agent("main", source, "main.asl")
    for name, fn in hooks.items():
        if name in ("event", "option", "intention"):
            setattr(ag.selection, name, fn)
        else:
            setattr(ag, name, fn)
    mas.run(timeout=10)
    return lines(out.getvalue())


PLANS = """!g(2).
+!g(N) : N > 0 <- .print(first).
+!g(N) : N > 1 <- .print(second).
+!g(N) : N > 5 <- .print(never).
+!g(_) <- .print(last).
"""


def last_option(agent: Agent, options: list[Option]) -> Option:
    return options[-1]


def test_an_option_selector_changes_which_plan_runs() -> None:
    assert run(PLANS) == ["first"]
    assert run(PLANS, option=last_option) == ["last"]
    seen: list[list[str]] = []

    def second(agent: Agent, options: list[Option]) -> Option:
        seen.append([o.plan.body[0].term.args[0].functor for o in options])
        return options[1]

    # only the applicable plans are offered, in source order, each with its unifier
    assert run(PLANS, option=second) == ["second"]
    assert seen == [["first", "second", "last"]]


def test_an_option_selector_may_choose_none_then_no_plan_is_applicable() -> None:
    def not_for_g(agent: Agent, options: list[Option]) -> Option | None:
        return None if options[0].plan.trigger.op == ADD else options[0]

    assert run(PLANS + "-!g(N) <- .print(failed(N)).", option=not_for_g) == ["failed(2)"]


def test_an_event_selector_that_prefers_goals() -> None:
    src = "b(1). b(2). !g.\n+b(X) <- .print(belief(X)).\n+!g <- .print(goal).\n"
    # default: first in, first out (the beliefs' events were queued before the goal's)
    default = run(src)
    assert default[-1] == "goal"

    def goals_first(agent: Agent, events: list[Event]) -> Event:
        return next((ev for ev in events if ev.trigger.is_goal), events[0])

    chosen = run(src, event=goals_first)
    assert chosen[0] == "goal" and sorted(chosen[1:]) == sorted(default[:-1])


def test_an_intention_selector_runs_one_intention_to_its_end() -> None:
    src = "!a. !b.\n+!a <- .print(a1); .print(a2); .print(a3).\n+!b <- .print(b1); .print(b2).\n"
    assert run(src) == ["a1", "a2", "b1", "a3", "b2"]     # round robin

    def newest(agent: Agent, intentions: list[Intention]) -> Intention:
        return max(intentions, key=lambda i: i.id)

    # a's intention runs alone until b's is intended; then b runs to its end before a goes on
    assert run(src, intention=newest) == ["a1", "b1", "b2", "a2", "a3"]


def test_a_selection_passed_to_the_constructor() -> None:
    arch = RecordingArch()
    ag = Agent("main", PLANS, arch, selection=Selection(option=last_option))
    run_until_idle(ag)
    assert arch.out == ["last"]


def test_a_belief_update_function_filters_the_percepts() -> None:
    arch = RecordingArch()
    src = "+seen(X) <- .print(seen(X)).\n"

    def only_near(agent: Agent, percepts: list) -> bool:
        return agent.update_percepts([p for p in percepts if p.args[0] < 5])

    ag = Agent("main", src, arch, belief_update=only_near)
    arch.percepts = [Literal("seen", (float(k),)) for k in (1, 7, 3)]
    run_until_idle(ag)
    assert sorted(arch.out) == ["seen(1)", "seen(3)"]
    assert sorted(str(b) for b in ag.bb) == ["seen(1)[source(percept)]", "seen(3)[source(percept)]"]


def test_a_message_acceptance_function_drops_refused_messages() -> None:
    out = io.StringIO()
    mas = LocalMas(clock=VirtualClock(), out=out)
    mas.add_agent("bob", "!s.\n+!s <- .send(alice, tell, hi(bob)); .send(alice, achieve, go).\n",
                  "bob.asl")
    mas.add_agent("carol", "!s.\n+!s <- .send(alice, tell, hi(carol)).\n", "carol.asl")
    alice = mas.add_agent("alice", "+hi(X) <- .print(hi(X)).\n+!go <- .print(going).\n",
                          "alice.asl")
    alice.accept_message = lambda agent, m: m.sender != "bob"
    mas.run(timeout=10)
    assert lines(out.getvalue(), "alice") == ["hi(carol)"]


DOC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "docs", "agent-hooks.md")


def test_the_pages_example_prints_what_the_page_says() -> None:
    with open(DOC, encoding="utf-8") as f:
        text = f.read()
    code = re.search(r"```python\n(.*?)```", text, re.S)
    shown = re.search(r"prints \(the lines of `bob` and `ann` aside\)\n\n```\n(.*?)```", text, re.S)
    assert code is not None and shown is not None
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code.group(1), DOC, "exec"), {"__name__": "agent_hooks_example"})
    robot = [ln for ln in printed.getvalue().splitlines() if ln.startswith("[robot]")]
    assert robot == shown.group(1).splitlines()


MAS2J_SECTION = "## From a `.mas2j`"


def _page_project(tmp_path: Path) -> tuple[Path, list[str]]:
    """The files of the page's ``.mas2j`` example written to ``tmp_path``; the project file and
    the lines the page says it prints."""
    with open(DOC, encoding="utf-8") as f:
        section = f.read().split(MAS2J_SECTION, 1)[1]
    files = re.findall(r"`([\w.]+)`:\n\n```\w*\n(.*?)```", section, re.S)
    assert [name for name, _ in files] == ["picky.py", "robot.asl", "sender.asl", "hooks.mas2j"]
    for name, text in files:
        (tmp_path / name).write_text(text, encoding="utf-8")
    shown = re.search(r"prints\n\n```\n(.*?)```", section, re.S)
    assert shown is not None
    return tmp_path / "hooks.mas2j", shown.group(1).splitlines()


def _run_project(path: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rason.asl", "run", str(path), "--timeout", "30"],
                          capture_output=True, text=True, timeout=120, cwd=path.parent)


def test_the_pages_mas2j_example_installs_the_hooks_and_the_belief_base(tmp_path: Path) -> None:
    project, shown = _page_project(tmp_path)
    done = _run_project(project)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines() == shown
    # without the classes: the default option, every message, no seen(box)
    plain = tmp_path / "plain.mas2j"
    plain.write_text(re.sub(r" agentClass \S+ beliefBaseClass \S+;", ";", project.read_text()))
    done = _run_project(plain)
    assert done.stdout.splitlines() == ["[robot] hello", "[robot] hi_from(bob)", "[robot] hi_from(ann)"]


def test_a_class_that_does_not_import_is_an_error_with_file_line_and_name(tmp_path: Path) -> None:
    project, _ = _page_project(tmp_path)
    bad = tmp_path / "bad.mas2j"
    bad.write_text(project.read_text().replace("picky.customise", "picky.customize"))
    done = _run_project(bad)
    assert done.returncode == 2 and done.stdout == ""
    assert f"{bad}:3: agent robot: agentClass 'picky.customize'" in done.stderr
    assert "module 'picky' has no 'customize'" in done.stderr
    bad.write_text(project.read_text().replace("picky.remembered", "nowhere.remembered"))
    done = _run_project(bad)
    assert done.returncode == 2
    assert f"{bad}:3: agent robot: beliefBaseClass 'nowhere.remembered'" in done.stderr
    assert "No module named 'nowhere'" in done.stderr


def test_a_belief_base_class_must_make_a_belief_base(tmp_path: Path) -> None:
    project, _ = _page_project(tmp_path)
    (tmp_path / "odd.py").write_text("def bb(*facts):\n    return set(facts)\n")
    bad = tmp_path / "bad.mas2j"
    bad.write_text(project.read_text().replace("picky.remembered", "odd.bb"))
    done = _run_project(bad)
    assert done.returncode == 2
    assert "beliefBaseClass 'odd.bb': returned set, not a rason.asl.beliefs.BeliefBase" in done.stderr


def test_jasons_own_classes_are_noted_and_ignored(tmp_path: Path) -> None:
    (tmp_path / "a.asl").write_text("!g. +!g <- .print(hi).\n")
    project = tmp_path / "j.mas2j"
    project.write_text("MAS j { agents: a agentClass jason.asSemantics.Agent "
                       "beliefBaseClass jason.bb.JDBCPersistentBB; }")
    done = _run_project(project)
    assert done.returncode == 0 and done.stdout.splitlines() == ["[a] hi"]
    assert "agentClass jason.asSemantics.Agent ignored" in done.stderr
    assert "beliefBaseClass jason.bb.JDBCPersistentBB ignored" in done.stderr


def test_jasons_text_persistent_belief_base_is_rasons_own(tmp_path: Path) -> None:
    # (tests/asl/test_asl_jason_belief_bases.py: what it keeps, as Jason keeps it)
    (tmp_path / "a.asl").write_text("!g. +!g <- +met(bob); .print(hi).\n")
    project = tmp_path / "j.mas2j"
    project.write_text("MAS j { agents: a beliefBaseClass jason.bb.TextPersistentBB; }")
    done = _run_project(project)
    assert done.returncode == 0 and done.stdout.splitlines() == ["[a] hi"]
    assert "TextPersistentBB" not in done.stderr
    assert (tmp_path / "a.bb").read_text().splitlines()[2:] == ["met(bob)[source(self)]."]
