"""What the behaviours share: the services they call and the record of each object.

Services (the driver, the planner's navigator, the learner handle) are injected into
each behaviour's constructor: they are dependencies, not data. Data that flows between
behaviours (the objects found, the object at hand with its run-time tree and ledger)
lives on the blackboard under the executive's namespace, with keys declared in each
behaviour's ``__init__`` as py_trees intends.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Protocol

from hero_driver.interface import Driver, Pose as DriverPose
from learner.criteria import Criterion
from learner.knowledge import Knowledge
from learner.matrix import DescriptionMatrix
from learner.position import Position
from learner.runtime import RecognitionSession
from learner.service.interface import LearnerService
from learner.selection import ScoredTest
from planner import Navigator, Pose as PlannerPose, Region

NAMESPACE = "/csl"


@dataclass(frozen=True)
class Params:
    """The control strategies' knobs (method.md §5)."""

    max_alternatives: int = 3  # N: alternatives tried at a node before backtracking
    nearest_after: int | None = None  # unreliable values before nearest neighbour; None: last resort
    max_steps: int = 40  # recognition steps per object before giving up
    changed_ratio: float = 0.25  # pixel-count change after a failed grasp meaning "changed"
    pushed_in: float = 1.0  # centroid shift meaning "pushed"


class EventSink(Protocol):
    """Where behaviours report what they decided, measured and paid (the episode log)."""

    def event(self, kind: str, **data: object) -> None: ...


@dataclass
class Services:
    """Everything a behaviour may call, shared by the whole tree."""

    driver: Driver
    navigator: Navigator
    learner: LearnerService
    knowledge: Knowledge
    criterion: Criterion
    params: Params
    log: EventSink
    clock: Callable[[], float] = time.perf_counter
    last_pose: DriverPose | None = None  # from the latest move result: fresher than state()
    _matrix: tuple[int, DescriptionMatrix] | None = None

    @property
    def namespace(self) -> str:
        """Blackboard namespace of this robot's tree (two robots never share keys)."""
        return f"{NAMESPACE}/{self.driver.robot}"

    def matrix(self) -> DescriptionMatrix:
        """The library as a matrix, rebuilt only when the library's version changed."""
        version = self.learner.version()
        if self._matrix is None or self._matrix[0] != version:
            snapshot = self.learner.library()
            self._matrix = (snapshot.version, DescriptionMatrix(snapshot.descriptions, self.knowledge))
        return self._matrix[1]

    def robot_pose(self) -> PlannerPose:
        """Where the robot is: the end of its last move, else what the driver reports."""
        return to_planner_pose(self.last_pose or self.driver.state().pose)


@dataclass
class Ledger:
    """Robot seconds by kind for one object, and the computation spent choosing."""

    moving_s: float = 0.0
    sensing_s: float = 0.0
    grasping_s: float = 0.0
    computing_s: float = 0.0  # wall seconds in the learner and planner
    tests: list[str] = field(default_factory=list)
    recoveries: Counter[str] = field(default_factory=Counter)

    @property
    def robot_s(self) -> float:
        return self.moving_s + self.sensing_s + self.grasping_s


@dataclass
class GraspAttempt:
    """A grasp tried in the current step: at a leaf, as an option, or as a feature."""

    grasp: str
    position: Position
    as_feature: ScoredTest | None = None
    success: bool | None = None


@dataclass
class ObjectRecord:
    """One object being approached and recognized: its region, tree, and costs."""

    index: int
    region: Region
    pixels_before: int
    session: RecognitionSession
    estimator: PlannerMoveCost
    first_region: Region | None = None  # where it was first seen (region follows it when pushed)
    ledger: Ledger = field(default_factory=Ledger)
    outcome: str | None = None  # grasped | left | failed
    grasp: str | None = None
    grasp_position: Position | None = None
    learned_id: str | None = None
    steps: int = 0
    test: ScoredTest | None = None  # the test chosen this step
    values: Mapping[str, float | None] | None = None  # what the last procedure yielded
    pending_unreliable: bool = False  # the current node's last value was not trusted
    unreliable_count: int = 0
    no_alternative: bool = False  # choosing a test failed at this node this step
    attempt: GraspAttempt | None = None
    side_effect: str | None = None  # what the camera saw after a failed grasp

    @property
    def done(self) -> bool:
        return self.outcome is not None

    def timed(self, services: Services, fn: Callable[[], Any]) -> Any:
        """Run learner or planner work, charging its wall time to computation."""
        start = services.clock()
        try:
            return fn()
        finally:
            self.ledger.computing_s += services.clock() - start


def to_planner_pose(p: DriverPose) -> PlannerPose:
    return PlannerPose(p.x_in, p.y_in, p.heading_deg)


def to_driver_pose(p: PlannerPose) -> DriverPose:
    return DriverPose(p.x_in, p.y_in, p.heading_deg)


class PlannerMoveCost:
    """The learner's move-cost estimator on the planner's vision map, for one object.

    Positions relative to the object become world poses (docs/conventions.md); the
    estimate mode of the planner prices them in milliseconds. Cached per pair: the
    learner prices the same few positions again at every node.
    """

    def __init__(self, navigator: Navigator, region: Region) -> None:
        self.navigator, self.region = navigator, region
        self._cache: dict[tuple[Position, Position], float] = {}

    def retarget(self, region: Region) -> None:
        """The object moved (pushed, knocked over): price positions around where it is now."""
        self.region = region
        self._cache.clear()

    def move_cost(self, start: Position, goal: Position) -> float:
        key = (start, goal)
        if key not in self._cache:
            if start == goal:
                self._cache[key] = 0.0
            else:
                a = self.pose(start)
                b = self.pose(goal)
                self._cache[key] = self.navigator.move_cost(a, b).seconds
        return self._cache[key]

    def pose(self, position: Position) -> PlannerPose:
        assert position.distance_in is not None
        return self.navigator.pose_for(self.region, position.distance_in, position.orientation_deg or 0.0)


def relative_position(navigator: Navigator, region: Region, pose: PlannerPose) -> Position:
    """Where a robot pose stands relative to an object, in the learner's terms (rounded)."""
    d, o = navigator.position_of(region, pose)
    return Position(round(max(d, 0.0), 1), round(o, 1) % 360.0)


