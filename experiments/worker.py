"""What each worker process of an experiment is given once: the seed libraries its jobs
name and the run's robot profile (the pool's initializer, :func:`install_worker`),
and where a job reads them. Sent once per worker, not once per job; read once for the
whole run, so every episode simulates the same robot even if the file changes while
the run goes on."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from learner.description import ObjectDescription
from robot_profile import RobotProfile

Libraries = Mapping[str, Sequence[ObjectDescription]]

_LIBRARIES: dict[str, tuple[ObjectDescription, ...]] = {}
_PROFILE: list[RobotProfile] = []  # the one robot profile of the run, read by the main process


def install_worker(libraries: Libraries, profile: RobotProfile) -> None:
    """Give this process the seed libraries jobs name and the robot profile (the pool's
    initializer: sent once per worker, not once per job). The profile is read once for
    the whole run, so every episode simulates the same robot even if the file changes
    while the run goes on."""
    _LIBRARIES.clear()
    _LIBRARIES.update({name: tuple(descs) for name, descs in libraries.items()})
    _PROFILE[:] = [profile]


def installed_profile() -> RobotProfile:
    """The run's robot profile, as :func:`install_worker` gave it to this process."""
    if not _PROFILE:
        raise ValueError("no robot profile was installed in this worker")
    return _PROFILE[0]


def installed_library(name: str = "trained") -> tuple[ObjectDescription, ...]:
    """The seed library :func:`install_worker` gave this process under ``name``."""
    seed_library = _LIBRARIES.get(name)
    if seed_library is None:
        raise ValueError(f"no library called {name!r} was installed in this worker")
    return seed_library
