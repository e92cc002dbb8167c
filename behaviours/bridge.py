"""Conversions between the driver's, the planner's and the learner's views of space
(the overhead image needs none: driver and planner share ``camera_model.image``).

The driver speaks world poses, the planner its own poses and regions, the learner
positions relative to the object (``docs/conventions.md``). These are the only places
where one becomes another, so behaviours and tests import them instead of re-typing
them.
"""

from __future__ import annotations

import math

from hero_driver.interface import Pose as DriverPose
from learner.position import Position
from planner import Navigator, Pose as PlannerPose, Region
from planner.positions import beam_blockers, neighbours


def to_planner_pose(p: DriverPose) -> PlannerPose:
    return PlannerPose(p.x_in, p.y_in, p.heading_deg)


def to_driver_pose(p: PlannerPose) -> DriverPose:
    return DriverPose(p.x_in, p.y_in, p.heading_deg)


def relative_position(navigator: Navigator, region: Region, pose: PlannerPose) -> Position:
    """Where a robot pose stands relative to an object, in the learner's terms (rounded)."""
    d, o = navigator.position_of(region, pose)
    return Position(round(max(d, 0.0), 1), round(o, 1) % 360.0)


def other_end(position: Position) -> Position:
    """The same approach from the opposite side: vision knows an object's reference
    direction only up to a half turn, so a grasp there is as good."""
    return Position(position.distance_in, ((position.orientation_deg or 0.0) + 180.0) % 360.0)


class PlannerMoveCost:
    """The learner's move-cost estimator on the planner's vision map, for one object.

    Positions relative to the object become world poses (docs/conventions.md); the
    estimate mode of the planner prices them in milliseconds. Cached per pair: the
    learner prices the same few positions again at every node.

    With ``beam_check`` a move to *sense* from a position whose sonar corridor meets
    another region of the latest image (``BeamClear?``'s own test, behaviours/clutter.py),
    or to sense a cluster at all, is priced ``inf``: the learner never picks such a test,
    instead of picking it and having ``BeamClear?`` refuse it. ``same_within_in`` is
    :data:`~behaviours.sameness.PUSHED_IN`: a region that near the object's centroid is the object itself.

    A learner position names where the sonar stands, not which way the robot faces, so
    the pose made from it faces the object. Where the robot really stands (the start of
    an object, a resume) it need not: its base is up to twice the sonar's offset away
    from that pose, which can lie inside an obstacle the real robot is clear of, and
    every move from it would be priced ``inf``. :meth:`stand_at` records the real pose
    for the position it returns, and moves from that position are priced from it (a
    move *to* a position still ends facing the object).

    The pose of each position is worked out once per vision map (:meth:`pose`): the
    exact rule prices every move between the positions its search explores, and each
    move names two poses, whose working out (the face's distance along the ray, the
    range tolerance's steps around an obstacle) is dearer than the price itself.
    """

    def __init__(self, navigator: Navigator, region: Region, beam_check: bool = False,
                 same_within_in: float = 1.0) -> None:
        self.navigator, self.region = navigator, region
        self.beam_check, self.same_within_in = beam_check, same_within_in
        self._cache: dict[tuple[Position, Position], float] = {}
        self._blocked: dict[Position, bool] = {}
        self._stood: dict[Position, PlannerPose] = {}
        self._poses: dict[Position, PlannerPose] = {}
        self._posed_on: object = None  # the vision map ``_poses`` were worked out on
        self.generation = 0  # learner.costs.MoveCostEstimator: changes with every retarget

    def retarget(self, region: Region) -> None:
        """The object moved (pushed, knocked over): price positions around where it is now.
        ``generation`` changes, so the learner's searches that keep prices from one
        decision to the next start afresh instead of choosing on the old ones."""
        self.region = region
        self.generation += 1
        self._cache.clear()
        self._blocked.clear()
        self._stood.clear()
        self._poses.clear()

    def stand_at(self, pose: PlannerPose) -> Position:
        """The learner position of the robot standing at ``pose``; moves from it are
        priced from ``pose`` itself, whichever way the robot faces."""
        here = relative_position(self.navigator, self.region, pose)
        self._stood[here] = pose
        self._cache = {key: cost for key, cost in self._cache.items() if key[0] != here}
        return here

    def move_cost(self, start: Position, goal: Position) -> float:
        key = (start, goal)
        if key not in self._cache:
            self._cache[key] = 0.0 if start == goal else \
                self.navigator.move_cost(self._stood.get(start) or self.pose(start), self.pose(goal)).seconds
        return self._cache[key]

    def sensing_move_cost(self, start: Position, goal: Position) -> float:
        """``move_cost``, or ``inf`` when a reading from ``goal`` would not be the object's alone."""
        return math.inf if self.beam_check and self.beam_blocked(goal) else self.move_cost(start, goal)

    def beam_blocked(self, position: Position) -> bool:
        """True when the sound from ``position`` would meet another object first (or the
        object is a cluster, its neighbour inside it). Cached per position; a new image
        of the scene is seen at the next ``retarget``."""
        if position not in self._blocked:
            others = neighbours(self.region, self.navigator.scene.regions, self.same_within_in)
            self._blocked[position] = self.region.cluster or bool(beam_blockers(
                self.region, position.distance_in or 0.0, position.orientation_deg or 0.0, others))
        return self._blocked[position]

    def pose(self, position: Position) -> PlannerPose:
        """The world pose from which the sonar stands at ``position`` facing the object
        (kept until the object moves or the map changes: the pose steps around obstacles
        on the map it was worked out on)."""
        on = self.navigator.vision_map
        if on is not self._posed_on:
            self._poses.clear()
            self._posed_on = on
        found = self._poses.get(position)
        if found is None:
            found = self._poses[position] = self.navigator.pose_for(
                self.region, position.distance_in or 0.0, position.orientation_deg or 0.0)
        return found
