"""setup.sh is never silent during a long build step: its ``progress`` function (taken from
setup.sh itself) prints the time so far and the build log's last line while the job runs."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

SETUP = Path(__file__).resolve().parents[2] / "setup.sh"


def _setup_part(pattern: str, what: str) -> str:
    """The first part of setup.sh that ``pattern`` (multiline, dot-all) matches."""
    match = re.search(pattern, SETUP.read_text(encoding="utf-8"), flags=re.M | re.S)
    assert match, f"setup.sh has no {what}"
    return match.group(0)


def _progress_function() -> str:
    return "\n".join(_setup_part(rf"^{name}\(\) \{{\n.*?^\}}\n", f"{name}() function")
                     for name in ("progress", "shown"))


def _run(job: str, log: Path, then: str = "") -> subprocess.CompletedProcess:
    script = (f"{_progress_function()}\n{_setup_part(r'^PIP_NOTES=.*?$', 'PIP_NOTES')}\n"
              f"({job}) > {log} 2>&1 &\nprogress {log} $! {then}\n")
    return subprocess.run(["bash", "-c", script], capture_output=True, text=True, timeout=60,
                          env={"PROGRESS_PERIOD": "1", "PATH": "/usr/bin:/bin"})


def test_progress_shows_elapsed_time_and_the_log_s_last_line(tmp_path):
    # 2.4 s: long enough for two lines of a 1 s period whatever the start's fraction of a second
    job = "for k in 1 2 3 4; do echo \"[ ${k}0%] Built target part$k\"; sleep 0.6; done"
    done = _run(job, tmp_path / "build.log")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert any(re.fullmatch(r" +\d+ s  \[ \d0%\] Built target part\d", line) for line in lines), lines
    assert len(lines) >= 3                       # several lines while it ran
    assert re.fullmatch(r" +\d+ s  done", lines[-1])


def test_progress_returns_the_job_s_failure(tmp_path):
    done = _run("echo compiling; sleep 0.3; exit 3", tmp_path / "build.log")
    assert done.returncode == 3
    assert done.stdout.splitlines()[-1].endswith("failed (3)")


#: what pip prints on this kind of machine (an extra index in pip.conf, one of its folders
#: missing), its real progress, then an error
PIP_LINES = [
    "Looking in indexes: https://pypi.org/simple, file:///opt/pypi/simple",
    "Looking in links: /opt/wheels",
    "Collecting lark==1.3.1",
    "WARNING: Location 'file:///opt/pypi-more/simple/lark/' is ignored: it is neither a file "
    "nor a directory.",
    "ERROR: No matching distribution found for nothere==9",
]


def test_pip_s_notes_about_the_machine_are_not_shown_but_its_progress_and_errors_are(tmp_path):
    job = "; ".join(f"echo \"{line}\"; sleep 0.5" for line in PIP_LINES) + "; exit 1"
    log = tmp_path / "pip.log"
    # as setup.sh calls it: the notes skipped in the progress and in the tail shown on failure
    done = _run(job, log, then='"$PIP_NOTES" || { shown ' + str(log) +
                ' "$PIP_NOTES" | tail -40 >&2; exit 7; }')
    assert done.returncode == 7
    shown = done.stdout + done.stderr
    assert "Looking in" not in shown and "is ignored" not in shown, shown
    assert "Collecting lark==1.3.1" in done.stdout
    assert done.stderr.splitlines() == ["Collecting lark==1.3.1",
                                        "ERROR: No matching distribution found for nothere==9"]
    assert done.stdout.splitlines()[-1].endswith("failed (1)")
    assert "WARNING: Location" in log.read_text()        # the log keeps every line


def _background_commands() -> list[tuple[str, str]]:
    """Each command setup.sh runs in the background (its lines joined), with the line after it."""
    lines = SETUP.read_text(encoding="utf-8").splitlines()
    found, command = [], ""
    for index, line in enumerate(lines):
        if line.lstrip().startswith("#"):
            continue
        command += line.rstrip("\\").strip() + " "
        if line.endswith("\\"):
            continue
        if command.rstrip().endswith("&"):
            found.append((command, lines[index + 1].strip() if index + 1 < len(lines) else ""))
        command = ""
    return found


def test_every_long_step_runs_under_progress():
    background = _background_commands()
    for step in ("pip install", "catkin_make", "rason.asl native build", "compileall"):
        assert any(step in command for command, _ in background), f"{step} is not under progress"
    for command, after in background:
        assert after.startswith("progress "), f"nothing waits for: {command}"
