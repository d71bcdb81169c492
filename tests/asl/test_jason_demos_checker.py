"""The checker of Jason's demos (benchmarks/jason_demos.py) keeps its strict verdict and adds a
looser one for what changes from run to run of Jason itself: numbers (random offers,
milliseconds) and the order of list items (scheduling)."""

from __future__ import annotations

import importlib.util
import sys
from collections import Counter
from pathlib import Path

CHECKER = Path(__file__).resolve().parents[2] / "benchmarks" / "jason_demos.py"
_spec = importlib.util.spec_from_file_location("jason_demos_checker", CHECKER)
assert _spec is not None and _spec.loader is not None
demos = importlib.util.module_from_spec(_spec)
sys.modules[_spec.name] = demos   # (its dataclass looks itself up there)
_spec.loader.exec_module(demos)


def test_numbers_become_hashes_and_list_items_are_sorted() -> None:
    line = 'Offers are [offer(105.42,p2),offer(-1e3,p1)] after 12 ms to p2 and "a,b"'
    assert demos.loosened(line) == 'Offers are [offer(#,p1),offer(#,p2)] after # ms to p2 and "a,b"'
    assert demos.loosened("CFP to [p1,pr,p2]") == demos.loosened("CFP to [pr,p2,p1]")
    assert demos.top_level_items('f(a,b),"x,y",c') == ["f(a,b)", '"x,y"', "c"]


def test_the_loose_verdict_does_not_hide_other_differences() -> None:
    jason = demos.per_agent("[c] winner is p3 with 104.4\n[c] CFP to [p1,p2]\n")
    ours = demos.per_agent("[c] CFP to [p2,p1]\n[c] winner is p3 with 100.7\n")
    assert not demos.same_lines(jason, ours)
    assert demos.same_lines(demos.loosen(jason), demos.loosen(ours))
    # another winner is another line: names are not numbers
    other = demos.per_agent("[c] CFP to [p2,p1]\n[c] winner is p1 with 100.7\n")
    assert not demos.same_lines(demos.loosen(jason), demos.loosen(other))
    missing = demos.per_agent("[c] CFP to [p2,p1]\n")
    assert not demos.same_lines(demos.loosen(jason), demos.loosen(missing))
    assert demos.loosen(jason)["c"] == Counter({"winner is p3 with #": 1, "CFP to [p1,p2]": 1})


def test_copies_made_by_hash_n_are_named_in_a_mas2j() -> None:
    text = """MAS m { // p #9 in a comment is not an agent
        agents: c; p #3;
        elf worker.asl [beliefs="kind(elf), secretary(edna)"] #10;
        bob [goals="g"]; }"""
    assert demos.copied_agents(text) == ["p", "elf"]


def test_within_variation_takes_each_line_between_jasons_fewest_and_most() -> None:
    families = ["p"]
    runs = [demos.merge_copies(demos.loosen(demos.per_agent(text)), families) for text in (
        "[c] winner is p1 with 101.5\n[p1] I won\n[p2] I lost\n[c] waiting\n",
        "[c] winner is p2 with 103.0\n[p2] I won\n[p1] I lost\n[c] waiting\n[c] waiting\n[c] waiting\n",
    )]
    assert runs[0]["p#"] == Counter({"I won": 1, "I lost": 1})
    assert runs[0]["c"] == Counter({"winner is p# with #": 1, "waiting": 1})

    def ours(text: str) -> bool:
        return demos.within_variation(runs, demos.merge_copies(demos.loosen(demos.per_agent(text)),
                                                               families))

    # another winner and a count of a timed line that Jason's runs span: within
    assert ours("[c] winner is p3 with 99.1\n[p3] I won\n[p1] I lost\n[c] waiting\n[c] waiting\n")
    # a line every Jason run printed is missing, one no run printed is added, a count beyond
    assert not ours("[p1] I won\n[p2] I lost\n[c] waiting\n")
    assert not ours("[c] winner is p1 with 1\n[p1] I won\n[p2] I lost\n[c] waiting\n[c] tie\n")
    assert not ours("[c] winner is p1 with 1\n[p1] I won\n[p2] I lost\n" + "[c] waiting\n" * 4)


def test_a_run_is_ranked_among_jasons_by_the_lines_outside_the_others_range() -> None:
    def waits(n: int, done: int = 1) -> dict[str, Counter]:
        return demos.per_agent("[s] working\n" * done + "[s] waiting\n" * n)

    # Jason's own runs of a random program: none lies within the range of all the others
    jason = [waits(3), waits(5), waits(4, done=2), waits(6)]
    assert demos.lines_outside(waits(3), jason[1:]) == 1        # one "waiting" below 4-6
    assert demos.lines_outside(waits(9), jason) == 3            # three above 3-6
    assert not demos.within_variation(jason, waits(7, done=2))  # the first test rejects it...
    assert demos.as_atypical(jason, waits(7, done=2)) == 1      # ...though a run of 3 is as far off
    # the least typical of all runs: no Jason run as far off, nor when it ties no one
    assert demos.as_atypical(jason, waits(9)) == 0
    assert demos.as_atypical(jason, waits(4)) == len(jason)


def test_a_run_is_timed_from_its_first_agent_line(tmp_path: Path) -> None:
    # a slow start (as Jason's JVM) is not counted: the run goes on 0.8 s from its first line,
    # so both lines are there although the start alone took longer than 0.8 s
    script = ("import sys, time\ntime.sleep(1.0)\nprint('[a] first', flush=True)\n"
              "time.sleep(0.3)\nprint('[a] second', flush=True)\ntime.sleep(60)\n")
    run = demos.run_for([sys.executable, "-c", script], tmp_path, 0.8, start_limit=20.0)
    assert run.first_line is not None and run.first_line >= 1.0
    assert demos.per_agent(run.output)["a"] == Counter({"first": 1, "second": 1})
    # each line keeps when it came: the agent lines counted from the first one
    (t1, a1, x1), (t2, a2, x2) = run.agent_lines()
    assert (t1, a1, x1, a2, x2) == (0.0, "a", "first", "a", "second") and t2 >= 0.3
    assert run.agent_lines(seconds=0.2) == [(0.0, "a", "first")]


def test_a_run_without_agent_lines_stops_after_the_start_limit(tmp_path: Path) -> None:
    script = "import time\nprint('not an agent line', flush=True)\ntime.sleep(60)\n"
    run = demos.run_for([sys.executable, "-c", script], tmp_path, 0.2, start_limit=0.5)
    assert run.first_line is None
    assert run.output == "not an agent line\n"


def test_keep_writes_each_runs_output_and_each_agents_lines(tmp_path: Path) -> None:
    output = "[a] one\nJava says something\n[b] two\n[a] three _12\n"
    demos.keep_run(tmp_path, "demos/x/x.mas2j", "jason0", output)
    folder = tmp_path / "demos__x__x" / "jason0"
    assert (folder / "all.txt").read_text() == output
    assert (folder / "a.txt").read_text() == "one\nthree _12\n"
    assert (folder / "b.txt").read_text() == "two\n"
    demos.keep_run(None, "demos/x/x.mas2j", "rason", output)   # no --keep: nothing written
    assert not (tmp_path / "demos__x__x" / "rason").exists()


def test_a_documented_jason_defect_is_named_only_when_it_explains_the_difference() -> None:
    defect = demos.KNOWN_JASON_DEFECTS["demos/hard_deadline/hard_deadline.mas2j"]
    jason = ("[bob] init\n[bob] end2\njava.lang.NullPointerException: " + defect.sign + "\n")
    ours = "[bob] init\n[bob] end2\n[bob] failed, deadline_reached for g(9)\n"
    assert demos.defect_explains(defect, [jason, jason], ours)
    # a Jason run without the defect's sign: Jason printed so by itself, no excuse
    assert not demos.defect_explains(defect, [jason, "[bob] init\n[bob] end2\n"], ours)
    # any other difference is still a difference
    assert not demos.defect_explains(defect, [jason], ours + "[bob] g9\n")
    assert not demos.defect_explains(defect, [jason], "[bob] init\n[bob] end2\n")
    assert not demos.defect_explains(None, [jason], ours)


def test_a_project_needing_java_is_left_out_and_one_written_for_jade_is_run(
        tmp_path: Path) -> None:
    projects = {
        "demos/plain": "MAS p { agents: a; }",
        "demos/jade": 'MAS p { infrastructure: Jade(main_container_host("localhost"))\n'
                      '  agents: a at "c1"; b at "c2" #3; }',
        "demos/env": "MAS p { environment: my.Env agents: a; }",
        "demos/arch": "MAS p { agents: a agentArchClass my.Arch; }",
        "demos/jasons-own": "MAS p { agents: a agentClass jason.asSemantics.Agent; }",
        "demos/commented": "MAS p { // environment: my.Env\n agents: a; }",
        "examples/cartago": "MAS p { workspace: w { artifact c: tools.Counter } agents: a; "
                            "infrastructure: Cartago }",
    }
    for folder, text in projects.items():
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / "p.mas2j").write_text(text)
    (tmp_path / "demos/java").mkdir()
    (tmp_path / "demos/java/p.mas2j").write_text("MAS p { agents: a; }")
    (tmp_path / "demos/java/Helper.java").write_text("class Helper {}")
    found = {p.parent.relative_to(tmp_path).as_posix() for p in demos.find_projects(tmp_path)}
    assert found == {"demos/plain", "demos/jade", "demos/jasons-own", "demos/commented"}


def test_several_filters_select_the_projects_matching_any(tmp_path: Path) -> None:
    for folder in ("demos/current-intention", "examples/st-claus", "demos/idle"):
        (tmp_path / folder).mkdir(parents=True)
        (tmp_path / folder / "p.mas2j").write_text("MAS p { agents: a; }")
    found = demos.find_projects(tmp_path)
    assert len(found) == 3
    picked = demos.select_projects(found, tmp_path, ["current-intention", "st-claus"])
    assert [p.parent.name for p in picked] == ["current-intention", "st-claus"]
    assert demos.select_projects(found, tmp_path, []) == found
    assert demos.select_projects(found, tmp_path, ["nowhere"]) == []


def test_the_jason_version_is_read_from_the_trees_gradle_properties(tmp_path: Path) -> None:
    assert demos.jason_version(tmp_path) == "unknown"   # no gradle.properties
    (tmp_path / "gradle.properties").write_text("groupId=x\n  jasonVersion = 3.2.2\n")
    assert demos.jason_version(tmp_path) == "3.2.2"
    (tmp_path / "gradle.properties").write_text("groupId=x\nversion=1.0\n")
    assert demos.jason_version(tmp_path) == "unknown"


def test_the_permutation_test_tells_a_shifted_count_from_jasons_own_spread() -> None:
    def waits(n: int) -> dict[str, Counter]:
        return demos.per_agent("[s] working\n" + "[s] waiting\n" * n)

    assert demos.distance(waits(3), waits(7)) == 4
    assert demos.distance(waits(3), demos.per_agent("[t] done\n")) == 5
    jason = [waits(n) for n in (6, 9, 12, 8, 11)]
    # fewer "waiting" lines in every rason run: only the observed split (and its mirror image)
    # is as far apart
    assert demos.permutation_p(jason, [waits(n) for n in (4, 4, 5, 4, 5)]) == 2 / 252
    assert demos.smallest_p(5, 5) == 2 / 252
    # drawn from the same spread: many splits are as far apart as the observed one
    assert demos.permutation_p(jason, [waits(n) for n in (7, 12, 9, 10, 8)]) > 0.3
    # alike on both sides: every split ties
    assert demos.permutation_p([waits(2)] * 3, [waits(2)] * 2) == 1.0
    # one rason run can be at best the most extreme of six
    assert demos.permutation_p(jason, [waits(0)]) == 1 / 6 == demos.smallest_p(5, 1)
