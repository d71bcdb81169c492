"""Where the case study's files are: found through the ROS package path, never an absolute path.

In an install space ``rospack find rason_diagnosis`` is ``share/rason_diagnosis``, where
CMakeLists.txt installs ``worlds/`` and the repository's top-level ``agents/``. In a devel space
it is the package's source folder, which holds ``worlds/``; the agents are then the
repository's ``agents/``, three levels above the package (``catkin_ws/src/rason_diagnosis``).
"""

from __future__ import annotations

from pathlib import Path

import rospkg
import yaml

PACKAGE = "rason_diagnosis"
#: The case study's agents, a folder of ``agents/``.
CASE_STUDY = "diagnosis"


def package_dir() -> Path:
    """The package's folder as the ROS package path resolves it."""
    return Path(rospkg.RosPack().get_path(PACKAGE))


def agents_dir() -> Path:
    """The agents users run (``agents/`` of the repository, installed with the package)."""
    package = package_dir()
    installed = package / "agents"
    return installed if installed.is_dir() else package.parents[2] / "agents"


def agent_file(robot: str) -> Path:
    """The case study's agent program for ``robot`` (``faulty`` or ``helper``)."""
    return agents_dir() / CASE_STUDY / f"{robot}.asl"


def world_file(name: str = "case_study") -> Path:
    """A world file shipped with the case study (``worlds/NAME.yaml``)."""
    return package_dir() / "worlds" / f"{name}.yaml"


def world_colours(world: Path) -> Path | None:
    """The cylinders' colours file a world names (``vision: {colours: FILE}``, relative to the
    world file's folder; rosrun rason_vision calibrate writes it), or None for the detector's
    default ranges."""
    data = yaml.safe_load(Path(world).read_text()) or {}
    vision = data.get("vision") if isinstance(data, dict) else None
    name = vision.get("colours") if isinstance(vision, dict) else None
    return None if not name else (Path(world).parent / str(name)).resolve()
