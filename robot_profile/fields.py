"""Field checks for hand-edited TOML tables: each failure is one line naming the place.

``where`` is the prefix of every message (``FILE: ENTRY (NAME)``), so a typo in a
profile reads as the file, the entry and the problem, never as a traceback.
"""

from __future__ import annotations

import math
from collections.abc import Mapping


def table(data: Mapping[str, object], key: str, where: str) -> Mapping[str, object]:
    """The sub-table ``[key]``, which must be present."""
    if key not in data:
        raise ValueError(f"{where}: missing table [{key}]")
    return as_table(data[key], f"{where}: [{key}]")


def array(data: Mapping[str, object], key: str, where: str) -> list[object]:
    """The array of tables ``[[key]]``, which must be present."""
    value = data.get(key)
    if value is None:
        raise ValueError(f"{where}: missing [[{key}]] entries")
    if not isinstance(value, list):
        raise ValueError(f"{where}: '{key}' must be an array of tables")
    return value


def as_table(value: object, where: str) -> Mapping[str, object]:
    if not isinstance(value, Mapping):
        raise ValueError(f"{where}: must be a table")
    return value


def only_keys(entry: Mapping[str, object], allowed: set[str], where: str) -> None:
    """Refuse unknown keys: a misspelt optional field would otherwise be silently ignored."""
    unknown = sorted(set(entry) - allowed)
    if unknown:
        raise ValueError(f"{where}: unknown key {unknown[0]!r} (allowed: {', '.join(sorted(allowed))})")


def name(entry: Mapping[str, object], where: str) -> str:
    value = entry.get("name")
    if not isinstance(value, str) or not value.strip():
        raise ValueError(f"{where}: missing field 'name'")
    return value


def flag(entry: Mapping[str, object], key: str, default: bool, where: str) -> bool:
    value = entry.get(key, default)
    if not isinstance(value, bool):
        raise ValueError(f"{where}: '{key}' must be true or false")
    return value


def cost(entry: Mapping[str, object], key: str, where: str) -> float:
    """A required finite, non-negative number (times, errors, distances)."""
    if key not in entry:
        raise ValueError(f"{where}: missing field '{key}'")
    value = entry[key]
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{where}: '{key}' must be a number, got {value!r}")
    if value < 0:
        raise ValueError(f"{where}: '{key}' must not be negative, got {value}")
    return float(value)


def positive(entry: Mapping[str, object], key: str, where: str) -> float:
    """A required number greater than 0 (what costs are divided by, or a body's size)."""
    value = cost(entry, key, where)
    if value == 0:
        raise ValueError(f"{where}: '{key}' must be greater than 0")
    return value


def pair(entry: Mapping[str, object], key: str, where: str) -> tuple[float, float]:
    """A required ``[low, high]`` of finite numbers with ``low <= high``."""
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


def unique(names: list[str], what: str) -> None:
    seen: set[str] = set()
    for n in names:
        if n in seen:
            raise ValueError(f"{what} {n!r} is defined twice")
        seen.add(n)
