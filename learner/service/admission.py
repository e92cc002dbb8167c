"""What the learner service admits into the shared library, and what it quarantines.

One description every robot reads can stop every robot: a value of 1e308 fails the
library check each ``csl run`` makes before moving, so one bad ``learn`` would keep the
whole fleet still until someone edited the database by hand. The service therefore
checks a description against the robot's knowledge *before* storing it, with the same
check a run makes (``check_library``) plus where the description says to measure and
grasp: a feature's position must be one its sensing procedure can reach, a grasp's one
its grasping procedure can. Descriptions stored before this check existed (or written
behind the service's back) are checked when the service opens its store; those that
fail are quarantined: kept in the store, untouched, but not served.
"""

from __future__ import annotations

from dataclasses import dataclass

from learner.description import ObjectDescription
from learner.knowledge import GraspingProcedure, Knowledge, SensingProcedure
from learner.library.checks import check_library
from learner.library.format import descriptions_from_json, descriptions_to_json
from learner.position import Position

MAX_ID_CHARS = 200
"""Longest id admitted; the training names objects in a few words, ``#n`` included."""

MAX_OBSERVATIONS = 1000
"""Most observations admitted in one description: a description records a feature only
where it told objects apart, tens at most in the shipped library; the cap keeps one
request from making every robot's library download megabytes larger."""


@dataclass(frozen=True)
class Quarantined:
    """A stored description the service does not serve, and the one-line reason."""

    object_id: str
    reason: str


def admitted(description: ObjectDescription, knowledge: Knowledge | None, source: str) -> ObjectDescription:
    """``description`` as the library JSON gives it back, or ValueError with one line.

    Always: it survives the library format (non-empty id, finite numbers, positions a
    distance >= 0 and a bearing in [0, 360)), so ``csl library export`` and the zenoh
    protocol can carry it, and its size is capped. With ``knowledge``: it also passes
    :func:`check_library` and its positions are reachable (:func:`check_positions`).
    Without knowledge only the format is checked: a service that was not told which
    robot it serves cannot know which features exist.
    """
    checked = descriptions_from_json(descriptions_to_json([description]), source)[0]
    where = f"{source}: description {checked.object_id[:MAX_ID_CHARS]!r}"
    if len(checked.object_id) > MAX_ID_CHARS:
        raise ValueError(f"{where}: id is {len(checked.object_id)} characters, at most {MAX_ID_CHARS} are admitted")
    if len(checked.observations) > MAX_OBSERVATIONS:
        raise ValueError(f"{where}: features: {len(checked.observations)} observations, at most "
                         f"{MAX_OBSERVATIONS} are admitted")
    if knowledge is not None:
        check_library([checked], knowledge, source)
        check_positions(checked, knowledge, where)
    return checked


def check_positions(description: ObjectDescription, knowledge: Knowledge, where: str) -> None:
    """ValueError unless every concrete distance is within its procedure's range.

    ``*`` is always admitted (the robot stays where it is along that slot). Assumes
    :func:`check_library` passed, so every feature and the grasp are known.
    """
    grasp = knowledge.grasp(description.grasp)
    _within(description.grasp_position, grasp, f"{where}: grasp_position {description.grasp_position}")
    for o in description.observations:
        procedure = knowledge.procedure_for(o.feature)
        _within(o.position, procedure, f"{where}: {o.feature}{o.position}")


def partition(descriptions: list[ObjectDescription], knowledge: Knowledge | None,
              source: str) -> tuple[tuple[ObjectDescription, ...], tuple[Quarantined, ...]]:
    """The stored descriptions split into those served and those quarantined, each
    checked alone so that one bad row costs only itself."""
    served: list[ObjectDescription] = []
    quarantined: list[Quarantined] = []
    for d in descriptions:
        try:
            admitted(d, knowledge, source)
        except ValueError as exc:
            quarantined.append(Quarantined(d.object_id, " ".join(str(exc).split())))
        else:
            served.append(d)
    return tuple(served), tuple(quarantined)


def _within(position: Position, procedure: SensingProcedure | GraspingProcedure, where: str) -> None:
    d = position.distance_in
    if d is not None and not procedure.applicable_at(d):
        lo, hi = procedure.range_in
        raise ValueError(f"{where}: distance {d:g} in is outside {procedure.name}'s range [{lo:g}, {hi:g}]")
