"""The knowledge profile as the simulator needs it: procedure times, ranges, errors and
the robot's physical constants.

The simulator reads the same TOML file the learner reads so that a procedure costs the
same robot time in simulation as the learner was told it would; nothing here is
hard-coded.
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

DEFAULT_PROFILE = Path(__file__).resolve().parent.parent / "profiles" / "hero2000.toml"


@dataclass(frozen=True)
class FeatureSpec:
    """One feature a sensing procedure yields; ``error`` is its expected error."""

    name: str
    error: float
    unit: str
    binary: bool


@dataclass(frozen=True)
class SensingProcedure:
    name: str
    time_s: float
    range_in: tuple[float, float]
    features: tuple[FeatureSpec, ...]


@dataclass(frozen=True)
class GraspingProcedure:
    name: str
    time_s: float
    range_in: tuple[float, float]


@dataclass(frozen=True)
class RobotConstants:
    """The ``[robot]`` table: shared with the planner (docs/conventions.md)."""

    base_radius_in: float
    sensor_offset_in: float
    sensor_height_in: float
    speed_in_per_s: float
    turn_deg_per_s: float
    centring_s: float
    vision_s: float


@dataclass(frozen=True)
class Profile:
    robot: RobotConstants
    sensing: dict[str, SensingProcedure]
    grasping: dict[str, GraspingProcedure]


def _number(table: dict, key: str, where: str) -> float:
    value = table.get(key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"{where}: field '{key}' must be a number, got {value!r}")
    return float(value)


def _range(table: dict, where: str) -> tuple[float, float]:
    value = table.get("range_in")
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
            or value[0] > value[1]):
        raise ValueError(f"{where}: field 'range_in' must be [lo, hi] with lo <= hi, got {value!r}")
    return float(value[0]), float(value[1])


def load_profile(path: str | Path | None = None) -> Profile:
    """Read a knowledge profile; a missing or mistyped field raises ValueError naming it."""
    source = Path(path) if path is not None else DEFAULT_PROFILE
    try:
        data = tomllib.loads(source.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"{source}: cannot read profile: {exc}".replace("\n", " ")) from exc
    robot_table = data.get("robot")
    if not isinstance(robot_table, dict):
        raise ValueError(f"{source}: missing [robot] table")
    robot = RobotConstants(**{
        name: _number(robot_table, name, f"{source} [robot]")
        for name in RobotConstants.__dataclass_fields__
    })
    sensing: dict[str, SensingProcedure] = {}
    for i, entry in enumerate(data.get("sensing", [])):
        where = f"{source} sensing[{i}]"
        features = tuple(
            FeatureSpec(
                name=str(f.get("name")),
                error=_number(f, "error", f"{where} features[{j}]"),
                unit=str(f.get("unit", "")),
                binary=bool(f.get("binary", False)),
            )
            for j, f in enumerate(entry.get("features", []))
        )
        if not features:
            raise ValueError(f"{where}: field 'features' must list at least one feature")
        name = str(entry.get("name"))
        sensing[name] = SensingProcedure(name, _number(entry, "time_s", where), _range(entry, where), features)
    grasping: dict[str, GraspingProcedure] = {}
    for i, entry in enumerate(data.get("grasping", [])):
        where = f"{source} grasping[{i}]"
        name = str(entry.get("name"))
        grasping[name] = GraspingProcedure(name, _number(entry, "time_s", where), _range(entry, where))
    if not sensing or not grasping:
        raise ValueError(f"{source}: needs [[sensing]] and [[grasping]] entries")
    return Profile(robot, sensing, grasping)
