"""The robot's knowledge: sensing and grasping procedures, their costs, and moving.

This is the learner's only view of a robot, so another robot is a new knowledge file
(format: ``docs/knowledge-format.md``). Loading validates strictly: a knowledge file is
hand-edited, and a typo that silently changed a cost would silently change every tree.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path


@dataclass(frozen=True)
class FeatureSpec:
    """A feature a sensing procedure yields, with the noise the learner must tolerate."""

    name: str
    error: float  # expected error, in the feature's unit: values this close are one branch
    unit: str
    binary: bool  # 0/1 features (holes); their domain is {0, 1}
    span: tuple[float, float]  # the values the feature can take, for the "unknown" subset
    angular_of: str | None = None  # the linear feature whose angular size this is (training distances)

    def covered_by(self, ranges: list[tuple[float, float]]) -> bool:
        """True when the observed ranges, widened by the error, cover the feature's domain.

        When they do not, a value outside them is possible, so scoring adds an "unknown"
        subset (method.md §3, missing values).
        """
        if self.binary:
            return all(any(lo - self.error <= v <= hi + self.error for lo, hi in ranges) for v in (0.0, 1.0))
        reach = self.span[0]
        for lo, hi in sorted(ranges):
            if lo - self.error > reach:
                return False
            reach = max(reach, hi + self.error)
        return reach >= self.span[1]


@dataclass(frozen=True)
class SensingProcedure:
    """An arm motion with the wrist sonar; one application yields all its features."""

    name: str
    time_s: float
    range_in: tuple[float, float]
    features: tuple[FeatureSpec, ...]

    def applicable_at(self, distance_in: float) -> bool:
        return self.range_in[0] - 1e-9 <= distance_in <= self.range_in[1] + 1e-9


@dataclass(frozen=True)
class GraspingProcedure:
    """A grasp; tried as a binary feature its cost is time plus the side-effect penalty."""

    name: str
    time_s: float
    range_in: tuple[float, float]
    side_effect_penalty_s: float
    verifiable: bool  # the finger sensor can confirm success; else never tried as a feature

    @property
    def feature_cost_s(self) -> float:
        return self.time_s + self.side_effect_penalty_s


@dataclass(frozen=True)
class MoveModel:
    """The default move-cost model, used until a planner prices moves on a map."""

    seconds_per_inch: float
    seconds_per_degree: float
    overhead_s: float


@dataclass(frozen=True)
class Knowledge:
    """Everything the learner knows about the robot it serves."""

    sensing: tuple[SensingProcedure, ...]
    grasping: tuple[GraspingProcedure, ...]
    move: MoveModel
    source: str = "<knowledge>"

    def feature(self, name: str) -> FeatureSpec:
        return self._features[name][0]

    def procedure_for(self, feature: str) -> SensingProcedure:
        """The procedure that yields ``feature`` (each feature has exactly one)."""
        return self._features[feature][1]

    def grasp(self, name: str) -> GraspingProcedure:
        for g in self.grasping:
            if g.name == name:
                return g
        raise KeyError(f"{self.source}: unknown grasping procedure {name!r}")

    def has_feature(self, name: str) -> bool:
        return name in self._features

    def has_grasp(self, name: str) -> bool:
        return any(g.name == name for g in self.grasping)

    @cached_property
    def _features(self) -> dict[str, tuple[FeatureSpec, SensingProcedure]]:
        return {f.name: (f, p) for p in self.sensing for f in p.features}


def load_knowledge(path: str | Path) -> Knowledge:
    """Read and validate a knowledge TOML file; errors name the file, entry and problem."""
    path = Path(path)
    try:
        with path.open("rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise ValueError(f"{path}: knowledge file not found") from None
    except IsADirectoryError:
        raise ValueError(f"{path}: is a folder, not a knowledge file") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text (TOML) knowledge file") from None
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from None
    return knowledge_from_dict(data, str(path))


def knowledge_from_dict(data: Mapping[str, object], source: str = "<knowledge>") -> Knowledge:
    """Validate parsed TOML data into :class:`Knowledge`."""
    _only_keys(data, {"move", "robot", "sensing", "grasping"}, source)
    move = _move(_table(data, "move", source), f"{source}: [move]")
    _robot(data.get("robot", {}), f"{source}: [robot]")
    sensing = tuple(
        _sensing(entry, f"{source}: sensing[{i}]") for i, entry in enumerate(_array(data, "sensing", source))
    )
    grasping = tuple(
        _grasping(entry, f"{source}: grasping[{i}]") for i, entry in enumerate(_array(data, "grasping", source))
    )
    _unique([p.name for p in sensing] + [g.name for g in grasping], f"{source}: procedure")
    seen: dict[str, tuple[FeatureSpec, str]] = {}
    for proc in sensing:
        for feat in proc.features:
            if feat.name in seen:
                other, other_proc = seen[feat.name]
                if (other.error, other.binary, other.span) != (feat.error, feat.binary, feat.span):
                    raise ValueError(
                        f"{source}: feature {feat.name!r} is yielded by {other_proc!r} and {proc.name!r} "
                        f"with different errors ({other.error} vs {feat.error})"
                    )
                raise ValueError(
                    f"{source}: feature {feat.name!r} is yielded by both {other_proc!r} and {proc.name!r}; "
                    "a feature must come from one procedure"
                )
            seen[feat.name] = (feat, proc.name)
    for feat, proc_name in seen.values():
        if feat.angular_of is not None and (feat.angular_of not in seen or seen[feat.angular_of][0].binary):
            raise ValueError(f"{source}: feature {feat.name!r} of {proc_name!r}: 'angular_of' names "
                             f"{feat.angular_of!r}, which no procedure yields as a linear feature")
    if not sensing:
        raise ValueError(f"{source}: no [[sensing]] procedures")
    if not grasping:
        raise ValueError(f"{source}: no [[grasping]] procedures")
    return Knowledge(sensing=sensing, grasping=grasping, move=move, source=source)


def _move(table: Mapping[str, object], where: str) -> MoveModel:
    _only_keys(table, {"seconds_per_inch", "seconds_per_degree", "overhead_s"}, where)
    return MoveModel(
        seconds_per_inch=_cost(table, "seconds_per_inch", where),
        seconds_per_degree=_cost(table, "seconds_per_degree", where),
        overhead_s=_cost(table, "overhead_s", where),
    )


_ROBOT_KEYS = {
    "base_radius_in", "sensor_offset_in", "sensor_height_in", "speed_in_per_s", "turn_deg_per_s",
    "centring_s", "vision_s",
}


def _robot(table: object, where: str) -> None:
    """The ``[robot]`` table is for the planner and simulator; check it is well formed."""
    if not isinstance(table, Mapping):
        raise ValueError(f"{where}: must be a table")
    _only_keys(table, _ROBOT_KEYS, where)
    for key in table:
        _cost(table, key, where)
    for key in ("speed_in_per_s", "turn_deg_per_s"):  # moves are priced by dividing by them
        if key in table and table[key] == 0:
            raise ValueError(f"{where}: '{key}' must be greater than 0")


def _sensing(entry: object, where: str) -> SensingProcedure:
    entry = _as_table(entry, where)
    name = _name(entry, where)
    where = f"{where} ({name})"
    _only_keys(entry, {"name", "time_s", "range_in", "features"}, where)
    features_raw = entry.get("features")
    if not isinstance(features_raw, list) or not features_raw:
        raise ValueError(f"{where}: 'features' must be a non-empty array of tables")
    features = tuple(_feature(f, f"{where} features[{i}]") for i, f in enumerate(features_raw))
    _unique([f.name for f in features], f"{where}: feature")
    return SensingProcedure(name=name, time_s=_cost(entry, "time_s", where),
                            range_in=_range(entry, where), features=features)


def _feature(entry: object, where: str) -> FeatureSpec:
    entry = _as_table(entry, where)
    name = _name(entry, where)
    where = f"{where} ({name})"
    _only_keys(entry, {"name", "error", "unit", "span", "binary", "angular_of"}, where)
    binary = entry.get("binary", False)
    if not isinstance(binary, bool):
        raise ValueError(f"{where}: 'binary' must be true or false")
    unit = entry.get("unit")
    if not isinstance(unit, str) or not unit:
        raise ValueError(f"{where}: missing field 'unit'")
    error = _cost(entry, "error", where)
    if binary:
        if "span" in entry:
            raise ValueError(f"{where}: a binary feature takes no 'span' (its values are 0 and 1)")
        span = (0.0, 1.0)
    else:
        span = _pair(entry, "span", where)
    angular_of = entry.get("angular_of")
    if angular_of is not None and (not isinstance(angular_of, str) or binary):
        raise ValueError(f"{where}: 'angular_of' must name a linear feature (and not be set on a binary one)")
    return FeatureSpec(name=name, error=error, unit=unit, binary=binary, span=span, angular_of=angular_of)


def _grasping(entry: object, where: str) -> GraspingProcedure:
    entry = _as_table(entry, where)
    name = _name(entry, where)
    where = f"{where} ({name})"
    _only_keys(entry, {"name", "time_s", "range_in", "side_effect_penalty_s", "verifiable"}, where)
    verifiable = entry.get("verifiable", True)
    if not isinstance(verifiable, bool):
        raise ValueError(f"{where}: 'verifiable' must be true or false")
    return GraspingProcedure(
        name=name,
        time_s=_cost(entry, "time_s", where),
        range_in=_range(entry, where),
        side_effect_penalty_s=_cost(entry, "side_effect_penalty_s", where) if "side_effect_penalty_s" in entry else 0.0,
        verifiable=verifiable,
    )


def _table(data: Mapping[str, object], key: str, where: str) -> Mapping[str, object]:
    if key not in data:
        raise ValueError(f"{where}: missing table [{key}]")
    return _as_table(data[key], f"{where}: [{key}]")


def _array(data: Mapping[str, object], key: str, where: str) -> list[object]:
    value = data.get(key)
    if value is None:
        raise ValueError(f"{where}: missing [[{key}]] entries")
    if not isinstance(value, list):
        raise ValueError(f"{where}: '{key}' must be an array of tables")
    return value


def _as_table(value: object, where: str) -> Mapping[str, object]:
    if not isinstance(value, Mapping):
        raise ValueError(f"{where}: must be a table")
    return value


def _only_keys(table: Mapping[str, object], allowed: set[str], where: str) -> None:
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r} (allowed: {', '.join(sorted(allowed))})")


def _name(entry: Mapping[str, object], where: str) -> str:
    name = entry.get("name")
    if not isinstance(name, str) or not name.strip():
        raise ValueError(f"{where}: missing field 'name'")
    return name


def _cost(entry: Mapping[str, object], key: str, where: str) -> float:
    if key not in entry:
        raise ValueError(f"{where}: missing field '{key}'")
    value = entry[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{where}: '{key}' must be a number, got {value!r}")
    if value < 0:
        raise ValueError(f"{where}: '{key}' must not be negative, got {value}")
    return float(value)


def _pair(entry: Mapping[str, object], key: str, where: str) -> tuple[float, float]:
    if key not in entry:
        raise ValueError(f"{where}: missing field '{key}'")
    value = entry[key]
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in value)):
        raise ValueError(f"{where}: '{key}' must be [low, high], got {value!r}")
    lo, hi = float(value[0]), float(value[1])
    if lo > hi:
        raise ValueError(f"{where}: '{key}' is empty: low {lo} > high {hi}")
    return lo, hi


def _range(entry: Mapping[str, object], where: str) -> tuple[float, float]:
    lo, hi = _pair(entry, "range_in", where)
    if lo < 0:
        raise ValueError(f"{where}: 'range_in' must not be negative, got [{lo}, {hi}]")
    return lo, hi


def _unique(names: list[str], what: str) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ValueError(f"{what} {n!r} is defined twice")
        seen.add(n)
