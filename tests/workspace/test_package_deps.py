"""Every catkin package declares in package.xml what its Python code imports.

A module of another ROS package, a workspace package or a Debian Python library must be named
as a ``depend``/``exec_depend`` (by its package or rosdep key); a library that only PyPI provides
must be pinned in requirements.txt. The standard library needs nothing.
"""

from __future__ import annotations

import ast
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
SRC = REPO / "catkin_ws" / "src"
PACKAGES = sorted(p.parent for p in SRC.glob("*/package.xml"))

#: Import names whose package.xml key differs from the import name.
ROSDEP_KEYS = {"numpy": "python3-numpy", "cv2": "python3-opencv", "yaml": "python3-yaml",
               "matplotlib": "python3-matplotlib", "lark": "python3-lark"}
#: Import names of libraries installed from PyPI only (pinned in requirements.txt), by the
#: requirement's name.
PYPI_ONLY = {"pybullet": "pybullet", "rosbags": "rosbags", "lz4": "lz4", "aiohttp": "aiohttp",
             "selenium": "selenium", "hypothesis": "hypothesis", "mypyc": "mypy"}
#: Modules that come with a declared package (catkin_pkg comes with catkin, genmsg with genpy).
BUNDLED = {"catkin_pkg": "catkin", "setuptools": "catkin", "rosgraph_msgs": "rosgraph_msgs",
           "rosbag": "rosbag"}


def _declared(package: Path) -> set[str]:
    root = ET.parse(package / "package.xml").getroot()
    tags = ("depend", "exec_depend", "build_depend", "buildtool_depend", "build_export_depend")
    return {e.text.strip() for tag in tags for e in root.iter(tag) if e.text}


def _imports(package: Path) -> dict[str, str]:
    """Top-level module imported -> first place it is imported (file:line)."""
    found: dict[str, str] = {}
    files = [*package.glob("src/**/*.py"), *(p for p in package.glob("scripts/*") if p.is_file())]
    for path in files:
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            for name in names:
                found.setdefault(name.split(".")[0], f"{path.relative_to(REPO)}:{node.lineno}")
    return found


def _pinned() -> set[str]:
    text = (REPO / "requirements.txt").read_text()
    return {m.group(1).lower() for m in re.finditer(r"^([A-Za-z0-9_.-]+)==", text, re.M)}


@pytest.mark.parametrize("package", PACKAGES, ids=lambda p: p.name)
def test_package_xml_declares_every_import(package):
    declared = _declared(package) | {package.name}
    pinned = _pinned()
    missing = []
    for module, where in sorted(_imports(package).items()):
        if module in sys.stdlib_module_names or module == package.name:
            continue
        if module in PYPI_ONLY:
            if PYPI_ONLY[module].lower() not in pinned:
                missing.append(f"{module} ({where}): pin {PYPI_ONLY[module]} in requirements.txt")
            continue
        key = ROSDEP_KEYS.get(module) or BUNDLED.get(module) or module
        if key not in declared:
            missing.append(f"{module} ({where}): declare <exec_depend>{key}</exec_depend>")
    assert not missing, f"{package.name}/package.xml:\n  " + "\n  ".join(missing)
