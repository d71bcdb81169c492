"""Jason 3.3 language forms added for Jason's own unit-test suite (issue 13): include
directives, anonymous labels, goal-state meta events, plans and rules as terms, the lark
.mas2j grammar, .create_agent, .at, .type and Java's random generator."""

from __future__ import annotations

import re
import subprocess
import sys

from asl_helpers import lines, run_source

from rason.asl import parse_mas2j
from rason.asl.arch import JavaRandom


def test_include_merges_the_other_file_in_place(tmp_path) -> None:
    (tmp_path / "lib").mkdir()
    (tmp_path / "lib" / "helper.asl").write_text("greeting(hello).\n+!say <- ?greeting(G); .print(G).\n")
    (tmp_path / "main.asl").write_text('{ include("helper.asl") }\n!say.\n')
    (tmp_path / "p.mas2j").write_text('MAS p { agents: main; aslSourcePath: "lib"; }')
    out = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(tmp_path / "p.mas2j")],
                         capture_output=True, text=True, timeout=60)
    assert out.stdout.splitlines() == ["[main] hello"]


def test_missing_include_is_a_clear_error(tmp_path) -> None:
    (tmp_path / "main.asl").write_text('{ include("nowhere.asl") }\n')
    out = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(tmp_path / "main.asl")],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 2 and "nowhere.asl' was not found" in out.stderr


def test_anonymous_labels_are_named_and_keep_their_annotations() -> None:
    prog = ("!s.\n@[atomic, test] +!t <- true.\n"
            "+!s <- .relevant_plans({+!t}, _, [L]); N[test] = L; .print(N); !t.\n")
    out = lines(run_source(prog))
    assert len(out) == 1 and out[0].startswith("p__")


def test_goal_state_events_report_achieved_goals() -> None:
    prog = "!s.\n+!s <- !g(1).\n+!g(X) <- .print(working).\n^!g(X)[state(S)] <- .print(X, S).\n"
    out = lines(run_source(prog))
    # as Jason 3.3: the states are posted at the start of the next cycle, before other events
    assert out == ["1pending", "working", "1executing", "1achieved", "1finished"]


def test_goal_state_of_a_failed_goal() -> None:
    prog = "!g.\n+!g <- .fail.\n-!g <- true.\n^!g[state(failed)] <- .print(failed_seen).\n"
    assert "failed_seen" in lines(run_source(prog))


def test_plan_terms_unify_part_by_part() -> None:
    prog = ("!s.\n@lab[atomic] +!h(Y) : Y > 1 <- .print(a); .print(b).\n"
            "+!s <- .relevant_plans({+!h(_)}, [P]); P = {@L +!T : C <- B}; .print(T, \" \", C);"
            " {First; Rest} = B; .print(First); .print(Rest).\n")
    out = lines(run_source(prog))   # the plan comes with fresh variables, as in Jason
    assert out[0].startswith("h(_") and out[0].endswith(" > 1)")
    assert out[1:] == [".print(a)", ".print(b)"]   # body parts print without braces, as in Jason


def test_trigger_terms_from_the_intention_stack() -> None:
    prog = ("!go.\n+!go <- .intention(_, _, [im(Label, TG, {Now; _}, _)|_], current);"
            " TG = {+!G[_|_]}; _[code_line(Line)] = Label; .print(G, \" \", Line).\n")
    assert lines(run_source(prog)) == ["go 2"]


def test_rules_as_terms_are_added_and_listed() -> None:
    prog = ("!s.\n+!s <- +{ double(X, Y) :- Y = X * 2 }; ?double(4, D); .print(D);"
            " .relevant_rules(double(_, _), R); .print(R).\n")
    # stored with fresh variables, as Jason 3.3 prints it: [{ double(_22,_21) :- (_21 = (_22*2)) }]
    shown = lines(run_source(prog))
    assert shown[0] == "8"
    assert re.fullmatch(r"\[\{ double\((_\d+),(_\d+)\) :- \(\2 = \(\1\*2\)\) \}\]", shown[1]), shown


def test_belief_plan_terms_can_be_added() -> None:
    prog = "!s.\n+!s <- .add_plan({ +b : true <- .print(got_b) }); +b.\n"
    assert lines(run_source(prog)) == ["got_b"]


def test_type_lists_the_types_of_a_term() -> None:
    prog = ('!s.\n+!s <- .findall(T, .type(a, T), L1); .print(L1); .findall(T, .type("s", T), L2);'
            " .print(L2); .findall(T, .type(X, T), L3); .print(L3).\n")
    assert lines(run_source(prog)) == ["[atom,literal,structure,ground]", "[string,ground]", "[free]"]


def test_seeded_random_follows_java() -> None:
    # java.util.Random(20).nextDouble() is 0.7320427537419555 (checked against a JVM)
    r = JavaRandom(20)
    assert abs(r.random() - 0.7320427537419555) < 1e-15
    prog = "!s.\n+!s <- .set_random_seed(20); X = math.random(10); .print(math.round(X * 100)).\n"
    assert lines(run_source(prog)) == ["732"]


def test_at_posts_the_event_later() -> None:
    prog = '!s.\n+!s <- .at("now +50 ms", {+!later}); .print(first).\n+!later <- .print(later).\n'
    assert lines(run_source(prog)) == ["first", "later"]


def test_create_and_kill_agent(tmp_path) -> None:
    (tmp_path / "child.asl").write_text("+!hi[source(A)] <- .print(hi_from, A).\n")
    (tmp_path / "boss.asl").write_text('!s.\n+!s <- .create_agent(kid, "child.asl"); '
                                       ".send(kid, achieve, hi); .wait(200); .kill_agent(kid);"
                                       " .all_names(N); .print(N).\n")
    (tmp_path / "p.mas2j").write_text("MAS p { agents: boss; }")
    out = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(tmp_path / "p.mas2j")],
                         capture_output=True, text=True, timeout=60)
    assert out.stdout.splitlines() == ["[kid] hi_fromboss", "[boss] [boss]"]


def test_mas2j_full_grammar(tmp_path) -> None:
    text = """MAS full {
        infrastructure: Centralised
        environment: my.Env(1, "x") at "host1"
        executionControl: jason.control.ExecutionControl
        agents:
            a ./sub/a.asl [verbose=2, goals="g(1)", beliefs="b(2)"] agentArchClass x.Arch #2;
            b agentClass my.Ag beliefBaseClass my.BB(3) at "host2";
        directives: d = my.Directive;
        classpath: "lib";
        aslSourcePath: "src"; "$jasonJar/test";
    }"""
    proj = parse_mas2j(text, str(tmp_path / "full.mas2j"))
    assert [a.name for a in proj.agents] == ["a1", "a2", "b"]
    assert proj.agents[0].asl_path.endswith("sub/a.asl") and proj.agents[0].arch_class == "x.Arch"
    assert proj.agents[0].options["goals"] == "g(1)"
    assert proj.agents[2].bb_class == "my.BB(3)" and proj.agents[2].host == "host2"
    assert proj.source_path[0].endswith("src")
    notes = " ".join(proj.notes)
    for word in ("infrastructure", "environment", "executionControl", "directives", "classpath",
                 "verbose"):
        assert word in notes


def test_mas2j_goals_and_beliefs_options(tmp_path) -> None:
    (tmp_path / "a.asl").write_text("+!g(X) : b(Y) <- .print(X + Y).\n")
    (tmp_path / "p.mas2j").write_text('MAS p { agents: a [goals="g(1)", beliefs="b(2)"]; }')
    out = subprocess.run([sys.executable, "-m", "rason.asl", "run", str(tmp_path / "p.mas2j")],
                         capture_output=True, text=True, timeout=60)
    assert out.stdout.splitlines() == ["[a] 3"]
