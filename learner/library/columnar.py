"""The library's columnar JSON layout (format version 3): large libraries as JSON that
parses an order of magnitude faster.

A 100,000-description library in the row layout (version 2) is about 1.8 million
``{"feature", "position", "value"}`` objects, and ``json.loads`` alone takes seconds to
build them; yet there are only some 12,500 distinct observations and a few dozen
positions, grasps and features. So version 3 lists each distinct thing once, in a
table, and gives every description's fields as one array per field, its observations as
indices into the observation table (docs/library-format.md). The parser then reads
small integers, and each distinct observation is built once and shared, as the SQLite
store's observation codes are.

Validation is as strict as the row layout's: every index is an integer (not a
``true``) within its table, every list as long as the ids, errors name the field and
the entry. The checks over the 1.8 million indices run as set and min/max operations in
C; only a failing file is walked entry by entry, to name what is wrong.
"""

from __future__ import annotations

import itertools
import sys
from collections.abc import Callable, Iterable, Sequence

import numpy as np

from learner.appearance import Appearance, appearance_from_json
from learner.description import ObjectDescription, Observation
from learner.position import Position, finite_number, position_from_json

COLUMNAR_VERSION = 3
_TOP_KEYS = frozenset({"format", "version", "features", "positions", "grasps", "observations", "descriptions"})
_COLUMNS = ("id", "grasp", "grasp_position", "observations", "appearance")
_REQUIRED = ("id", "grasp", "grasp_position", "observations")


def columnar_to_json(descriptions: Iterable[ObjectDescription], format_name: str) -> dict[str, object]:
    """The version-3 document: tables of the distinct features, positions, grasps and
    observations (each in the library's canonical order, so a description's observation
    indices ascend as its observations do), then one array per description field."""
    descriptions = list(descriptions)
    observations = sorted({o for d in descriptions for o in d.observations}, key=_order_key)
    features = sorted({o.feature for o in observations})
    positions = sorted({o.position for o in observations} | {d.grasp_position for d in descriptions},
                       key=Position.order_key)
    grasps = sorted({d.grasp for d in descriptions})
    feature_at = {f: i for i, f in enumerate(features)}
    position_at = {p: i for i, p in enumerate(positions)}
    grasp_at = {g: i for i, g in enumerate(grasps)}
    observation_at = {o: i for i, o in enumerate(observations)}
    columns: dict[str, list[object]] = {
        "id": [d.object_id for d in descriptions],
        "grasp": [grasp_at[d.grasp] for d in descriptions],
        "grasp_position": [position_at[d.grasp_position] for d in descriptions],
        "observations": [[observation_at[o] for o in d.observations] for d in descriptions],
    }
    if any(d.appearance is not None for d in descriptions):
        columns["appearance"] = [None if d.appearance is None else d.appearance.to_json() for d in descriptions]
    return {
        "format": format_name,
        "version": COLUMNAR_VERSION,
        "features": features,
        "positions": [p.to_json() for p in positions],
        "grasps": grasps,
        "observations": [[feature_at[o.feature], position_at[o.position], _json_num(o.value)]
                         for o in observations],
        "descriptions": columns,
    }


def columnar_from_json(data: dict[str, object], source: str) -> list[ObjectDescription]:
    """The descriptions of a version-3 document (``format`` and ``version`` already
    checked by the caller); any fault is one ValueError naming the field and entry."""
    unknown = sorted(set(data) - _TOP_KEYS)
    if unknown:
        raise ValueError(f"{source}: unknown key {unknown[0]!r}")
    features = _names(data, "features", source)
    grasps = _names(data, "grasps", source)
    positions = [position_from_json(p, f"{source}: positions[{i}]")
                 for i, p in enumerate(_list(data, "positions", source))]
    observations = [_observation(entry, features, positions, f"{source}: observations[{i}]")
                    for i, entry in enumerate(_list(data, "observations", source))]
    columns = data.get("descriptions")
    if not isinstance(columns, dict):
        raise ValueError(f"{source}: 'descriptions' must be an object of one array per field ({', '.join(_COLUMNS)})")
    extra = sorted(set(columns) - set(_COLUMNS))
    if extra:
        raise ValueError(f"{source}: descriptions: unknown key {extra[0]!r}")
    for key in _REQUIRED:
        if not isinstance(columns.get(key), list):
            raise ValueError(f"{source}: descriptions.{key} must be a list")
    ids = columns["id"]
    n = len(ids)
    for key in _COLUMNS:
        if key in columns and (not isinstance(columns[key], list) or len(columns[key]) != n):
            raise ValueError(f"{source}: descriptions.{key} must be a list as long as descriptions.id ({n})")
    if set(map(type, ids)) - {str} or not all(ids):
        i = next(i for i, x in enumerate(ids) if type(x) is not str or not x)
        raise ValueError(f"{source}: descriptions.id[{i}]: must be a non-empty string, got {ids[i]!r}")
    if len(set(ids)) != n:
        seen: set[str] = set()
        twice = next(x for x in ids if x in seen or seen.add(x))
        raise ValueError(f"{source}: description id {twice!r} appears twice")
    _indices(columns["grasp"], len(grasps), lambda i: f"{source}: descriptions.grasp[{i}]", "grasps")
    _indices(columns["grasp_position"], len(positions), lambda i: f"{source}: descriptions.grasp_position[{i}]",
             "positions")
    coded = columns["observations"]
    if set(map(type, coded)) - {list}:
        i = next(i for i, x in enumerate(coded) if type(x) is not list)
        raise ValueError(f"{source}: descriptions.observations[{i}]: must be a list of indices into 'observations'")
    flat = list(itertools.chain.from_iterable(coded))
    if not _valid_indices(flat, len(observations)):
        for i, codes in enumerate(coded):
            _indices(codes, len(observations),
                     lambda j, i=i: f"{source}: descriptions.observations[{i}][{j}] ({ids[i]})", "observations")
    appearances = columns.get("appearance") or [None] * n
    # canonical order: the table sorted, each description's indices mapped to ranks and sorted
    order = sorted(range(len(observations)), key=lambda i: _order_key(observations[i]))
    table = [observations[i] for i in order]
    rank = [0] * len(order)
    for r, i in enumerate(order):
        rank[i] = r
    to_rank, decode = rank.__getitem__, table.__getitem__
    in_canonical_order = order == list(range(len(order))) and _ascending(coded, flat)
    seen_appearance: dict[tuple[object, ...], Appearance] = {}
    out = []
    for i, (object_id, g, p, codes, look) in enumerate(zip(ids, columns["grasp"], columns["grasp_position"], coded,
                                                         appearances)):
        held = tuple(map(decode, codes if in_canonical_order else sorted(map(to_rank, codes))))
        appearance = None if look is None else _appearance(
            look, seen_appearance, f"{source}: descriptions.appearance[{i}] ({object_id})")
        out.append(ObjectDescription(object_id, grasps[g], positions[p], held, appearance))
    return out


def _ascending(coded: list[list[int]], flat: list[int]) -> bool:
    """Whether every description's indices ascend (as the writer leaves them), checked
    over all of them at once: then no description's observations need sorting."""
    lengths = np.fromiter(map(len, coded), dtype=np.int64, count=len(coded))
    step = np.diff(np.array(flat, dtype=np.int64))
    within = np.ones(len(step), dtype=bool)
    boundaries = np.cumsum(lengths)[:-1] - 1  # the step from a description's last index to the next's first
    within[boundaries[(boundaries >= 0) & (boundaries < len(step))]] = False
    return bool((step[within] > 0).all())


def _order_key(o: Observation) -> tuple[str, tuple[bool, float, bool, float], float]:
    return (o.feature, o.position.order_key(), o.value)


def _list(data: dict[str, object], key: str, source: str) -> list[object]:
    value = data.get(key)
    if not isinstance(value, list):
        raise ValueError(f"{source}: '{key}' must be a list")
    return value


def _names(data: dict[str, object], key: str, source: str) -> list[str]:
    names = _list(data, key, source)
    for i, name in enumerate(names):
        if not isinstance(name, str) or not name:
            raise ValueError(f"{source}: {key}[{i}]: must be a non-empty string, got {name!r}")
    return [sys.intern(name) for name in names]


def _observation(entry: object, features: Sequence[str], positions: Sequence[Position], where: str) -> Observation:
    if not isinstance(entry, list) or len(entry) != 3:
        raise ValueError(f"{where}: an observation is [feature index, position index, value], got {entry!r}")
    f, p, value = entry
    if type(f) is not int or not 0 <= f < len(features):
        _indices([f], len(features), lambda _: f"{where}[0]", "features")
    if type(p) is not int or not 0 <= p < len(positions):
        _indices([p], len(positions), lambda _: f"{where}[1]", "positions")
    if type(value) not in (int, float) or not finite_number(value):
        raise ValueError(f"{where}[2]: the value must be a finite number, got {value!r}")
    return Observation(features[f], positions[p], float(value))


def _valid_indices(values: list[object], size: int) -> bool:
    """Whether every value is an int (exactly: JSON ``true`` is not one) in ``[0, size)``,
    checked in C over the whole list."""
    return not values or (set(map(type, values)) == {int} and min(values) >= 0 and max(values) < size)


def _indices(values: list[object], size: int, where: Callable[[int], str], table: str) -> None:
    """Refuse the first value that is not an index into ``table`` (of ``size`` entries),
    naming it by ``where(position in values)``."""
    if _valid_indices(values, size):
        return
    for i, v in enumerate(values):
        if type(v) is not int or not 0 <= v < size:
            raise ValueError(f"{where(i)}: must be an index into '{table}' (0 to {size - 1}), got {v!r}")


def _appearance(look: object, seen: dict[tuple[object, ...], Appearance], where: str) -> Appearance:
    """One appearance, parsed once per distinct ``(round, area, elongation)`` with the
    same JSON types (so a cached one is only reused for what would parse the same)."""
    key = None
    if type(look) is dict and len(look) == 3:
        fields = (look.get("round"), look.get("area_in2"), look.get("elongation"))
        if all(type(f) in (bool, int, float) for f in fields):
            key = (*fields, *map(type, fields))
            if key in seen:
                return seen[key]
    appearance = appearance_from_json(look, where)
    if key is not None:
        seen[key] = appearance
    return appearance


def _json_num(v: float) -> float | int:
    return int(v) if float(v).is_integer() else v
