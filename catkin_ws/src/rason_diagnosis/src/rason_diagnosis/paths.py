"""Where the case study's files are: found through the ROS package path, never the source tree.

In a devel space ``rospack find rason_diagnosis`` is the package's source folder; in an install
space it is ``share/rason_diagnosis``, where CMakeLists.txt installs ``agents/`` and ``worlds/``.
"""

from __future__ import annotations

from pathlib import Path

import rospkg

PACKAGE = "rason_diagnosis"


def package_dir() -> Path:
    """The package's folder as the ROS package path resolves it."""
    return Path(rospkg.RosPack().get_path(PACKAGE))


def agent_file(robot: str) -> Path:
    """The case study's agent program for ``robot`` (``faulty`` or ``helper``)."""
    return package_dir() / "agents" / f"{robot}.asl"


def world_file(name: str = "case_study") -> Path:
    """A world file shipped with the case study (``worlds/NAME.yaml``)."""
    return package_dir() / "worlds" / f"{name}.yaml"
