"""The real headless Chromium the inspector's browser tests drive (Debian's ``chromium`` and
``chromium-driver``, through selenium), and a run's process read line by line.

Tests import it as ``from browser import ...`` (tests/ is on ``sys.path``).
"""

from __future__ import annotations

import queue
import re
import shutil
import signal
import subprocess
import threading
import time
from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np
from interrupts import sigint_as_in_a_terminal
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

CHROMIUM = shutil.which("chromium") or "/usr/bin/chromium"
CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"
CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                  "--no-first-run", "--disable-background-networking",
                  "--disable-component-update", "--disable-sync", "--window-size=1600,1250")
#: The demo's and the mission's line giving the inspector's address.
INSPECTOR_LINE = r"\[(?:demo|mission)\] mind inspector: (http://127\.0\.0\.1:\d+/)"
#: The demo's and the mission's line saying that ``--hold`` holds: the result is out.
HOLDING_LINE = r"\[(?:demo|mission)\] holding"


class RunProcess:
    """A run (``python -m rason_diagnosis ...``) with its stdout read line by line in a thread."""

    def __init__(self, cmd: Sequence[str]) -> None:
        self.lines: list[str] = []
        self._queue: queue.Queue[str | None] = queue.Queue()
        # Ctrl-C as from a terminal: a suite started in the background (`cmd &` without job
        # control) hands its children SIGINT ignored, and `end()` would then wait its timeout
        self.proc = subprocess.Popen(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                     text=True, preexec_fn=sigint_as_in_a_terminal)
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.proc.stdout is not None
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))
            self._queue.put(line)
        self._queue.put(None)

    def wait_for(self, pattern: str, timeout: float) -> re.Match[str]:
        regex = re.compile(pattern)
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                line = self._queue.get(timeout=0.5)
            except queue.Empty:
                continue
            if line is None:
                break
            match = regex.search(line)
            if match:
                return match
        raise AssertionError(f"the run did not print /{pattern}/; output:\n" +
                             "\n".join(self.lines[-40:]))

    def end(self, timeout: float) -> int:
        """End the run as a user does: Ctrl-C (SIGINT) if it still runs, which ends a ``--hold``
        (or, failing, the run); wait `timeout` seconds for it to stop, then SIGTERM, then SIGKILL.
        Its exit status."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.proc.terminate()
        try:
            return self.proc.wait(30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return self.proc.wait(30)


def chromium(profile: Path) -> webdriver.Chrome:
    """Headless Chromium with its own profile folder."""
    options = webdriver.ChromeOptions()
    options.binary_location = CHROMIUM
    for flag in CHROMIUM_FLAGS:
        options.add_argument(flag)
    options.add_argument(f"--user-data-dir={profile}")
    return webdriver.Chrome(options=options, service=Service(executable_path=CHROMEDRIVER))


def map_ink(driver: webdriver.Chrome) -> int:
    """How many pixels of the robot map are drawn."""
    return driver.execute_script("""
        const c = document.getElementById('map'), ctx = c.getContext('2d');
        const px = ctx.getImageData(0, 0, c.width, c.height).data;
        let ink = 0;
        for (let k = 3; k < px.length; k += 4) if (px[k] > 0) ink++;
        return ink;""")


def assert_not_blank(shot: Path) -> None:
    """The screenshot at `shot` is a page-sized picture with something on it."""
    image = cv2.imread(str(shot))
    assert image is not None and image.shape[0] >= 600 and image.shape[1] >= 1000
    colours = np.unique(image.reshape(-1, 3) // 8, axis=0)
    assert image.std() > 20 and len(colours) > 50, \
        f"blank screenshot? std {image.std():.1f}, {len(colours)} colours"
