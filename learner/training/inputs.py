"""Inputs of the training stage: the training objects and where measurements come from.

Training objects are labelled only with their grasp (docs/method.md §4) plus their overhead
footprint, from which training orientations are derived. Measurements come from a
:class:`MeasurementSource`: the simulator or a live driver in the executive, or a
*replay* file of values a team recorded on a real robot (``docs/training-format.md``).
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Protocol, runtime_checkable

from learner.appearance import Appearance, appearance_from_json
from learner.position import Position, position_from_json


OBJECTS_READS = (1, 2)  # version 2: an object may carry its camera appearance


@dataclass(frozen=True)
class TrainingObject:
    """A training object: its correct grasp and its footprint in its own frame.

    The footprint polygon is in inches with +x along the object's reference axis (the
    overhead region's major axis); a round footprint has no orientation. ``appearance``
    is what the camera measured of it (None: not recorded), kept in its description.
    """

    object_id: str
    grasp: str
    grasp_position: Position
    polygon: tuple[tuple[float, float], ...]
    round: bool
    appearance: Appearance | None = None


@runtime_checkable
class MeasurementSource(Protocol):
    """Applies a sensing procedure to a training object at a position."""

    def measure(self, object_id: str, procedure: str, position: Position) -> Mapping[str, float | None]: ...


class ReplaySource:
    """Measurements recorded earlier, looked up by (object, procedure, position)."""

    def __init__(self, records: Mapping[tuple[str, str, Position], Mapping[str, float | None]], source: str) -> None:
        self._records = dict(records)
        self.source = source

    def measure(self, object_id: str, procedure: str, position: Position) -> Mapping[str, float | None]:
        try:
            return self._records[(object_id, procedure, position)]
        except KeyError:
            raise ValueError(f"{self.source}: no recorded {procedure} of {object_id!r} at {position}") from None


def read_objects(path: str | Path) -> list[TrainingObject]:
    """Read a training-objects JSON file (``format: csl-training-objects``)."""
    data, source = _read_json(path, "csl-training-objects", OBJECTS_READS)
    entries = data.get("objects")
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"{source}: 'objects' must be a non-empty list")
    objects = [_object(e, f"{source}: objects[{i}]") for i, e in enumerate(entries)]
    ids = [o.object_id for o in objects]
    for oid in ids:
        if ids.count(oid) > 1:
            raise ValueError(f"{source}: object id {oid!r} appears twice")
    return objects


def _object(entry: object, where: str) -> TrainingObject:
    if not isinstance(entry, dict):
        raise ValueError(f"{where}: must be an object")
    _only(entry, {"id", "grasp", "grasp_position", "polygon", "round", "appearance"}, where)
    for key in ("id", "grasp"):
        if not isinstance(entry.get(key), str) or not entry[key]:
            raise ValueError(f"{where}: missing or empty string field '{key}'")
    where = f"{where} ({entry['id']})"
    round_ = entry.get("round", False)
    if not isinstance(round_, bool):
        raise ValueError(f"{where}: 'round' must be true or false")
    polygon = entry.get("polygon", [])
    if (not isinstance(polygon, list)
            or not all(isinstance(p, list) and len(p) == 2 and all(_finite(c) for c in p) for p in polygon)):
        raise ValueError(f"{where}: 'polygon' must be a list of [x, y] points in inches")
    if not round_ and len(polygon) < 3:
        raise ValueError(f"{where}: a footprint that is not round needs a 'polygon' of 3 or more points")
    grasp_position = position_from_json(entry.get("grasp_position", [6, "*"]), f"{where}: grasp_position")
    appearance = appearance_from_json(entry["appearance"], f"{where}: appearance") if "appearance" in entry else None
    return TrainingObject(entry["id"], entry["grasp"], grasp_position,
                          tuple((float(x), float(y)) for x, y in polygon), round_, appearance)


def read_replay(path: str | Path) -> ReplaySource:
    """Read a replay measurements JSON file (``format: csl-measurements``)."""
    data, source = _read_json(path, "csl-measurements", (1,))
    entries = data.get("measurements")
    if not isinstance(entries, list):
        raise ValueError(f"{source}: 'measurements' must be a list")
    records: dict[tuple[str, str, Position], dict[str, float | None]] = {}
    for i, e in enumerate(entries):
        where = f"{source}: measurements[{i}]"
        if not isinstance(e, dict):
            raise ValueError(f"{where}: must be an object")
        _only(e, {"object", "procedure", "position", "values"}, where)
        for key in ("object", "procedure"):
            if not isinstance(e.get(key), str) or not e[key]:
                raise ValueError(f"{where}: missing or empty string field '{key}'")
        if "position" not in e:
            raise ValueError(f"{where}: missing field 'position'")
        position = position_from_json(e["position"], f"{where}: position")
        values = e.get("values")
        if not isinstance(values, dict) or not values:
            raise ValueError(f"{where}: 'values' must be a non-empty object of feature: number|null")
        for name, v in values.items():
            if v is not None and not _finite(v):
                raise ValueError(f"{where}: value of {name!r} must be a finite number or null, got {v!r}")
        records[(e["object"], e["procedure"], position)] = {k: (None if v is None else float(v))
                                                            for k, v in values.items()}
    return ReplaySource(records, source)


def replay_document(records: Mapping[tuple[str, str, Position], Mapping[str, float | None]]) -> dict[str, object]:
    """The JSON document for recorded measurements (what a recorder writes)."""
    return {
        "format": "csl-measurements",
        "version": 1,
        "measurements": [
            {"object": o, "procedure": p, "position": pos.to_json(), "values": dict(v)}
            for (o, p, pos), v in sorted(records.items(), key=lambda kv: (kv[0][0], kv[0][1], kv[0][2]))
        ],
    }


def objects_document(objects: Sequence[TrainingObject]) -> dict[str, object]:
    """The JSON document for training objects (``read_objects`` reads it back)."""
    return {
        "format": "csl-training-objects",
        "version": OBJECTS_READS[-1],
        "objects": [
            {"id": o.object_id, "grasp": o.grasp, "grasp_position": o.grasp_position.to_json(),
             **({"round": True} if o.round else {"polygon": [list(p) for p in o.polygon]}),
             **({} if o.appearance is None else {"appearance": o.appearance.to_json()})}
            for o in objects
        ],
    }


def _read_json(path: str | Path, fmt: str, versions: tuple[int, ...]) -> tuple[dict[str, object], str]:
    path = Path(path)
    source = str(path)
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise ValueError(f"{source}: file not found") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as exc:
        raise ValueError(f"{source}: not valid JSON: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != fmt:
        raise ValueError(f"{source}: 'format' must be {fmt!r}")
    version = data.get("version")
    if isinstance(version, bool) or version not in versions:
        raise ValueError(f"{source}: unsupported 'version' {version!r} (this csl reads "
                         f"{', '.join(map(str, versions))})")
    return data, source


def _only(entry: Mapping[str, object], allowed: set[str], where: str) -> None:
    unknown = sorted(set(entry) - allowed - {"comment"})
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r}")


def _finite(v: object) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
