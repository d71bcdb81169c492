"""docs/faults.md: every test a row names exists, so each row stays backed by a test."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PAGE = REPO / "docs" / "faults.md"
TESTS = REPO / "tests"


def _rows() -> list[str]:
    return [line for line in PAGE.read_text().splitlines()
            if line.startswith("| ") and not line.startswith(("| fault ", "|---"))]


def _references(cell: str) -> list[tuple[str, str | None]]:
    """(file, test or None) of each `file.py::test` / `::test` / `file.py` in a test cell; a bare
    `::test` belongs to the file named before it."""
    refs, current = [], None
    for ref in re.findall(r"`([^`]+)`", cell):
        path, _, name = ref.partition("::")
        if path:
            current = path
        if current and current.endswith(".py"):
            refs.append((current, name or None))
    return refs


def _find(path: str) -> Path:
    matches = [p for p in TESTS.rglob(Path(path).name) if p.as_posix().endswith(path)]
    assert len(matches) == 1, f"docs/faults.md names {path}: found {matches}"
    return matches[0]


@pytest.mark.parametrize("row", _rows(), ids=lambda row: row.split("|")[1].strip()[:50])
def test_each_row_names_tests_that_exist(row: str):
    cell = row.rstrip().rstrip("|").rsplit("|", 1)[-1]
    refs = _references(cell)
    assert refs, f"a row without a test: {row[:120]}"
    for path, name in refs:
        source = _find(path).read_text()
        if name:
            assert re.search(rf"^def {re.escape(name)}\(", source, re.M), f"{path}::{name}"
