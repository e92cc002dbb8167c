"""Training fidelity: does every value in a trained library hold where it claims to?

A trained value claims to hold at its position, and a ``*`` slot claims it holds at
every training position of that slot (docs/method.md §4). Checking that claim needs an
exact measurement source (the simulator with noise off, or any oracle): each value is
compared with the exact value at every training position it stands for, and a value
further off than its feature's expected error is a *misfit*. Noise-free training with a
faithful merge gives none, so a misfit points at the merge (or at the source).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.position import Position
from learner.training.inputs import MeasurementSource, TrainingObject
from learner.training.stage import reachable_distances, sensed_at


@dataclass(frozen=True)
class Misfit:
    """A library value off its exact value by more than the feature's expected error."""

    object_id: str
    feature: str
    recorded_at: Position
    checked_at: Position
    value: float
    exact: float | None  # None: the exact source yields no value there
    error: float

    def __str__(self) -> str:
        exact = "nothing" if self.exact is None else f"{self.exact:g}"
        return (f"{self.object_id}: {self.feature}{self.recorded_at} = {self.value:g}, "
                f"exact at {self.checked_at}: {exact} (expected error ±{self.error:g})")


@dataclass(frozen=True)
class FidelityReport:
    """How many library values were compared (one per position they stand for) and
    which of them are off by more than the expected error."""

    checked: int
    misfits: tuple[Misfit, ...]


def stands_for(obj: TrainingObject, feature: str, position: Position, orientations: Sequence[float],
               distances: Sequence[float], knowledge: Knowledge) -> list[Position]:
    """The concrete positions, as the robot was staged for training, that a value recorded
    at ``position`` claims to hold at: ``*`` orientation means every training orientation
    (a round object: the one it is sensed at), ``*`` distance every training distance the
    feature's procedure reaches."""
    ds = [position.distance_in] if position.distance_in is not None else sorted(
        reachable_distances(feature, distances, knowledge))
    os_ = [position.orientation_deg] if position.orientation_deg is not None else list(orientations)
    return sorted({sensed_at(obj, Position(d, o)) for d in ds for o in os_})


def check_fidelity(descriptions: Sequence[ObjectDescription], objects: Sequence[TrainingObject],
                   knowledge: Knowledge, orientations: Sequence[float], distances: Sequence[float],
                   exact: MeasurementSource) -> FidelityReport:
    """Compare every value of ``descriptions`` with ``exact`` wherever it stands for."""
    by_id: Mapping[str, TrainingObject] = {o.object_id: o for o in objects}
    cache: dict[tuple[str, str, Position], Mapping[str, float | None]] = {}
    checked, misfits = 0, []
    for description in descriptions:
        obj = by_id.get(description.object_id)
        if obj is None:
            raise ValueError(f"library object {description.object_id!r} is not among the training objects")
        for obs in description.observations:
            proc = knowledge.procedure_for(obs.feature)
            error = knowledge.feature(obs.feature).error
            for at in stands_for(obj, obs.feature, obs.position, orientations, distances, knowledge):
                key = (obj.object_id, proc.name, at)
                if key not in cache:
                    cache[key] = exact.measure(obj.object_id, proc.name, at)
                truth = cache[key].get(obs.feature)
                checked += 1
                if truth is None or abs(obs.value - float(truth)) > error + 1e-9:
                    misfits.append(Misfit(obj.object_id, obs.feature, obs.position, at, obs.value,
                                          None if truth is None else float(truth), error))
    return FidelityReport(checked, tuple(misfits))
