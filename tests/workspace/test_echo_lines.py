"""Lines the harness relays from several processes at once (the demo's console: both agents and
the demo itself) stay whole on one stdout (they once spliced: ``print`` writes the text and the
newline separately). No ROS: plain processes through :class:`rason.process.harness.Process`."""

from __future__ import annotations

import re
import subprocess
import sys

LINES = 5000
NAMES = ("faulty", "helper", "sim")

RELAY = f"""
import sys, tempfile
from pathlib import Path
from rason.process.harness import Process, echo_line
folder = Path(tempfile.mkdtemp())
child = "for i in range({LINES}): print(str(i) + ' x' + ' y' * 20)"
procs = [Process(name, [sys.executable, "-c", child], {{}}, folder / (name + ".log"),
                 echo=name + " | ") for name in {NAMES!r}]
for i in range({LINES}):
    echo_line("[demo] " + str(i) + " x" + " y" * 20)
for proc in procs:
    proc.wait()
"""


def test_relayed_lines_of_processes_running_at_once_stay_whole():
    out = subprocess.run([sys.executable, "-c", RELAY], capture_output=True, text=True,
                         timeout=300, check=True).stdout.splitlines()
    whole = re.compile(r"^(faulty \| |helper \| |sim \| |\[demo\] )(\d+) x( y){20}$")
    broken = [line for line in out if not whole.match(line)]
    assert not broken, broken[:5]
    for prefix in ("faulty | ", "helper | ", "sim | ", "[demo] "):
        numbers = [int(line[len(prefix):].split()[0]) for line in out if line.startswith(prefix)]
        assert numbers == list(range(LINES)), prefix
