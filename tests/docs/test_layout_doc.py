"""docs/layout.md says where a change goes: its folder tables name every tracked top-level
folder and file, every catkin package, every subpackage of ``rason`` and every folder under
``docs/`` and ``tests/``; agents/README.md names every folder of ``agents/``."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
#: the files a newcomer reads first and needs no row for
SELF_EXPLAINED = {".gitignore", "README.md", "CHANGELOG.md"}


def _tracked() -> list[Path]:
    out = subprocess.run(["git", "ls-files"], cwd=REPO, capture_output=True, text=True,
                         check=True, timeout=60).stdout
    return [Path(line) for line in out.splitlines()]


def _folders_under(folder: str) -> set[str]:
    """The folders directly under ``folder`` that hold a tracked file."""
    depth = len(Path(folder).parts)
    return {path.parts[depth] for path in _tracked()
            if path.parts[:depth] == Path(folder).parts and len(path.parts) > depth + 1}


def _folder_table() -> str:
    text = (REPO / "docs" / "layout.md").read_text(encoding="utf-8")
    return text.split("## Folders", 1)[1].split("\n## ", 1)[0]


def _expected_names() -> list[str]:
    tracked = _tracked()
    top = {path.parts[0] + ("/" if len(path.parts) > 1 else "") for path in tracked}
    names = sorted(top - SELF_EXPLAINED)
    names += [f"catkin_ws/src/{package}" for package in sorted(_folders_under("catkin_ws/src"))]
    names += [f"rason.{sub}" for sub in sorted(_folders_under("catkin_ws/src/rason/src/rason"))]
    names += [f"docs/{sub}/" for sub in sorted(_folders_under("docs"))]
    names += [f"tests/{sub}/" for sub in sorted(_folders_under("tests"))]
    return names


@pytest.mark.parametrize("name", _expected_names())
def test_the_folder_table_names_it(name: str):
    # a top-level folder may be named through its own rows (`catkin_ws/src/...`, `docs/...`)
    quoted = f"`{name}" if name.endswith("/") and "/" not in name[:-1] else f"`{name}`"
    assert quoted in _folder_table(), f"docs/layout.md's folder table does not name {name}"


@pytest.mark.parametrize("folder", sorted(_folders_under("agents")))
def test_agents_readme_names_each_folder(folder: str):
    readme = (REPO / "agents" / "README.md").read_text(encoding="utf-8")
    assert f"`{folder}/`" in readme, f"agents/README.md does not name {folder}/"
