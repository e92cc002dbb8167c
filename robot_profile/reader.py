"""The one reader of a robot profile (format: docs/knowledge-format.md).

The learner, the planner and the simulator all take their part of the robot from
here, so a procedure costs the same robot time in simulation as the learner was told
and the planner inflates the map by the body the simulator drives. Validation is
strict: a profile is hand-edited, and a typo that silently changed a cost would
silently change every tree.

Two readings of one file: :func:`load_profile`, the whole robot, for whatever drives
the planner or the simulator, requires ``[robot]``; :func:`load_knowledge`, the
learner's part only, does not (the learner never reads it, and a file of procedures
alone, as the paper gives them, must be enough for ``csl tree`` and ``csl train``).
Whatever either reads is checked the same way.
"""

from __future__ import annotations

import dataclasses
import os
import stat
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import BinaryIO, TypeVar

from learner.knowledge import FeatureSpec, GraspingProcedure, Knowledge, MoveModel, SensingProcedure
from robot_profile import fields
from robot_profile.model import (SCANNER_DEFAULTS, SCANNER_MODELS, Robot, RobotGeometry, RobotMotion, RobotProfile,
                                 ScannerSpec)

DEFAULT_PROFILE = Path(__file__).resolve().parent.parent / "hero_driver" / "profiles" / "hero2000.toml"

_Part = TypeVar("_Part", RobotGeometry, RobotMotion)


def load_profile(path: str | Path = DEFAULT_PROFILE) -> RobotProfile:
    """Read and validate a profile file; errors name the file, entry and problem."""
    path = Path(path)
    return profile_from_dict(_read(path), str(path))


def load_knowledge(path: str | Path = DEFAULT_PROFILE) -> Knowledge:
    """Read and validate the learner's part of a knowledge file: ``[robot]`` may be
    absent (the learner never reads it); the rest is checked as :func:`load_profile`
    checks it."""
    path = Path(path)
    return knowledge_from_dict(_read(path), str(path))


def _read(path: Path) -> dict[str, object]:
    """The parsed TOML of a knowledge file; every failure is one line naming the file."""
    try:
        with _open_regular(path) as fh:
            return tomllib.load(fh)
    except FileNotFoundError:
        raise ValueError(f"{path}: knowledge file not found") from None
    except IsADirectoryError:
        raise ValueError(f"{path}: is a folder, not a knowledge file") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path}: not a text (TOML) knowledge file") from None
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path}: not valid TOML: {exc}") from None
    except OSError as exc:
        raise ValueError(f"{path}: cannot read knowledge file: {exc.strerror}") from None


def _shown(name: str) -> str:
    """An entry's name as an error shows it: as written, unless it holds a newline or
    another unprintable character, which would split the one-line error."""
    return name if name.isprintable() else repr(name)


def _open_regular(path: Path) -> BinaryIO:
    """``path`` opened for reading when it is a regular file. Opened without blocking
    and checked on the open descriptor: a FIFO would otherwise wait for a writer for
    ever, and /dev/zero would be read until memory runs out (the driver side may not
    import the learner's ``input_file``, so this small guard is kept here)."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    mode = os.fstat(fd).st_mode
    if stat.S_ISDIR(mode):
        os.close(fd)
        raise IsADirectoryError(path)
    if not stat.S_ISREG(mode):
        os.close(fd)
        raise ValueError(f"{path}: is a device or a pipe, not a knowledge file")
    return os.fdopen(fd, "rb")


def profile_from_dict(data: Mapping[str, object], source: str = "<profile>") -> RobotProfile:
    """Validate parsed TOML data into a :class:`RobotProfile` (``[robot]`` required)."""
    robot, knowledge, scanner = _parts(data, source, robot_required=True)
    assert robot is not None
    return RobotProfile(robot=robot, move=knowledge.move, sensing=knowledge.sensing, grasping=knowledge.grasping,
                        source=source, scanner=scanner)


def knowledge_from_dict(data: Mapping[str, object], source: str = "<knowledge>") -> Knowledge:
    """Validate parsed TOML data into the learner's :class:`Knowledge` (``[robot]``
    optional, and checked when present: a typo there is still a typo)."""
    return _parts(data, source, robot_required=False)[1]


def _parts(data: Mapping[str, object], source: str,
           robot_required: bool) -> tuple[Robot | None, Knowledge, ScannerSpec | None]:
    """The ``[robot]`` table (None when absent and not required), the learner's part and
    the optional ``[scanner]``, checked in the file's reading order so the first problem
    is the one reported (the learner ignores the scanner, but a typo there is still one)."""
    fields.only_keys(data, {"move", "robot", "sensing", "grasping", "scanner"}, source)
    move = _move(fields.table(data, "move", source), f"{source}: [move]")
    robot = (_robot(fields.table(data, "robot", source), f"{source}: [robot]")
             if robot_required or "robot" in data else None)
    sensing = tuple(
        _sensing(entry, f"{source}: sensing[{i}]") for i, entry in enumerate(fields.array(data, "sensing", source))
    )
    grasping = tuple(
        _grasping(entry, f"{source}: grasping[{i}]")
        for i, entry in enumerate(fields.array(data, "grasping", source))
    )
    fields.unique([p.name for p in sensing] + [g.name for g in grasping], f"{source}: procedure")
    _check_features(sensing, source)
    if not sensing:
        raise ValueError(f"{source}: no [[sensing]] procedures")
    if not grasping:
        raise ValueError(f"{source}: no [[grasping]] procedures")
    where = f"{source}: [scanner]"
    scanner = _scanner(fields.as_table(data["scanner"], where), where) if "scanner" in data else None
    return robot, Knowledge(sensing=sensing, grasping=grasping, move=move, source=source), scanner


def _check_features(sensing: tuple[SensingProcedure, ...], source: str) -> None:
    """Each feature comes from exactly one procedure, and ``angular_of`` names a linear one."""
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


def _move(table: Mapping[str, object], where: str) -> MoveModel:
    fields.only_keys(table, {"seconds_per_inch", "seconds_per_degree", "overhead_s"}, where)
    return MoveModel(
        seconds_per_inch=fields.cost(table, "seconds_per_inch", where),
        seconds_per_degree=fields.cost(table, "seconds_per_degree", where),
        overhead_s=fields.cost(table, "overhead_s", where),
    )


def _robot(table: Mapping[str, object], where: str) -> Robot:
    """Every field without a default is required: the planner and the simulator must
    agree on all of them. A field with a default (a constant added after the robots
    that predate it, docs/conventions.md) takes it when the key is absent.

    The keys are the two parts' dataclass fields, so a new constant needs no code here.
    """
    allowed = {f.name for part in (RobotGeometry, RobotMotion) for f in dataclasses.fields(part)}
    fields.only_keys(table, allowed, where)
    return Robot(geometry=_part(RobotGeometry, table, where), motion=_part(RobotMotion, table, where))


def _part(part: type[_Part], table: Mapping[str, object], where: str) -> _Part:
    """One ``[robot]`` part, each field checked as its metadata says (model.POSITIVE)."""
    values = {
        f.name: (fields.positive if f.metadata.get("positive") else fields.cost)(table, f.name, where)
        for f in dataclasses.fields(part) if f.name in table or f.default is dataclasses.MISSING
    }
    return part(**values)


def _scanner(table: Mapping[str, object], where: str) -> ScannerSpec:
    """The ``[scanner]`` table: its ``model`` and any of that model's values overridden."""
    fields.only_keys(table, {"model", *SCANNER_DEFAULTS["lidar"]}, where)
    model = table.get("model")
    if model not in SCANNER_MODELS:
        raise ValueError(f"{where}: 'model' must be one of {', '.join(SCANNER_MODELS)}, got {model!r}")
    values = dict(SCANNER_DEFAULTS[str(model)])
    if "beams" in table:
        beams = table["beams"]
        if isinstance(beams, bool) or not isinstance(beams, int) or not 1 <= beams <= 3600:
            raise ValueError(f"{where}: 'beams' must be a whole number from 1 to 3600, got {beams!r}")
        values["beams"] = beams
    if "range_in" in table:
        lo, hi = fields.pair(table, "range_in", where)
        if lo < 0 or lo == hi:
            raise ValueError(f"{where}: 'range_in' must be [low, high] with 0 <= low < high, got [{lo:g}, {hi:g}]")
        values["range_in"] = (lo, hi)
    for key, top in (("beam_deg", 179.0), ("specular_deg", 90.0), ("height_in", None), ("time_s", None)):
        if key in table:
            value = fields.cost(table, key, where)
            if top is not None and value > top:
                raise ValueError(f"{where}: '{key}' must be at most {top:g}, got {value:g}")
            values[key] = value
    if "through_glass" in table:
        values["through_glass"] = fields.flag(table, "through_glass", False, where)
    return ScannerSpec(model=str(model), **values)  # type: ignore[arg-type]


def _sensing(entry: object, where: str) -> SensingProcedure:
    entry = fields.as_table(entry, where)
    name = fields.name(entry, where)
    where = f"{where} ({_shown(name)})"
    fields.only_keys(entry, {"name", "time_s", "range_in", "features"}, where)
    features_raw = entry.get("features")
    if not isinstance(features_raw, list) or not features_raw:
        raise ValueError(f"{where}: 'features' must be a non-empty array of tables")
    features = tuple(_feature(f, f"{where} features[{i}]") for i, f in enumerate(features_raw))
    fields.unique([f.name for f in features], f"{where}: feature")
    return SensingProcedure(name=name, time_s=fields.cost(entry, "time_s", where),
                            range_in=_range(entry, where), features=features)


def _feature(entry: object, where: str) -> FeatureSpec:
    entry = fields.as_table(entry, where)
    name = fields.name(entry, where)
    where = f"{where} ({_shown(name)})"
    fields.only_keys(entry, {"name", "error", "unit", "span", "binary", "angular_of"}, where)
    binary = fields.flag(entry, "binary", False, where)
    unit = entry.get("unit")
    if not isinstance(unit, str) or not unit:
        raise ValueError(f"{where}: missing field 'unit'")
    error = fields.cost(entry, "error", where)
    if binary:
        if "span" in entry:
            raise ValueError(f"{where}: a binary feature takes no 'span' (its values are 0 and 1)")
        span = (0.0, 1.0)
    else:
        span = fields.pair(entry, "span", where)
    angular_of = entry.get("angular_of")
    if angular_of is not None and (not isinstance(angular_of, str) or binary):
        raise ValueError(f"{where}: 'angular_of' must name a linear feature (and not be set on a binary one)")
    return FeatureSpec(name=name, error=error, unit=unit, binary=binary, span=span, angular_of=angular_of)


def _grasping(entry: object, where: str) -> GraspingProcedure:
    entry = fields.as_table(entry, where)
    name = fields.name(entry, where)
    where = f"{where} ({_shown(name)})"
    fields.only_keys(entry, {"name", "time_s", "range_in", "side_effect_penalty_s", "failure_harm_s", "verifiable"},
                     where)
    penalty = fields.cost(entry, "side_effect_penalty_s", where) if "side_effect_penalty_s" in entry else 0.0
    harm = fields.cost(entry, "failure_harm_s", where) if "failure_harm_s" in entry else 0.0
    return GraspingProcedure(
        name=name,
        time_s=fields.cost(entry, "time_s", where),
        range_in=_range(entry, where),
        side_effect_penalty_s=penalty,
        verifiable=fields.flag(entry, "verifiable", True, where),
        failure_harm_s=harm,
    )


def _range(entry: Mapping[str, object], where: str) -> tuple[float, float]:
    lo, hi = fields.pair(entry, "range_in", where)
    if lo < 0:
        raise ValueError(f"{where}: 'range_in' must not be negative, got [{lo}, {hi}]")
    return lo, hi
