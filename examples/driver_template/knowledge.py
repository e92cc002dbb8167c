"""The robot's knowledge profile (the TOML of docs/knowledge-format.md) as the driver
needs it: the procedures it must run, the [robot] constants, and the profile's name
and fingerprint that ``hello`` sends under the ``profile`` feature.

The fingerprint is computed exactly as docs/driver-protocol.md ("The `profile`
feature") gives it, with the standard library only: the SHA-256 of the canonical JSON
of every [robot] constant and, per procedure, its name, range_in and time_s (and a
sensing procedure's feature names). A client compares it with the fingerprint of the
profile it plans with (``csl run --knowledge FILE``, ``csl driver check --profile
FILE``) and refuses the driver when they differ: the robot it would drive is not the
one it planned for.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from dataclasses import dataclass
from pathlib import Path

DEFAULT_PROFILE = Path(__file__).resolve().parent / "hero2000.toml"


@dataclass(frozen=True)
class Procedure:
    """What the driver needs of one procedure: how long it takes and the distance
    range (inches from the sonar or hand to the object) it runs at."""

    time_s: float
    range_in: tuple[float, float]
    features: tuple[str, ...] = ()  # the feature names a sensing procedure reports


@dataclass(frozen=True)
class Knowledge:
    """One profile file: ``name`` is its stem, ``sha256`` its fingerprint."""

    name: str
    sha256: str
    robot: dict[str, float]  # the [robot] table: base_radius_in, speed_in_per_s, ...
    sensing: dict[str, Procedure]
    grasping: dict[str, Procedure]


def load(path: str | Path = DEFAULT_PROFILE) -> Knowledge:
    """Read a profile; ValueError naming the file and what is wrong with it."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        robot = {key: float(value) for key, value in data["robot"].items()}
        sensing = {entry["name"]: Procedure(float(entry["time_s"]), _pair(entry["range_in"]),
                                            tuple(feature["name"] for feature in entry["features"]))
                   for entry in data["sensing"]}
        grasping = {entry["name"]: Procedure(float(entry["time_s"]), _pair(entry["range_in"]))
                    for entry in data["grasping"]}
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the profile: {exc}") from None
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"{path}: not a knowledge profile ({type(exc).__name__}: {exc})") from None
    return Knowledge(path.stem, fingerprint(robot, sensing, grasping), robot, sensing, grasping)


def fingerprint(robot: dict[str, float], sensing: dict[str, Procedure], grasping: dict[str, Procedure]) -> str:
    """docs/driver-protocol.md's canonical text, hashed: keys sorted, no spaces,
    procedures sorted by name, feature names sorted, every number a float."""
    constants = {
        "robot": {key: float(value) for key, value in robot.items()},
        "sensing": [{"name": name, "range_in": list(p.range_in), "time_s": p.time_s, "features": sorted(p.features)}
                    for name, p in sorted(sensing.items())],
        "grasping": [{"name": name, "range_in": list(p.range_in), "time_s": p.time_s}
                     for name, p in sorted(grasping.items())],
    }
    text = json.dumps(constants, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def _pair(value: list) -> tuple[float, float]:
    lo, hi = value
    return float(lo), float(hi)
