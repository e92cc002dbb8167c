"""The training stage's numbers, as the paper reports them (docs/method.md §6).

The paper's training on Table 3 found the orientations 0/90/181/272° and the distances
6/16/24 in and cost about 7 hours of robot time; training *exhaustively*, every
procedure at every position, it estimated at over 5 years. :func:`summarise` gives the
same figures for a training run, the exhaustive ones computed from the knowledge alone
(nothing is run for them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from learner.knowledge import Knowledge
from learner.training.inputs import TrainingObject
from learner.training.stage import TrainingResult

SECONDS_PER_HOUR = 3600.0
SECONDS_PER_YEAR = 365.25 * 24 * SECONDS_PER_HOUR


@dataclass(frozen=True)
class TrainingSummary:
    """What a training run found and what it cost, next to exhaustive training.

    ``applications``: sensing procedures applied (object, procedure, position), phase 1's
    size scans included. ``every_procedure_at_positions_s``: sensing time had every
    procedure been applied to every object at every chosen training position (round
    objects once per distance). ``exhaustive_s``: sensing time of the paper's exhaustive
    training, every procedure at every position it can reach on a grid of whole inches
    and whole degrees, for every object; moves are not counted, so it is a lower bound.
    """

    orientations_deg: tuple[float, ...]
    distances_in: tuple[float, ...]
    descriptions: int
    observations: int
    applications: int
    sensing_s: float
    moving_s: float
    every_procedure_at_positions_s: float
    exhaustive_s: float

    @property
    def total_s(self) -> float:
        return self.sensing_s + self.moving_s

    @property
    def robot_hours(self) -> float:
        return self.total_s / SECONDS_PER_HOUR

    @property
    def exhaustive_years(self) -> float:
        return self.exhaustive_s / SECONDS_PER_YEAR


def summarise(result: TrainingResult, objects: Sequence[TrainingObject], knowledge: Knowledge) -> TrainingSummary:
    """The figures of one training run of ``objects`` (the objects it was given)."""
    log = result.log
    return TrainingSummary(
        orientations_deg=tuple(log.orientations),
        distances_in=tuple(log.distances),
        descriptions=len(result.descriptions),
        observations=sum(len(d.observations) for d in result.descriptions),
        applications=len(log.applied),
        sensing_s=log.sensing_s,
        moving_s=log.moving_s,
        every_procedure_at_positions_s=every_procedure_at_positions_s(objects, knowledge, log.orientations,
                                                                      log.distances),
        exhaustive_s=exhaustive_training_s(len(objects), knowledge),
    )


def every_procedure_at_positions_s(objects: Sequence[TrainingObject], knowledge: Knowledge,
                                   orientations: Sequence[float], distances: Sequence[float]) -> float:
    """Sensing time of applying every procedure to every object at every training
    position (a round object at one orientation per distance, as training stages it)."""
    total = 0.0
    for obj in objects:
        seen_from = 1 if obj.round else len(orientations)
        total += seen_from * sum(p.time_s for d in distances for p in knowledge.sensing if p.applicable_at(d))
    return total


def exhaustive_training_s(objects: int, knowledge: Knowledge, distance_step_in: float = 1.0,
                          orientation_step_deg: float = 1.0) -> float:
    """Sensing time of every procedure at every position on a grid, for ``objects``
    objects: distances from the nearest to the farthest any procedure reaches in
    ``distance_step_in`` steps, all ``360 / orientation_step_deg`` orientations.

    The paper does not say how it counted "every position"; a whole-inch, whole-degree
    grid is the finest a sonar accurate to ±0.5 in and a 1° sweep can tell apart, and for
    the HERO 2000 gives a little over 5 years for Table 3, the paper's figure.
    """
    if distance_step_in <= 0 or orientation_step_deg <= 0:
        raise ValueError("exhaustive training: grid steps must be positive")
    if not knowledge.sensing:
        return 0.0
    near = min(p.range_in[0] for p in knowledge.sensing)
    far = max(p.range_in[1] for p in knowledge.sensing)
    steps = int(math.floor((far - near) / distance_step_in + 1e-9))
    per_orientation = sum(p.time_s for i in range(steps + 1) for p in knowledge.sensing
                          if p.applicable_at(near + i * distance_step_in))
    return objects * round(360.0 / orientation_step_deg) * per_orientation
