"""What a recording was made of: the robot, its profile (file and hash), the criterion,
the seed and the versions of the software that ran, as one MCAP metadata record named
``csl-run`` (docs/recording.md). A recording found on a disk months later says which
robot and which code made it, and two recordings that differ can be told apart by
their profile hash before anyone compares their messages. No Foxglove or mcap import.
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version

from robot_profile import RobotProfile, profile_stamp

RUN_METADATA = "csl-run"
DISTRIBUTIONS = ("csl-executive", "py-trees", "eclipse-zenoh", "ompl", "foxglove-sdk", "mcap")
"""The distributions whose versions a recording names (those installed)."""


@dataclass(frozen=True)
class RunDescription:
    """One run, as the ``csl-run`` record carries it (MCAP metadata is text to text)."""

    robot: str
    profile: str  # the profile file as given
    profile_name: str  # profile_stamp's name: the file's stem
    profile_sha256: str  # profile_stamp's hash of the constants that matter
    criterion: str
    seed: int
    versions: tuple[tuple[str, str], ...]  # (distribution, version), in DISTRIBUTIONS order

    def record(self) -> dict[str, str]:
        """The metadata record: one key a field, ``version.<distribution>`` a version."""
        return {"robot": self.robot, "profile": self.profile, "profile_name": self.profile_name,
                "profile_sha256": self.profile_sha256, "criterion": self.criterion, "seed": str(self.seed),
                **{f"version.{name}": number for name, number in self.versions}}


def installed_versions() -> tuple[tuple[str, str], ...]:
    """The versions of :data:`DISTRIBUTIONS` that are installed, as their metadata says
    (nothing is imported)."""
    found = []
    for name in DISTRIBUTIONS:
        try:
            found.append((name, version(name)))
        except PackageNotFoundError:
            continue
    return tuple(found)


def describe_run(robot: str, profile: RobotProfile, criterion: str, seed: int) -> RunDescription:
    """The description of a run of ``robot`` with ``profile``, ``criterion`` and ``seed``
    (the executive's: the one its choices left to chance draw from)."""
    stamp = profile_stamp(profile)
    return RunDescription(robot, profile.source, stamp.name, stamp.sha256, criterion, seed, installed_versions())
