"""A profile's name and fingerprint: what a driver process and a client compare to
know they mean the same robot.

The fingerprint covers only what the robot *does*, so two files that differ in the
learner's knowledge (feature errors, spans, the ``[move]`` cost model, side-effect
penalties) still name the same robot, while any change the planner or the simulator
would feel changes it: every ``[robot]`` constant, and for each procedure its name,
its distance range and its execution time (and, for sensing, the names of the
features it yields, since the driver is the one that reports them). The ``[scanner]``
table is left out: every scan states its own angles and range limits, so a client
reads a scan right whatever scanner the robot carries, and no plan depends on it.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import MISSING, dataclass, fields
from pathlib import Path

from robot_profile.model import RobotProfile


@dataclass(frozen=True)
class ProfileStamp:
    """``name``: the profile file's stem (``hero2000``, ``rover``), for people;
    ``sha256``: 64 lowercase hex digits of :func:`profile_stamp`'s canonical text, for
    comparing."""

    name: str
    sha256: str


def profile_stamp(profile: RobotProfile) -> ProfileStamp:
    """The stamp of ``profile``: its file's stem and the SHA-256 of the canonical JSON
    of the constants that matter (docs/driver-protocol.md, "The robot profile").

    Canonical means: keys sorted, no spaces, procedures sorted by name, every number a
    float; so the order of keys and of ``[[sensing]]``/``[[grasping]]`` entries in the
    file, and ``13`` versus ``13.0``, change nothing.
    """
    constants = {
        "robot": {key: float(value) for part in (profile.robot.geometry, profile.robot.motion)
                  for key, value in set_constants(part).items()},
        "sensing": sorted(({"name": p.name, "range_in": _floats(p.range_in), "time_s": float(p.time_s),
                            "features": sorted(f.name for f in p.features)} for p in profile.sensing),
                          key=lambda entry: entry["name"]),
        "grasping": sorted(({"name": g.name, "range_in": _floats(g.range_in), "time_s": float(g.time_s)}
                            for g in profile.grasping), key=lambda entry: entry["name"]),
    }
    text = json.dumps(constants, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    return ProfileStamp(Path(profile.source).stem, hashlib.sha256(text.encode("utf-8")).hexdigest())


def set_constants(part: object) -> dict[str, float]:
    """A ``[robot]`` part's constants, less those at their field's default: a constant
    added later with a default that leaves the robots before it as they were changes
    neither their files nor their fingerprints (a robot that sets another value has
    another fingerprint, as it should)."""
    return {f.name: getattr(part, f.name) for f in fields(part)  # type: ignore[arg-type]
            if f.default is MISSING or getattr(part, f.name) != f.default}


def _floats(pair: tuple[float, float]) -> list[float]:
    return [float(value) for value in pair]
