"""The default KQML plans kept between runs in the user's cache folder: read back as parsed, made
anew when the file is not the one of this text and these modules."""

from __future__ import annotations

import glob
import os
import pickle
import re

import pytest

from rason.asl import kqml
from rason.asl.parser import parse_source


@pytest.fixture
def cache_folder(tmp_path, monkeypatch) -> str:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    return os.path.join(str(tmp_path), "rason")


def _texts(plans: list) -> list[str]:
    """The plans' text, anonymous variables (named afresh in each reading) as ``_``."""
    return [re.sub(r"\b_\d+\b", "_", str(p)) for p in plans]


def test_stored_plans_read_back_as_parsed(cache_folder: str) -> None:
    parsed = parse_source(kqml.KQML_PLANS, "kqmlPlans.asl", src=kqml.KQML_SRC).plans
    first = kqml._stored_plans()                         # parses and stores
    files = glob.glob(os.path.join(cache_folder, "kqml-*.pickle"))
    assert len(files) == 1
    second = kqml._stored_plans()                        # reads the file
    assert _texts(first) == _texts(second) == _texts(parsed)
    assert len(second) >= 20


def test_a_file_made_for_another_stamp_is_not_used(cache_folder: str) -> None:
    kqml._stored_plans()
    (path,) = glob.glob(os.path.join(cache_folder, "kqml-*.pickle"))
    with open(path, "rb") as f:
        stamp, plans = pickle.load(f)
    with open(path, "wb") as f:                          # same name, other stamp, one plan
        pickle.dump((stamp + "x", plans[:1]), f)
    assert len(kqml._stored_plans()) == len(plans)       # parsed again, and stored anew
    with open(path, "rb") as f:
        assert pickle.load(f)[0] == stamp


def test_an_unreadable_file_is_replaced(cache_folder: str) -> None:
    kqml._stored_plans()
    (path,) = glob.glob(os.path.join(cache_folder, "kqml-*.pickle"))
    with open(path, "wb") as f:
        f.write(b"not a pickle")
    assert len(kqml._stored_plans()) >= 20
    with open(path, "rb") as f:
        assert pickle.load(f)[0].startswith(kqml.KQML_PLANS)
