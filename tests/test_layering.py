"""The map of docs/conventions.md ("Where things live") held to the code: each package
imports only those it may, and no module imports itself round a circle. Read from the
source (every import statement, those inside functions too), so an import moved into a
function to hide a circle still counts."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
LEAVES = {"camera_model", "zenoh_rpc"}
BELOW_EXECUTIVE = {"behaviours", "learner", "planner", "hero_driver", "robot_profile", "mapping", *LEAVES}
MAY_IMPORT: dict[str, set[str]] = {
    "camera_model": set(),
    "zenoh_rpc": set(),
    "robot_profile": {"learner"},  # the learner's own types, built from the file (learner.knowledge alone)
    "learner": {"zenoh_rpc"},  # its service's transport only; the core imports nothing of ours
    "planner": {"camera_model", "robot_profile"},
    "hero_driver": {"camera_model", "robot_profile", "zenoh_rpc", "planner"},  # planner: the camera check's vision
    "mapping": {"camera_model", "planner"},  # planner: the map it plans on (VisionMap) and its Pose
    "behaviours": {"camera_model", "hero_driver", "learner", "planner", "robot_profile"},
    "executive": BELOW_EXECUTIVE,
    "reporting": {"executive", *BELOW_EXECUTIVE},
    "recording": {"executive", *BELOW_EXECUTIVE},
    "experiments": {"executive", "reporting", *BELOW_EXECUTIVE},
    "csl_testing": {"executive", *BELOW_EXECUTIVE},
    "csl_cli": {"executive", "experiments", "reporting", "recording", *BELOW_EXECUTIVE},
}


def _modules() -> dict[str, Path]:
    found = {}
    for package in MAY_IMPORT:
        for path in (ROOT / package).rglob("*.py"):
            parts = list(path.relative_to(ROOT).with_suffix("").parts)
            found[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return found


MODULES = _modules()


def _imports(module: str, path: Path) -> Iterator[str]:
    """The modules of ours ``module`` imports (a ``from package import module`` names
    the module, not the package)."""
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            named = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = ".".join(package[:len(package) - node.level + 1] + [node.module or ""]) if node.level else node.module
            base = (base or "").strip(".")
            named = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in MODULES else base for alias in node.names]
        else:
            continue
        for name in named:
            while name and name not in MODULES:
                name = name.rpartition(".")[0]
            if name and name != module:
                yield name


GRAPH = {module: set(_imports(module, path)) for module, path in MODULES.items()}


def test_the_map_covers_every_package() -> None:
    packages = {p.parent.name for p in ROOT.glob("*/__init__.py")} - {"tests"}
    assert packages == set(MAY_IMPORT)


@pytest.mark.parametrize("package", sorted(MAY_IMPORT))
def test_a_package_imports_only_what_the_map_allows(package: str) -> None:
    wrong = sorted(f"{m} imports {i}" for m, imported in GRAPH.items() if m.split(".")[0] == package
                   for i in imported if i.split(".")[0] not in MAY_IMPORT[package] | {package})
    assert wrong == []


def test_robot_profile_takes_only_the_learners_types() -> None:
    taken = {i for m, imported in GRAPH.items() if m.startswith("robot_profile") for i in imported
             if i.startswith("learner")}
    assert taken <= {"learner.knowledge"}


def test_no_module_imports_itself_round_a_circle() -> None:
    """Tarjan's strongly connected components: every one a single module."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    circles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in GRAPH[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                circles.append(sorted(component))

    for module in sorted(GRAPH):
        if module not in index:
            visit(module)
    assert circles == []


def test_a_circle_is_found() -> None:
    """The checker itself: two modules importing each other are one component."""
    saved = dict(GRAPH)
    try:
        GRAPH.update({"executive.exit_status": {"executive.episode_log"},
                      "executive.episode_log": {"executive.exit_status"}})
        with pytest.raises(AssertionError):
            test_no_module_imports_itself_round_a_circle()
    finally:
        GRAPH.clear()
        GRAPH.update(saved)
