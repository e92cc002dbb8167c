"""Measuring everything: the paper's two strawmen, priced from the robot's knowledge.

- *Measure every feature* (plain ID3 on the robot, docs/method.md §6: "over 1.5 hours
  per object"): every sensing procedure at every training position, with the moves
  between the positions, then the grasp.
- *Exhaustive training* ("over 5 years", priced by ``learner.training.summary``), in
  the feasible version the experiment runs: every procedure at every *chosen* training
  position, whose descriptions execution then uses (the paper: only ~9% cheaper to
  execute).
"""

from __future__ import annotations

from collections.abc import Sequence

from learner.costs import ModelMoveCost
from learner.description import ObjectDescription, Observation
from learner.knowledge import Knowledge
from learner.position import Position
from learner.training.inputs import MeasurementSource, TrainingObject
from learner.training.stage import generalise

def positions(distances: Sequence[float], orientations: Sequence[float], round_object: bool) -> list[Position]:
    """The training positions an object is sensed from, far to near; a round object has
    no orientation, so one per distance (sensed at 0°)."""
    turns = [0.0] if round_object else sorted(orientations)
    return [Position(d, o) for d in sorted(distances, reverse=True) for o in turns]


def measure_everything_s(knowledge: Knowledge, distances: Sequence[float], orientations: Sequence[float],
                         round_object: bool, grasp: str) -> float:
    """Robot seconds to apply every sensing procedure in range at every training position
    (moving between them by the knowledge's move model), then execute ``grasp``."""
    mover = ModelMoveCost(knowledge.move)
    stops = positions(distances, orientations, round_object)
    sensing = sum(p.time_s for at in stops for p in knowledge.sensing if p.applicable_at(at.distance_in or 0.0))
    moving = sum(mover.move_cost(a, b) for a, b in zip(stops, stops[1:]))
    return sensing + moving + knowledge.grasp(grasp).time_s


def exhaustive_library(objects: Sequence[TrainingObject], knowledge: Knowledge, source: MeasurementSource,
                       distances: Sequence[float], orientations: Sequence[float]) -> tuple[list[ObjectDescription],
                                                                                            float]:
    """Every procedure in range at every chosen training position, for every object, merged
    and generalised as training merges (``learner.training.stage.generalise``). Returns the
    descriptions and the robot seconds of sensing it took."""
    out = []
    spent = 0.0
    for obj in objects:
        observations = []
        for at in positions(distances, orientations, obj.round):
            record_at = Position(at.distance_in, None) if obj.round else at
            for proc in knowledge.sensing:
                if not proc.applicable_at(at.distance_in or 0.0):
                    continue
                values = source.measure(obj.object_id, proc.name, at)
                spent += proc.time_s
                observations += [Observation(f.name, record_at, float(v))
                                 for f in proc.features if (v := values.get(f.name)) is not None]
        out.append(ObjectDescription(obj.object_id, obj.grasp, obj.grasp_position,
                                     tuple(generalise(observations, knowledge, orientations, distances))))
    return out, spent
