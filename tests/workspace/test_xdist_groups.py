"""The end-to-end group that ``./run.sh test`` keeps on one xdist worker
(tests/conftest.py)."""

from __future__ import annotations

import re
from pathlib import Path

from conftest import E2E_MARKERS, E2E_NODEIDS, is_end_to_end

ROOT = Path(__file__).resolve().parents[2]


def test_every_end_to_end_module_marks_itself_in_its_pytestmark_line():
    # the group is chosen by node id (xdist's controller sees no markers): a test marked `demo`
    # or `hosts` on its own, not by its module's pytestmark, would run beside the others
    names = "|".join(sorted(E2E_MARKERS))
    marked = [path for path in (ROOT / "tests").rglob("test_*.py")
              if re.search(rf"pytest\.mark\.({names})\b", path.read_text(encoding="utf-8"))]
    assert len(marked) >= 5
    assert [str(path.relative_to(ROOT)) for path in marked
            if not is_end_to_end(f"{path.relative_to(ROOT).as_posix()}::test_x", ROOT)] == []


def test_the_group_names_only_tests_that_exist():
    missing = []
    for prefix in E2E_NODEIDS:
        path, _, name = prefix.partition("::")
        if not (ROOT / path).is_file() or (name and f"def {name}(" not in (ROOT / path).read_text()):
            missing.append(prefix)
    assert missing == []


def test_the_group_leaves_the_light_tests_out():
    assert is_end_to_end("tests/demo/test_demo.py::test_demo_diagnoses_the_injected_fault[none]", ROOT)
    assert is_end_to_end("tests/workspace/test_install_space.py::test_demo_runs_from_the_install_space",
                     ROOT)
    assert not is_end_to_end("tests/asl/test_asl_native.py::test_the_compiled_modules_are_in_use", ROOT)
    assert not is_end_to_end("tests/demo/test_outcome.py::test_x", ROOT)
    assert not is_end_to_end("tests/workspace/test_xdist_groups.py::test_x", ROOT)
