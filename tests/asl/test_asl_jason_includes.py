"""Where ``{ include(...) }`` and ``.include`` find a file, and the ``url`` its plans get, as
Jason 3.3 does (checked 2026-11-27 on a project run from its folder): relative to the
including file's folder (an included file's own includes too), then to the project's source
paths; ``file:`` before a path; ``jar:file:JAR!/ENTRY``, read from the jar (a zip). The url is
``file:`` and the path found, relative to the project's folder."""

from __future__ import annotations

import io
import re
import zipfile
from pathlib import Path

import pytest

from rason.asl import LocalMas, VirtualClock, load_mas2j
from rason.asl.parser import AslSyntaxError, path_include_resolver

MAIN = """\
{ include("sub/s.asl") }
{ include("l.asl") }
{ include("file:lib/f.asl") }
{ include("jar:file:JAR!/inc/j.asl") }
!start.
+!start <- .include("sub/dyn.asl"); .include("lib/f2.asl", N); .print(ns, N);
    .relevant_plans({+!_}, L); for (.member(P, L)) { .print(P) }.
"""


def _project(root: Path) -> Path:
    """A project whose agent includes files in every form; its ``.mas2j``."""
    for path, text in {
        "src/sub/s.asl": '+!s <- .print(s). { include("near.asl") }\n',
        "src/sub/near.asl": "+!near <- .print(near).\n",
        "src/sub/dyn.asl": "+!dyn <- .print(dyn).\n",
        "lib/l.asl": "+!l <- .print(l).\n",
        "lib/f.asl": "+!f <- .print(f).\n",
        "lib/f2.asl": "+!f2 <- .print(f2).\n",
    }.items():
        (root / path).parent.mkdir(parents=True, exist_ok=True)
        (root / path).write_text(text)
    jar = root / "x.jar"
    with zipfile.ZipFile(jar, "w") as z:
        z.writestr("inc/j.asl", '+!j <- .print(j). { include("k.asl") }\n')
        z.writestr("inc/k.asl", "+!k <- .print(k).\n")
    (root / "src/a.asl").write_text(MAIN.replace("JAR", str(jar)))
    mas = root / "m.mas2j"
    mas.write_text('MAS m { agents: a; aslSourcePath: "src"; "lib"; }\n')
    return mas


def _run(mas: Path) -> list[str]:
    out = io.StringIO()
    runner = LocalMas(clock=VirtualClock(), out=out)
    runner.load_project(load_mas2j(str(mas)))
    runner.run(timeout=10.0)
    return [re.sub(r"\b_\d+", "_N", re.sub(r"p__\d+", "p__N", ln))
            for ln in out.getvalue().splitlines()]


def test_every_form_is_found_and_named_as_jason_names_it(tmp_path: Path, monkeypatch) -> None:
    mas = _project(tmp_path)
    monkeypatch.chdir(tmp_path)      # as Jason runs a project: from its folder
    shown = _run(mas)
    assert re.fullmatch(r"\[a\] nsns\d+", shown[0])   # the free namespace: a new one
    urls = [re.search(r'url\("([^"]*)"\)\] \+!(\w+)', ln).groups() for ln in shown[1:]]
    # the default KQML plans are listed too, as Jason's resource kqmlPlans.asl
    assert {u for u, _ in urls if "kqml" in u} == {"kqmlPlans.asl"}
    urls = [(u, g) for u, g in urls if "kqml" not in u]
    jar = f"jar:file:{tmp_path}/x.jar!/inc/j.asl"
    assert urls == [
        ("file:src/sub/s.asl", "s"), ("file:src/sub/near.asl", "near"), ("file:lib/l.asl", "l"),
        ("file:lib/f.asl", "f"), (jar, "j"),
        # beside j.asl in the jar (Jason 3.3 does not find it there: rason's own)
        (f"jar:file:{tmp_path}/x.jar!/inc/k.asl", "k"),
        ("file:src/a.asl", "start"), ("file:src/sub/dyn.asl", "dyn")]


def test_a_project_outside_the_current_folder_names_its_files_by_their_full_path(
        tmp_path: Path, monkeypatch) -> None:
    mas = _project(tmp_path / "p")
    (tmp_path / "elsewhere").mkdir()
    monkeypatch.chdir(tmp_path / "elsewhere")
    shown = " ".join(_run(mas))
    assert f'url("file:{tmp_path}/p/lib/l.asl")' in shown
    assert f'url("file:{tmp_path}/p/src/sub/near.asl")' in shown


def test_a_missing_jar_or_entry_is_not_found(tmp_path: Path) -> None:
    resolve = path_include_resolver([])
    with zipfile.ZipFile(tmp_path / "y.jar", "w") as z:
        z.writestr("a.asl", "b.\n")
    assert resolve(f"jar:file:{tmp_path}/y.jar!/a.asl", "")[1] == "b.\n"
    for url in (f"jar:file:{tmp_path}/y.jar!/none.asl", f"jar:file:{tmp_path}/no.jar!/a.asl",
                f"jar:file:{tmp_path}/y.jar"):
        with pytest.raises(OSError):
            resolve(url, "")
    (tmp_path / "main.asl").write_text(f'{{ include("jar:file:{tmp_path}/y.jar!/none.asl") }}\n')
    runner = LocalMas(clock=VirtualClock(), out=io.StringIO())
    with pytest.raises(AslSyntaxError, match=r"none\.asl' was not found"):
        runner.add_agent("main", (tmp_path / "main.asl").read_text(), str(tmp_path / "main.asl"))


def test_jason_jar_paths_are_read_from_the_jar_or_tree_named_by_the_environment(
        tmp_path: Path, monkeypatch) -> None:
    # a file of the same name beside the agent: found by its name when no Jason is named
    (tmp_path / "helper.asl").write_text("+!h <- .print(beside).\n")
    (tmp_path / "main.asl").write_text(
        '{ include("$jasonJar/test/jason/inc/helper.asl") }\n!h.\n')
    jar = tmp_path / "jason.jar"
    with zipfile.ZipFile(jar, "w") as z:
        z.writestr("test/jason/inc/helper.asl",
                   '+!h <- .print(in_jar); !more.\n{ include("$jasonJar/asl/more.asl") }\n')
        z.writestr("asl/more.asl", "+!more <- .print(more_in_jar).\n")
    tree = tmp_path / "jason-tree" / "jason-interpreter" / "src"
    (tree / "test/jason/inc").mkdir(parents=True)
    (tree / "main/resources/asl").mkdir(parents=True)
    (tree / "test/jason/inc/helper.asl").write_text(
        '+!h <- .print(in_tree); !more.\n{ include("$jasonJar/asl/more.asl") }\n')
    (tree / "main/resources/asl/more.asl").write_text("+!more <- .print(more_in_tree).\n")

    def shown() -> list[str]:
        out = io.StringIO()
        runner = LocalMas(clock=VirtualClock(), out=out)
        runner.add_agent("main", (tmp_path / "main.asl").read_text(), str(tmp_path / "main.asl"))
        runner.run(timeout=10.0)
        return out.getvalue().splitlines()

    monkeypatch.delenv("RASON_JASON_JAR", raising=False)
    assert shown() == ["[main] beside"]
    monkeypatch.setenv("RASON_JASON_JAR", str(jar))
    assert shown() == ["[main] in_jar", "[main] more_in_jar"]
    assert path_include_resolver([])("$jasonJar/asl/more.asl", "")[2] == f"jar:file:{jar}!/asl/more.asl"
    monkeypatch.setenv("RASON_JASON_JAR", str(tmp_path / "jason-tree"))
    assert shown() == ["[main] in_tree", "[main] more_in_tree"]
    # what neither has is still looked up by its file name
    with zipfile.ZipFile(jar, "w") as z:
        z.writestr("other.asl", "a.\n")
    monkeypatch.setenv("RASON_JASON_JAR", str(jar))
    assert shown() == ["[main] beside"]


def test_a_jason_jar_source_path_is_a_folder_of_the_named_jason_tree(
        tmp_path: Path, monkeypatch) -> None:
    inc = tmp_path / "tree" / "jason-interpreter" / "src" / "test" / "jason" / "inc"
    inc.mkdir(parents=True)
    (inc / "lib.asl").write_text("+!l <- .print(from_tree).\n")
    (tmp_path / "a.asl").write_text('{ include("lib.asl") }\n!l.\n')
    mas = tmp_path / "m.mas2j"
    mas.write_text('MAS m { agents: a; aslSourcePath: "$jasonJar/test/jason/inc"; }\n')
    monkeypatch.setenv("RASON_JASON_JAR", str(tmp_path / "tree"))
    assert load_mas2j(str(mas)).source_path == [str(inc)]
    assert _run(mas) == ["[a] from_tree"]
    monkeypatch.delenv("RASON_JASON_JAR")
    assert load_mas2j(str(mas)).source_path == []
