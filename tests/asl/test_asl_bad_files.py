"""Source files that are not UTF-8 give a ``file:`` error and exit status 2, not a traceback."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from asl_helpers import subprocess_env

from rason.asl import AslSyntaxError, load_agent_source


def _run(path: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "rason.asl", "run", str(path), "--timeout", "10"],
                          capture_output=True, text=True, env=subprocess_env(), timeout=60)


def test_non_utf8_asl_is_a_file_line_col_error_with_status_2(tmp_path: Path) -> None:
    path = tmp_path / "latin1.asl"
    path.write_bytes('!g.\n+!g <- .print("caf\u00e9").\n'.encode("latin-1"))
    proc = _run(path)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"{path}:2:19: not UTF-8 text (byte 0xe9)")
    assert "Traceback" not in proc.stderr


def test_load_agent_source_names_the_first_bad_byte(tmp_path: Path) -> None:
    path = tmp_path / "bad.asl"
    path.write_bytes(b"a.\nb.\n  c(\xff).\n")
    try:
        load_agent_source(path)
    except AslSyntaxError as e:
        assert (e.file, e.line, e.col) == (str(path), 3, 5)
    else:
        raise AssertionError("no error for a non-UTF-8 file")
    good = tmp_path / "good.asl"
    good.write_text("greeting(\"\u00e9t\u00e9 \u2603\").\n", encoding="utf-8")
    assert "\u2603" in load_agent_source(good)


def test_non_utf8_project_file_has_status_2(tmp_path: Path) -> None:
    path = tmp_path / "bad.mas2j"
    path.write_bytes(b"MAS x {\n  agents: a;\n}\n// \xff\n")
    proc = _run(path)
    assert proc.returncode == 2
    assert proc.stderr.startswith(f"{path}: not UTF-8 text")
    assert "Traceback" not in proc.stderr
