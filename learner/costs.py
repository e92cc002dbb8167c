"""Costs: what it costs the robot to move, and what its grasps have cost.

The learner prices every candidate test from where the robot stands *now*, so the move
estimator is pluggable: the knowledge file's simple model by default, the planner's
map-based heuristic once an executive provides one (any object with ``move_cost``).
An estimator may also price a move to a *sensing* position apart (optional
``sensing_move_cost``): a position from which the sound would meet another object is
worth nothing for sensing (``inf``) though a grasp from there is fine; callers price
through :func:`sensing_cost`, never ask the estimator which it has.

Grasps are priced by the knowledge file until the robot has tried them: the paper
"neglects learning failure recovery costs for grasping procedures"; here each grasp's
attempts are kept (:class:`GraspCostRecord`) and :func:`with_learned_grasp_costs` prices
it by their Bayesian mean, the file's cost its prior (docs/method.md §5.7).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from learner.knowledge import Knowledge, MoveModel
from learner.position import Position


@runtime_checkable
class MoveCostEstimator(Protocol):
    """Seconds to move the sensor from ``start`` to ``goal`` (both concrete); ``inf``: no path.

    Optionally also ``sensing_move_cost(start, goal) -> float``: the move to *sense* from
    ``goal``, ``inf`` when a reading there would not be the object's alone (its sound
    meets a neighbour). Optional, so not a protocol member: :func:`sensing_cost` asks.
    And optionally ``generation``, an int that changes whenever the estimator's prices
    change (the object was pushed or knocked over): work kept from one decision to the
    next on its prices is dropped when it does (:func:`estimator_generation`).
    """

    def move_cost(self, start: Position, goal: Position) -> float: ...


def estimator_generation(estimator: MoveCostEstimator) -> int:
    """The estimator's optional ``generation`` (0 without one: its prices never change)."""
    generation = getattr(estimator, "generation", 0)  # optional: see MoveCostEstimator
    return generation if isinstance(generation, int) else 0


def sensing_cost(estimator: MoveCostEstimator, start: Position, goal: Position) -> float:
    """Seconds to move to ``goal`` to *sense* there: the estimator's ``sensing_move_cost``
    where it has one, else its ``move_cost`` (the move is the same; only the reading's
    worth differs, and an estimator without the optional method knows nothing of it)."""
    priced = getattr(estimator, "sensing_move_cost", None)  # optional: one look, here only
    return priced(start, goal) if priced is not None else estimator.move_cost(start, goal)


class ModelMoveCost:
    """The knowledge file's model: straight-line travel, the turns, a fixed overhead.

    Positions are polar around the object's centre. The robot faces the object at both
    ends, so it turns towards the goal, drives, and turns back to face the object.
    """

    def __init__(self, model: MoveModel) -> None:
        self.model = model

    def move_cost(self, start: Position, goal: Position) -> float:
        if start.distance_in is None or goal.distance_in is None:
            raise ValueError(f"move cost needs concrete positions, got {start} -> {goal}")
        sx, sy = _point(start)
        gx, gy = _point(goal)
        length = math.hypot(gx - sx, gy - sy)
        if length < 1e-9:
            return 0.0
        face_start = (start.orientation_deg or 0.0) + 180.0
        face_goal = (goal.orientation_deg or 0.0) + 180.0
        travel = math.degrees(math.atan2(gy - sy, gx - sx))
        turning = abs(_wrap(travel - face_start)) + abs(_wrap(face_goal - travel))
        m = self.model
        return m.overhead_s + m.seconds_per_inch * length + m.seconds_per_degree * turning


def _point(p: Position) -> tuple[float, float]:
    theta = math.radians(p.orientation_deg or 0.0)
    d = p.distance_in or 0.0
    return d * math.cos(theta), d * math.sin(theta)


def _wrap(deg: float) -> float:
    return (deg + 180.0) % 360.0 - 180.0


# -- grasp costs learned from what grasps actually cost ------------------------------
PRIOR_WEIGHT = 3.0
"""How many attempts the knowledge file's grasp cost counts for (docs/method.md §5.7):
the learned cost moves halfway to what attempts cost after three of them."""


ROBOT_WEIGHT = 200
"""How many attempts of one grasp one robot's record may weigh in the fleet's totals
(docs/method.md §5.7): a robot that floods its grasp costs (a fault, or a robot
someone controls) moves the fleet's price at most as far as 200 attempts of its own
can, however many it sends, while an honest robot's price is as good as its 200 last
attempts make it (the prior weighs 3). Which robot sent a record is the service's key
(``csl/learner/<name>/rpc/record_grasps/<robot>``), which the router's access control
can tie to one user per robot (docs/security.md)."""

DURATION_FACTOR = 10.0
"""How far a grasp's seconds may lie from its procedure's ``time_s``, either way, before
they are implausible: milliseconds (x 1000) and minutes (/ 60) both lie beyond; the
simulator's grasps take their ``time_s`` exactly, a real arm within a few times."""


def implausible_attempt(knowledge: Knowledge, grasp: str, seconds: float, success: bool) -> str | None:
    """Why a recorded attempt of ``grasp`` costing ``seconds`` cannot be true on this
    robot, or None. An attempt costs its grasp's seconds (within :data:`DURATION_FACTOR`
    of ``time_s`` either way) and, for a failure that knocked the object over, the
    sensing that must be paid again: at most every sensing procedure the robot has,
    :data:`DURATION_FACTOR` times over. So one client cannot price a grasp for every
    robot with a day per attempt (once, 1,000 x 86,400 s were accepted). A grasp the
    profile prices at 0 s, or does not know, takes no judging."""
    if not knowledge.has_grasp(grasp):
        return None
    expected = knowledge.grasp(grasp).time_s
    if expected <= 0:
        return None
    voided = 0.0 if success else DURATION_FACTOR * sum(p.time_s for p in knowledge.sensing)
    low, high = expected / DURATION_FACTOR, expected * DURATION_FACTOR + voided
    if low <= seconds <= high:
        return None
    return (f"{seconds:g} s for a {'successful' if success else 'failed'} {grasp} is implausible: "
            f"its time_s is {expected:g} s, so {low:g} to {high:g} s")


@dataclass(frozen=True)
class GraspCostRecord:
    """What one grasping procedure has cost on this robot so far: robot seconds spent on
    the attempts that held and on those that failed, a failure's recovery included (the
    executive decides what a failure cost; the learner only adds it up)."""

    grasp: str
    successes: int = 0
    success_s: float = 0.0
    failures: int = 0
    failure_s: float = 0.0

    @property
    def attempts(self) -> int:
        return self.successes + self.failures

    def capped(self, at: int) -> GraspCostRecord:
        """This record weighing at most ``at`` attempts, each kind's mean cost and the
        share that held kept (counts rounded, seconds scaled with them): what one robot's
        record may weigh in the fleet's (:data:`ROBOT_WEIGHT`). Unchanged when it
        weighs no more; scaling again and again makes it a window over about the last
        ``at`` attempts, so a robot's share also follows a grasp that changed."""
        if self.attempts <= at:
            return self
        successes = round(self.successes * at / self.attempts)
        failures = at - successes
        return dataclasses.replace(
            self, successes=successes, failures=failures,
            success_s=self.success_s * successes / self.successes if self.successes else 0.0,
            failure_s=self.failure_s * failures / self.failures if self.failures else 0.0)

    def plus(self, other: GraspCostRecord) -> GraspCostRecord:
        """Both records' attempts together (the same grasp)."""
        return dataclasses.replace(self, successes=self.successes + other.successes,
                                   success_s=self.success_s + other.success_s,
                                   failures=self.failures + other.failures, failure_s=self.failure_s + other.failure_s)

    def with_attempt(self, seconds: float, success: bool) -> GraspCostRecord:
        """This record with one more attempt of ``seconds`` (finite, >= 0)."""
        if not (math.isfinite(seconds) and seconds >= 0):
            raise ValueError(f"grasp {self.grasp}: an attempt's cost must be a finite number >= 0, got {seconds!r}")
        if success:
            return dataclasses.replace(self, successes=self.successes + 1, success_s=self.success_s + seconds)
        return dataclasses.replace(self, failures=self.failures + 1, failure_s=self.failure_s + seconds)


def bayesian_mean(prior_s: float, total_s: float, count: int, weight: float = PRIOR_WEIGHT) -> float:
    """The mean cost with the prior counted as ``weight`` attempts of ``prior_s``:
    ``(weight * prior_s + total_s) / (weight + count)``; the prior alone with no attempt."""
    return (weight * prior_s + total_s) / (weight + count)


def with_learned_grasp_costs(knowledge: Knowledge, records: Iterable[GraspCostRecord],
                             weight: float = PRIOR_WEIGHT) -> Knowledge:
    """``knowledge`` with each recorded grasp priced by what it has cost, not by the file.

    A grasp's ``time_s`` (what a leaf's grasp costs when it holds) becomes the Bayesian
    mean of the attempts that held, and its ``failure_time_s`` (what a failure costs in
    robot seconds, side effects included) the mean of those that failed, each with the
    file's value as the prior of ``weight`` attempts. The penalty is what separates the
    two, never below 0: a failure is not priced under the grasp's own time. The failure
    harm is kept as the file sets it: it is a price on what a failure does, not seconds,
    so no number of attempts can learn it away. Everything that prices a grasp reads
    these (``feature_cost_s`` adds the harm), so ranking grasps as tests and ordering an
    ambiguous leaf's grasps both use the learned costs. A grasp with no record keeps the
    file's costs; a record of a grasp the knowledge lacks is ignored.
    """
    by_grasp = {r.grasp: r for r in records}
    grasping = []
    for g in knowledge.grasping:
        r = by_grasp.get(g.name)
        if r is None or r.attempts == 0:
            grasping.append(g)
            continue
        time_s = bayesian_mean(g.time_s, r.success_s, r.successes, weight)
        failure_s = bayesian_mean(g.failure_time_s, r.failure_s, r.failures, weight)
        grasping.append(dataclasses.replace(g, time_s=time_s, side_effect_penalty_s=max(0.0, failure_s - time_s)))
    return dataclasses.replace(knowledge, grasping=tuple(grasping),
                               source=f"{knowledge.source} (learned grasp costs)")
