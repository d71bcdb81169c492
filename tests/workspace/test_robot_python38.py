"""The robot side runs on the robots' Noetic: Python 3.8, numpy 1.17, OpenCV 4.2 (#35 item 5).

What runs on a TurtleBot's laptop (docs/real-robot.md): the fault injector, the motion
decomposer, rason_vision's synthesizer and detector, kobuki_msgs, and every module of this
workspace they import (followed here through their imports: the robot side's import closure).
The workstation keeps Python 3.11 (the agents, rason.asl); the robot side must not import it.

Checked statically on every machine: Python 3.8 syntax (``ast.parse(feature_version=(3, 8))``),
3.9+ annotation forms only under ``from __future__ import annotations``, vermin (pinned in
requirements.txt) finding nothing newer than 3.8, third-party imports limited to what Noetic
ships, and the numpy / OpenCV names called checked one by one against numpy 1.17 and OpenCV
4.2 (``NOETIC_NUMPY`` / ``NOETIC_OPENCV``: a name not listed fails until someone checks it).

Dynamically, the robot side's unit tests run under ``/usr/bin/python3.8`` where the machine has
one (a Noetic machine, with its python3-pytest). Debian 12 ships no Python 3.8 and none can be
had from the package registries this project reaches (PyPI, Debian, npm: npm's portable Python
downloads its binary from elsewhere at install time), so there that test is SKIPPED, reported
as not run: it never counts as passed here.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SRC = ROOT / "catkin_ws" / "src"
#: What a robot's laptop runs (rosrun), and the robot-side modules no script names.
ROBOT_SCRIPTS = [SRC / "rason" / "scripts" / "motion_decomposer",
                 SRC / "kobuki_fault_injector" / "scripts" / "fault_injector",
                 SRC / "rason_vision" / "scripts" / "robot_synthesizer"]
ROBOT_MODULES = ["rason_vision.detector"]
#: The robot side's unit tests (no ROS master needed): run under Python 3.8 where there is one.
ROBOT_UNIT_TESTS = [ROOT / "tests" / "robot" / name for name in (
    "test_motion_checks.py", "test_base_safety.py", "test_faults.py", "test_angles.py")] + [
    ROOT / "tests" / "vision" / "test_heading_history.py"]
#: The workstation's: the robot side must not import them.
WORKSTATION_ONLY = ("rason.asl", "rason.inspector", "rason_diagnosis", "turtlebot_sim")
#: Third-party modules a Noetic robot has (ROS' Python packages, python3-numpy, -opencv, -yaml)
#: besides the standard library and message and service packages (``*_msgs``, ``*_srvs``: Noetic's
#: ros_base has std_srvs).
NOETIC_THIRD_PARTY = {"rospy", "rosgraph", "genpy", "message_filters", "numpy", "cv2", "yaml"}
PYTHON38 = Path("/usr/bin/python3.8")

#: numpy names the robot side uses, each checked in numpy 1.17's reference (all older than
#: 1.17 unless noted); with the keywords passed to them.
NOETIC_NUMPY: dict[str, set[str]] = {
    "abs": set(), "argmin": set(), "argsort": set(), "array": set(), "array_equal": set(),
    "ascontiguousarray": {"dtype"}, "empty": {"dtype"},
    "float32": set(), "frombuffer": {"dtype"}, "isfinite": set(), "median": {"axis"},
    "nan": set(), "ndarray": set(), "nonzero": set(), "stack": {"axis"}, "uint32": set(),
    "uint8": set(), "lib": set(), "lib.stride_tricks": set(),
    "lib.stride_tricks.as_strided": {"shape", "strides", "writeable"},  # writeable: 1.12
    "arange": {"dtype"}, "argmax": set(), "asarray": {"dtype"}, "bincount": {"minlength"},
    "ceil": set(), "clip": set(), "dtype": set(), "errstate": {"invalid", "divide"},
    "float64": set(), "floor": set(), "int32": set(), "percentile": set(), "roll": set(),
    "round": set(), "uint16": set(), "zeros": {"dtype"},
    "nan_to_num": {"nan", "posinf"},            # these keywords are new in 1.17 itself
}
#: OpenCV names the robot side uses, each checked in OpenCV 4.2's Python bindings.
NOETIC_OPENCV: dict[str, set[str]] = {
    "CC_STAT_AREA": set(), "COLOR_BGR2HSV": set(), "COLOR_RGB2HSV": set(), "CV_32S": set(),
    "MORPH_CLOSE": set(), "MORPH_ELLIPSE": set(), "MORPH_OPEN": set(), "bitwise_or": set(),
    "boundingRect": set(), "connectedComponents": {"connectivity"},
    "connectedComponentsWithStats": {"connectivity", "ltype"}, "cvtColor": set(),
    "getStructuringElement": set(), "inRange": set(), "morphologyEx": set(),
    "COLOR_BGR2RGB": set(), "COLOR_RGB2BGR": set(), "COLOR_BayerBG2RGB": set(),
    "COLOR_BayerGB2RGB": set(), "COLOR_BayerGR2RGB": set(), "COLOR_BayerRG2RGB": set(),
    "COLOR_YUV2RGB_UYVY": set(), "IMREAD_COLOR": set(), "IMREAD_UNCHANGED": set(),
    "IMWRITE_JPEG_QUALITY": set(), "IMWRITE_PNG_COMPRESSION": set(), "imdecode": set(),
    "imencode": set(),
}
NOETIC_APIS = {"numpy": NOETIC_NUMPY, "cv2": NOETIC_OPENCV}


@dataclass
class Closure:
    """The workspace modules the robot side imports (name -> file) and the other top-level
    modules it imports (name -> importing files)."""

    modules: dict[str, Path] = field(default_factory=dict)
    external: dict[str, set[str]] = field(default_factory=dict)

    @property
    def files(self) -> list[Path]:
        return [*ROBOT_SCRIPTS, *self.modules.values()]


def workspace_packages() -> dict[str, Path]:
    """Top-level Python package name -> its folder, for every package of the workspace."""
    return {init.parent.name: init.parent for init in SRC.glob("*/src/*/__init__.py")}


def module_file(name: str, packages: dict[str, Path]) -> Path | None:
    top, *rest = name.split(".")
    if top not in packages:
        return None
    path = packages[top].joinpath(*rest)
    if (path / "__init__.py").is_file():
        return path / "__init__.py"
    return path.with_suffix(".py") if path.with_suffix(".py").is_file() else None


def imported_names(tree: ast.AST, module: str, is_package: bool) -> Iterator[str]:
    """Every module name an import statement of `tree` may load (also inside functions)."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = module.split(".") if is_package else module.split(".")[:-1]
                base = ".".join(parts[:len(parts) - node.level + 1])
                name = f"{base}.{node.module}" if node.module else base
            else:
                name = node.module or ""
            yield name
            yield from (f"{name}.{alias.name}" for alias in node.names)


def robot_closure(scripts: list[Path] = ROBOT_SCRIPTS,
                  modules: list[str] = ROBOT_MODULES) -> Closure:
    """What `scripts` and `modules` import, followed through the workspace's modules."""
    packages = workspace_packages()
    closure = Closure()
    todo = [(name, "") for name in modules]
    for script in scripts:
        todo += [(name, str(script)) for name in
                 imported_names(ast.parse(script.read_text()), "__main__", False)]
    while todo:
        name, importer = todo.pop()
        if name in closure.modules:
            continue
        path = module_file(name, packages)
        if path is None:
            top = name.split(".")[0]
            if top not in packages:
                closure.external.setdefault(top, set()).add(importer)
            continue
        closure.modules[name] = path
        parts = name.split(".")
        todo += [(".".join(parts[:i]), str(path)) for i in range(1, len(parts))]
        todo += [(imported, str(path)) for imported in
                 imported_names(ast.parse(path.read_text()), name, path.name == "__init__.py")]
    return closure


@pytest.fixture(scope="module")
def closure() -> Closure:
    return robot_closure()


def rel(path: Path) -> str:
    return str(path.relative_to(ROOT))


def test_the_closure_is_the_robot_side_and_pulls_no_workstation_module(closure: Closure):
    # the resolver must find the robot side itself, or every check below passes vacuously
    for expected in ("rason.execution.motion", "rason.execution.safety", "rosnode_kit.params",
                     "kobuki_fault_injector.node", "rason_vision.synthesizer",
                     "rason_vision.detector", "turtlebot_model.geometry"):
        assert expected in closure.modules, expected
    pulled = [f"{name} ({rel(path)})" for name, path in closure.modules.items()
              if name.startswith(WORKSTATION_ONLY)]
    assert not pulled, f"the robot side imports workstation modules: {pulled}"


def test_the_fault_injector_and_the_simulator_import_no_rason():
    """Layers point one way: the functional layer (injector, simulator) builds on rosnode_kit,
    never on the agent bridge above it."""
    for script in (SRC / "kobuki_fault_injector" / "scripts" / "fault_injector",
                   SRC / "turtlebot_sim" / "scripts" / "sim"):
        closure = robot_closure([script], [])
        assert "rosnode_kit.params" in closure.modules, script   # the resolver followed it
        pulled = sorted(name for name in closure.modules if name.split(".")[0] == "rason")
        assert not pulled, f"{rel(script)} imports rason: {pulled}"


def test_third_party_imports_are_what_noetic_ships(closure: Closure):
    foreign = {name: sorted(rel(Path(f)) if f else "?" for f in importers)
               for name, importers in closure.external.items()
               if name not in sys.stdlib_module_names and name not in NOETIC_THIRD_PARTY
               and not name.endswith(("_msgs", "_srvs")) and name != "__future__"}
    assert not foreign, f"not on a Noetic robot: {foreign}"


def test_robot_side_and_its_unit_tests_parse_as_python_38(closure: Closure):
    bad = []
    for path in [*closure.files, *ROBOT_UNIT_TESTS]:
        try:
            ast.parse(path.read_text(), str(path), feature_version=(3, 8))
        except SyntaxError as err:
            bad.append(f"{rel(path)}:{err.lineno}: {err.msg}")
    assert not bad, "not Python 3.8:\n" + "\n".join(bad)


def newer_annotation(node: ast.expr) -> bool:
    """Whether an annotation uses ``X | Y`` or a builtin generic (``list[int]``): 3.9+/3.10+
    forms that Python 3.8 can only keep as text (postponed evaluation)."""
    for sub in ast.walk(node):
        if isinstance(sub, ast.BinOp) and isinstance(sub.op, ast.BitOr):
            return True
        if isinstance(sub, ast.Subscript):
            value = sub.value
            name = value.id if isinstance(value, ast.Name) else \
                value.attr if isinstance(value, ast.Attribute) else ""
            if name in {"list", "dict", "tuple", "set", "frozenset", "type", "deque",
                        "Callable", "Iterable", "Iterator", "Sequence", "Mapping"}:
                return True
    return False


def annotations(tree: ast.AST) -> Iterator[ast.expr]:
    for node in ast.walk(tree):
        if isinstance(node, ast.AnnAssign):
            yield node.annotation
        elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            args = node.args
            for arg in [*args.posonlyargs, *args.args, *args.kwonlyargs, args.vararg, args.kwarg]:
                if arg is not None and arg.annotation is not None:
                    yield arg.annotation
            if node.returns is not None:
                yield node.returns


def test_newer_annotation_forms_only_with_postponed_annotations(closure: Closure):
    missing = []
    for path in [*closure.files, *ROBOT_UNIT_TESTS]:
        tree = ast.parse(path.read_text())
        postponed = any(isinstance(n, ast.ImportFrom) and n.module == "__future__"
                        and any(a.name == "annotations" for a in n.names) for n in tree.body)
        if not postponed and any(map(newer_annotation, annotations(tree))):
            missing.append(rel(path))
    assert not missing, f"add 'from __future__ import annotations' to {missing}"


def test_vermin_finds_nothing_newer_than_python_38(closure: Closure):
    """vermin's rules: library functions, modules, keywords and syntax by Python version."""
    files = [str(p) for p in [*closure.files, *ROBOT_UNIT_TESTS]]
    run = subprocess.run([sys.executable, "-c", "import sys; from vermin.main import main; "
                          "sys.exit(main())", "--target=3.8-", "--violations", "--no-tips",
                          *files], capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
    assert f"Analyzing {len(files)} files" in run.stdout, run.stdout


def api_uses(path: Path) -> Iterator[tuple[str, str, set[str]]]:
    """``(library, dotted name, keywords)`` of every numpy / cv2 name `path` uses."""
    tree = ast.parse(path.read_text())
    alias = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            alias.update({a.asname or a.name: a.name for a in node.names
                          if a.name in NOETIC_APIS})
        elif isinstance(node, ast.ImportFrom) and node.module in NOETIC_APIS:
            for a in node.names:
                yield node.module, a.name, set()
    keywords: dict[int, set[str]] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            keywords[id(node.func)] = {k.arg for k in node.keywords if k.arg}
    for node in ast.walk(tree):
        chain: list[str] = []
        value: ast.expr = node
        while isinstance(value, ast.Attribute):
            chain.insert(0, value.attr)
            value = value.value
        if chain and isinstance(value, ast.Name) and value.id in alias:
            yield alias[value.id], ".".join(chain), keywords.get(id(node), set())


def test_numpy_and_opencv_names_exist_in_noetics_versions(closure: Closure):
    unchecked = sorted({f"{lib}.{name}({', '.join(sorted(kw - NOETIC_APIS[lib].get(name, set())))})"
                        f" in {rel(path)}"
                        for path in closure.files for lib, name, kw in api_uses(path)
                        if name not in NOETIC_APIS[lib] or kw - NOETIC_APIS[lib][name]})
    assert not unchecked, ("check these against numpy 1.17 / OpenCV 4.2, then list them in "
                           "NOETIC_NUMPY / NOETIC_OPENCV:\n" + "\n".join(unchecked))
    used = {(lib, name) for path in closure.files for lib, name, _ in api_uses(path)}
    assert ("cv2", "inRange") in used and ("numpy", "frombuffer") in used   # not vacuous


@pytest.mark.skipif(not PYTHON38.exists(), reason=f"NOT RUN: no {PYTHON38} on this machine "
                    "(Debian 12 has none, nor do the registries reached); the static checks "
                    "of this module stand in for it")
def test_robot_unit_tests_pass_under_python_38():
    paths = ":".join(str(p.parent) for p in workspace_packages().values())
    run = subprocess.run([str(PYTHON38), "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "--noconftest", "-o", "addopts=", "-c", "/dev/null",
                          *map(str, ROBOT_UNIT_TESTS)],
                         capture_output=True, text=True, timeout=600, cwd=ROOT,
                         env={"PATH": "/usr/bin:/bin", "PYTHONPATH": paths})
    assert run.returncode == 0, run.stdout[-4000:] + run.stderr[-2000:]
