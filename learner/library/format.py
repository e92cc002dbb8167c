"""The library's JSON exchange format (docs/library-format.md): for people and version control.

A library file is ``{"format": "csl-library", "version": 2, "descriptions": [...]}``:
one object per description, its features as ``{"feature", "position", "value"}``
entries (version 1 has no appearances; version 3 is the columnar layout of
``learner.library.columnar``). Reading checks the document's shape and names the entry
and field of any fault; whether this robot can use a description is
``learner.library.checks``'s question, and the SQLite store a running robot appends to
is ``learner.library.store``.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Iterable
from pathlib import Path

from learner.appearance import appearance_from_json
from learner.description import ObjectDescription, Observation, in_order
from learner.library.columnar import COLUMNAR_VERSION, columnar_from_json, columnar_to_json
from learner.library.input_file import open_input, read_input
from learner.library.json_text import NotJson, parse_json
from learner.position import finite_number, known_position_json, position_from_json

FORMAT = "csl-library"
VERSION = 2  # 2: descriptions may carry the camera's appearance of their object
READS = (1, 2)  # a version-1 library loads with no appearances
JSON_READS = (*READS, COLUMNAR_VERSION)  # JSON files may also be columnar (learner/library/columnar.py)


def descriptions_to_json(descriptions: Iterable[ObjectDescription]) -> dict[str, object]:
    """The documented JSON document for a set of descriptions."""
    return {
        "format": FORMAT,
        "version": VERSION,
        "descriptions": [
            {
                "id": d.object_id,
                "grasp": d.grasp,
                "grasp_position": d.grasp_position.to_json(),
                "features": [
                    {"feature": o.feature, "position": o.position.to_json(), "value": _json_num(o.value)}
                    for o in d.observations
                ],
                **({} if d.appearance is None else {"appearance": d.appearance.to_json()}),
            }
            for d in descriptions
        ],
    }


def descriptions_from_json(data: object, source: str = "<library>") -> list[ObjectDescription]:
    """Parse and validate a library JSON document; errors name the entry and field."""
    if not isinstance(data, dict):
        raise ValueError(f"{source}: a library is a JSON object with 'format' and 'descriptions'")
    if data.get("format") != FORMAT:
        raise ValueError(f"{source}: 'format' must be {FORMAT!r}, got {data.get('format')!r}")
    version = data.get("version")
    if isinstance(version, bool) or version not in JSON_READS:
        raise ValueError(f"{source}: unsupported 'version' {version!r} (this csl reads "
                         f"{', '.join(map(str, JSON_READS))})")
    if version == COLUMNAR_VERSION:
        return columnar_from_json(data, source)
    unknown = sorted(set(data) - {"format", "version", "descriptions"})
    if unknown:
        raise ValueError(f"{source}: unknown key {unknown[0]!r}")
    entries = data.get("descriptions")
    if not isinstance(entries, list):
        raise ValueError(f"{source}: 'descriptions' must be a list")
    out = [_description(e, f"{source}: descriptions[{i}]", version) for i, e in enumerate(entries)]
    seen: set[str] = set()
    for d in out:
        if d.object_id in seen:
            raise ValueError(f"{source}: description id {d.object_id!r} appears twice")
        seen.add(d.object_id)
    return out


_ENTRY_KEYS = {1: frozenset({"id", "grasp", "grasp_position", "features"}),
               2: frozenset({"id", "grasp", "grasp_position", "features", "appearance"})}
_FEATURE_KEYS = frozenset({"feature", "position", "value"})


def _description(entry: object, where: str, version: int) -> ObjectDescription:
    if not isinstance(entry, dict):
        raise ValueError(f"{where}: must be an object")
    if not entry.keys() <= _ENTRY_KEYS[version]:
        raise ValueError(f"{where}: unknown key {sorted(entry.keys() - _ENTRY_KEYS[version])[0]!r}")
    for key in ("id", "grasp"):
        if not isinstance(entry.get(key), str) or not entry[key]:
            raise ValueError(f"{where}: missing or empty string field '{key}'")
        if not entry[key].isprintable():
            raise ValueError(f"{where}: '{key}' must be printable text (no control or format characters: a "
                             f"newline, NUL, a right-to-left override), got {entry[key]!r:.120}")
    where = f"{where} ({entry['id']})"
    if "grasp_position" not in entry:
        raise ValueError(f"{where}: missing field 'grasp_position'")
    grasp_position = position_from_json(entry["grasp_position"], f"{where}: grasp_position")
    features = entry.get("features", [])
    if not isinstance(features, list):
        raise ValueError(f"{where}: 'features' must be a list")
    observations = _plain_observations(features)
    if observations is None:
        observations = [_observation(f, f"{where}: features[{j}]") for j, f in enumerate(features)]
    appearance = (appearance_from_json(entry["appearance"], f"{where}: appearance")
                  if "appearance" in entry else None)
    return ObjectDescription(entry["id"], sys.intern(entry["grasp"]), grasp_position, in_order(observations),
                             appearance)


def _plain_observations(features: list[object]) -> list[Observation] | None:
    """The observations when every entry is plainly valid (the usual case), else None.

    The bulk path of loading: no error context is built, and positions seen before are
    looked up rather than parsed. Anything unusual (an unseen position, a missing or
    extra key, a bad value) returns None, and :func:`_observation` then parses each entry
    with full checks and the error naming it, so validation is exactly the same.
    """
    out = []
    for f in features:
        if type(f) is not dict or len(f) != 3:
            return None
        feature, value = f.get("feature"), f.get("value")
        position = known_position_json(f.get("position"))
        if (position is None or type(feature) is not str or not feature
                or type(value) not in _JSON_NUMBER or not finite_number(value)):
            return None
        out.append(Observation(sys.intern(feature), position, float(value)))
    return out


def _observation(f: object, where: str) -> Observation:
    """One ``features[j]`` entry, fully checked; errors name ``where`` and the field."""
    if not isinstance(f, dict):
        raise ValueError(f"{where}: must be an object")
    if not f.keys() <= _FEATURE_KEYS:
        raise ValueError(f"{where}: unknown key {sorted(f.keys() - _FEATURE_KEYS)[0]!r}")
    if not isinstance(f.get("feature"), str) or not f["feature"]:
        raise ValueError(f"{where}: missing field 'feature'")
    value = f.get("value")
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not finite_number(value):
        raise ValueError(f"{where}: 'value' must be a finite number, got {value!r}")
    if "position" not in f:
        raise ValueError(f"{where}: missing field 'position'")
    return Observation(sys.intern(f["feature"]), position_from_json(f["position"], f"{where}: position"),
                       float(value))


_JSON_NUMBER = (int, float)  # exact types: a JSON true is a bool, not a number


def read_library_json(path: str | Path) -> list[ObjectDescription]:
    """A library JSON file: only a regular file is read (a FIFO would wait for ever),
    and JSON that is not a library's, however broken, is one ValueError line."""
    path = Path(path)
    with open_input(path, "library file") as stream:
        text = read_input(stream, path, "library file")
    try:
        data = parse_json(text)
    except NotJson as exc:
        raise ValueError(f"{path}: not valid JSON: {exc}") from None
    return descriptions_from_json(data, str(path))


def write_library_json(path: str | Path, descriptions: Iterable[ObjectDescription], *,
                       columnar: bool = False) -> None:
    """Write a library JSON file atomically (see :func:`write_json_atomically`): the row
    layout (version 2, one object per description, for people and diffs), or with
    ``columnar`` version 3, which a large library loads from an order of magnitude faster."""
    document = columnar_to_json(descriptions, FORMAT) if columnar else descriptions_to_json(descriptions)
    write_json_atomically(path, document, indent=None if columnar else 2)


def write_json_atomically(path: str | Path, document: object, indent: int | None = 2) -> None:
    """Write a JSON document so that a reader never sees half a file and a failure
    leaves none behind. ``indent=None``: one line (a columnar library, whose arrays
    would otherwise take a line per index)."""
    path = Path(path)
    if path.is_dir():
        raise ValueError(f"{path}: is a folder, not a file to write to")
    tmp = path.with_name(path.name + ".tmp")
    try:
        tmp.write_text(json.dumps(document, indent=indent, ensure_ascii=False) + "\n", encoding="utf-8")
        tmp.replace(path)
    finally:
        tmp.unlink(missing_ok=True)


def _json_num(v: float) -> float | int:
    return int(v) if float(v).is_integer() else v
