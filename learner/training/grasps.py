"""Training without a teacher: find each training object's grasp by trying grasps
(docs/method.md §4.1).

The paper's training objects come labelled with their grasp, noting that the grasps
"could be determined by the robot by conducting grasping experiments". Here they are:
for each object the robot tries every grasp the finger sensor can confirm, from each of
the object's approaches (a round object has one; another is grasped end-on, along its
reference axis, or from the side), until one holds. If none holds, the object gets the
grasp that leaves it (No-Grab). A grasp found on an object with several approaches is
tried from the others too, and recorded at any side, ``(d,*)``, if it holds from all.

The order is the one that minimises the expected cost of finding a working grasp when
attempts succeed independently with chance ``p`` at cost ``c``: highest ``p / c`` first
(Simon & Kadane's optimal satisficing search). ``p`` is what the robot has learned so
far, every earlier attempt's outcome counted per grasp with a uniform prior,
``(holds + 1) / (attempts + 2)``; ``c`` is the move to the approach plus the attempt's
expected cost, ``p * time_s + (1 - p) * feature_cost_s`` (a failure pays the
side-effect penalty and is priced with its harm). Every attempt's robot seconds and every move are counted.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Protocol, runtime_checkable

from learner.costs import MoveCostEstimator
from learner.knowledge import GraspingProcedure, Knowledge
from learner.position import Position
from learner.training.inputs import TrainingObject

APPROACHES_DEG = (0.0, 90.0)  # end-on and from the side, relative to the reference axis


@dataclass(frozen=True)
class GraspOutcome:
    """What one attempt did: whether the finger sensor says it holds, and its robot seconds."""

    success: bool
    seconds: float


@runtime_checkable
class GraspTrials(Protocol):
    """Tries a grasp on a training object staged alone, the robot at ``position`` (its
    orientation ``None`` for a round object: any approach)."""

    def try_grasp(self, object_id: str, grasp: str, position: Position) -> GraspOutcome: ...


@dataclass(frozen=True)
class GraspTrial:
    """One attempt of the search, in the order made."""

    object_id: str
    grasp: str
    position: Position
    success: bool
    seconds: float
    move_s: float


@dataclass(frozen=True)
class GraspSearch:
    """The objects labelled with the grasps found, and every attempt that found them."""

    objects: tuple[TrainingObject, ...]
    trials: tuple[GraspTrial, ...]

    @property
    def grasping_s(self) -> float:
        return sum(t.seconds for t in self.trials)

    @property
    def moving_s(self) -> float:
        return sum(t.move_s for t in self.trials)


def approaches(obj: TrainingObject, distance_in: float) -> list[Position]:
    """Where a grasp may be tried from: anywhere round a round object, else end-on and
    from the side."""
    if obj.round:
        return [Position(distance_in, None)]
    return [Position(distance_in, a) for a in APPROACHES_DEG]


def success_chance(holds: int, attempts: int) -> float:
    """The chance an attempt of a grasp holds, from its record: ``(holds + 1) / (attempts + 2)``."""
    return (holds + 1) / (attempts + 2)


def find_grasps(objects: Sequence[TrainingObject], knowledge: Knowledge, trials: GraspTrials,
                estimator: MoveCostEstimator) -> GraspSearch:
    """Label each of ``objects`` (their given grasp ignored) with the first grasp that
    holds, trying them in the order of the module docstring; the record of outcomes
    carries from one object to the next."""
    leave = next((g for g in knowledge.grasping if not g.verifiable), None)
    search = _Search(knowledge, trials, estimator)
    found: list[TrainingObject] = []
    for obj in objects:
        label = search.label(obj)
        if label is None:
            if leave is None:
                raise ValueError(f"training object {obj.object_id!r}: no grasp holds it and {knowledge.source} "
                                 "has no grasp for leaving an object")
            label = (leave.name, Position(leave.range_in[0], None))
        found.append(replace(obj, grasp=label[0], grasp_position=label[1]))
    return GraspSearch(tuple(found), tuple(search.made))


class _Search:
    """The record of outcomes so far (per grasp), every attempt made, and where the
    robot stands at the object being tried."""

    def __init__(self, knowledge: Knowledge, trials: GraspTrials, estimator: MoveCostEstimator) -> None:
        self.confirmable = [g for g in knowledge.grasping if g.verifiable]
        self.trials, self.estimator = trials, estimator
        self.holds = {g.name: 0 for g in self.confirmable}
        self.attempts = {g.name: 0 for g in self.confirmable}
        self.made: list[GraspTrial] = []
        self.here: Position | None = None

    def label(self, obj: TrainingObject) -> tuple[str, Position] | None:
        """The grasp (and where) that holds ``obj``, or None if none does."""
        self.here = None  # the object is staged with the robot at the first approach
        options = [(g, at) for g in self.confirmable for at in approaches(obj, g.range_in[0])]
        while options:
            g, at = min(options, key=lambda o: self.priority(o[0], o[1]))
            options.remove((g, at))
            if self.attempt(obj, g.name, at):
                return self.generalised(obj, g.name, at)
        return None

    def attempt(self, obj: TrainingObject, grasp: str, at: Position) -> bool:
        """Try ``grasp`` from ``at``, record it and learn from its outcome."""
        move = _move(self.here, at, self.estimator)
        outcome = self.trials.try_grasp(obj.object_id, grasp, at)
        self.made.append(GraspTrial(obj.object_id, grasp, at, outcome.success, outcome.seconds, move))
        self.attempts[grasp] += 1
        self.holds[grasp] += outcome.success
        self.here = at
        return outcome.success

    def generalised(self, obj: TrainingObject, grasp: str, at: Position) -> tuple[str, Position]:
        """The grasp found, tried from the object's other approaches too: if it holds
        from every one, its position is generalised to any side, ``(d,*)``, as training
        generalises a grasp position (docs/method.md §4); else it stays where it held.
        Without this a grasp that holds from anywhere would send the robot round to one
        side at run time."""
        others = [a for a in approaches(obj, at.distance_in or 0.0) if a != at]
        failed_here = {t.position for t in self.made if t.object_id == obj.object_id and t.grasp == grasp}
        if not others or failed_here & set(others):
            return grasp, at  # one approach, or it already failed from another
        for other in others:
            if not self.attempt(obj, grasp, other):
                return grasp, at
        return grasp, Position(at.distance_in, None)

    def priority(self, g: GraspingProcedure, at: Position) -> tuple[float, str, float]:
        """Sort key: highest chance per expected second first, then by name and approach."""
        p = success_chance(self.holds[g.name], self.attempts[g.name])
        expected = _move(self.here, at, self.estimator) + p * g.time_s + (1.0 - p) * g.feature_cost_s
        return (-p / expected, g.name, at.orientation_deg or 0.0)


def _move(here: Position | None, at: Position, estimator: MoveCostEstimator) -> float:
    """The move from the last approach tried on this object (the first is staged: free)."""
    return 0.0 if here is None else estimator.move_cost(_staged(here), _staged(at))


def _staged(at: Position) -> Position:
    """A concrete position to price a move from or to (a round object's any-side at 0°)."""
    return at if at.orientation_deg is not None else Position(at.distance_in, 0.0)
