"""The mind inspector in a real browser, during a real demo run.

``./run.sh demo`` (both actuators faulty) starts the inspector on a free port and prints its
address; headless Chromium (Debian's ``chromium`` and ``chromium-driver``, driven by selenium)
opens the page once and never reloads it. The page must list both agents, follow Faulty live
until its ``diagnosis(D)`` belief appears, step back through the history (to a state mid-run,
with an intention's current step marked), and show the robots; the screenshot (saved in the
test's tmp folder) must not be blank. The run is a short one, so it is started with ``--hold``:
its nodes, the inspector among them, stay up after the result until the test sends Ctrl-C, and
the history can be browsed however late the browser comes.
"""

from __future__ import annotations

import os
import sys

import pytest
from browser import (
    CHROMEDRIVER,
    CHROMIUM,
    HOLDING_LINE,
    INSPECTOR_LINE,
    RunProcess,
    assert_not_blank,
    chromium,
    map_ink,
)
from selenium import webdriver
from selenium.common.exceptions import WebDriverException
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

pytestmark = [pytest.mark.ros, pytest.mark.demo]


# The page redraws its lists as pushed events arrive: read them in one script, not element by
# element (an element found a moment ago may be gone already).

def _history(driver: webdriver.Chrome) -> tuple[str, int | None]:
    mode, index = driver.execute_script(
        "const l = document.getElementById('history-label');"
        "return [l.dataset.mode || '', l.dataset.index || ''];")
    return mode, int(index) if index else None


def _step_into_history(driver: webdriver.Chrome, wait: WebDriverWait) -> int:
    """Leave live view with one click on back; the index of the state now held."""
    driver.find_element(By.ID, "history-back").click()
    wait.until(lambda d: _history(d)[0] == "history")
    return _history(driver)[1]


def _beliefs(driver: webdriver.Chrome) -> list[str]:
    return driver.execute_script(
        "return [...document.querySelectorAll('#beliefs li.belief')].map(b => b.dataset.belief);")


def _agents(driver: webdriver.Chrome) -> set[str]:
    return set(driver.execute_script(
        "return [...document.querySelectorAll('#agent-list li')].map(li => li.dataset.agent);"))


def _current_steps(driver: webdriver.Chrome) -> int:
    return driver.execute_script(
        "return document.querySelectorAll('#intentions .means li.current').length;")


def _diagnosis(driver: webdriver.Chrome) -> str | None:
    return next((b for b in _beliefs(driver) if b.startswith("diagnosis(")), None)


def test_page_follows_a_demo_live_and_steps_back(tmp_path):
    assert os.path.exists(CHROMEDRIVER) and os.path.exists(CHROMIUM), \
        "Debian's chromium and chromium-driver are needed: ./setup.sh installs them"
    demo = RunProcess([sys.executable, "-m", "rason_diagnosis", "--fault", "both_actuators",
                       "--seed", "11", "--inspector-port", "0", "--quiet", "--hold",
                       "--out", str(tmp_path / "run")])
    driver = None
    try:
        url = demo.wait_for(INSPECTOR_LINE, 120).group(1)
        driver = chromium(tmp_path / "chromium-profile")
        driver.get(url)
        driver.execute_script("window.loadedOnce = 'yes';")   # gone if the page ever reloads
        wait = WebDriverWait(driver, 90, poll_frequency=0.2)

        # both agents, found through presence
        wait.until(lambda d: _agents(d) >= {"faulty", "helper"})
        # until the selected agent's own state is on screen the bar names none, so the wait
        # below cannot pass on the state shown before (a click on back would then do nothing)
        named = driver.execute_script(
            "document.querySelector('#agent-list li[data-agent=\"faulty\"]').click();"
            "return document.getElementById('history-label').dataset.index;")
        assert named == "", f"the history bar still names state {named} after the click"
        wait.until(lambda d: d.find_element(By.ID, "mind-title").text.startswith("faulty")
                   and _history(d)[0] == "live" and (_history(d)[1] or 0) >= 3)

        # the history steps back (while the run goes on, or after it), and back to live (the
        # live state may move on between reading it and the click, so the step is checked once
        # held)
        held = _step_into_history(driver, wait)
        driver.find_element(By.ID, "history-back").click()
        wait.until(lambda d: _history(d) == ("history", held - 1))
        driver.find_element(By.ID, "history-live").click()
        wait.until(lambda d: _history(d)[0] == "live" and _history(d)[1] > held)

        # Faulty's diagnosis appears without a reload; intentions and the robots are on the page
        WebDriverWait(driver, 150, poll_frequency=0.2).until(_diagnosis)
        assert _diagnosis(driver) == "diagnosis(both_actuators)"
        assert driver.execute_script("return window.loadedOnce;") == "yes"
        shot = tmp_path / "inspector.png"
        driver.save_screenshot(str(shot))
        robots = driver.find_element(By.ID, "robots").text
        assert "faulty: fault_injector: fault injected: both_actuators" in robots, robots
        assert "helper sees faulty" in robots or "no perception" not in robots, robots
        drawn = map_ink(driver)
        assert drawn > 2000, f"the map is (almost) empty: {drawn} drawn pixels"

        # step back from the diagnosis until the state before it (the page's history), then on
        # to a state mid-run: Faulty's intentions as stacks of plan instances, the current step
        # marked
        final_index = _history(driver)[1]
        _step_into_history(driver, wait)
        for _ in range(80):
            if _diagnosis(driver) is None and _current_steps(driver):
                break
            before = _history(driver)[1]
            driver.find_element(By.ID, "history-back").click()
            wait.until(lambda d, before=before: _history(d)[1] is not None
                       and _history(d)[1] < before)
        assert _history(driver)[0] == "history"
        assert _history(driver)[1] < final_index
        assert _diagnosis(driver) is None, "stepping back never reached a state before it"
        assert _current_steps(driver), "no state before the diagnosis shows a current step"
        driver.save_screenshot(str(tmp_path / "inspector-running.png"))

        assert_not_blank(shot)
        demo.wait_for(HOLDING_LINE, 120)
    except WebDriverException as err:
        pytest.fail(f"browser failed: {err.msg}\ndemo output:\n" + "\n".join(demo.lines[-30:]))
    finally:
        if driver is not None:
            driver.quit()
        status = demo.end(240)          # Ctrl-C: ends the hold (or, failing, the run)
    assert status == 0, "\n".join(demo.lines[-40:])
    assert "CORRECT" in "\n".join(demo.lines)
