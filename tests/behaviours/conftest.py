"""Shared fixtures for the per-behaviour tests (Nav2 ``RecoveryDummy`` style).

Every behaviour is ticked on its own against hand-made collaborators whose answers the
tests choose:

- :class:`FakeDriver`: each verb returns a ``Future`` scripted by the test: already
  resolved with a result, failed with a :class:`DriverError` of a chosen code, or left
  pending (:data:`PENDING`) to observe RUNNING. Calls are recorded; a verb called with
  nothing scripted fails the test (so "no driver call" is checked for free).
- :class:`FakeNavigator`: plain polar geometry around the region's centroid
  (``pose_for(region, d, o)`` is the point ``d`` inches from the centroid along bearing
  ``o``, facing it); a move costs 2 s per inch of straight line, exactly the shipped
  profile's ``[move]`` model, so the session's move costs are the paper's worked ones.
  ``plan`` finds a one-waypoint path unless the goal was blocked with :meth:`block`;
  ``observe`` returns the regions queued with :meth:`FakeNavigator.see`.
- :class:`RecordingLog`: the event sink, refusing kinds outside ``Event`` as the real
  log does.
- :func:`library`: four hand-made descriptions (cup, box, tumbler, closed box) built
  into a matrix with the shipped HERO 2000 knowledge; the decisions they lead to are
  worked out in the tests.
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import Future
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import py_trees
import pytest
from py_trees.common import Status

from behaviours.bridge import PlannerMoveCost, to_driver_pose
from behaviours.events import Event
from behaviours.records import ObjectRecord, Step, reset_blackboard
from behaviours.services import LibraryMatrix, Params, Services, namespace
from camera_model.image import CameraImage
from hero_driver.interface import DriverError, GraspResult, MoveResult, Pose as DriverPose, RobotState, SenseResult
from learner.choosing.criteria import criterion
from learner.choosing.matrix import DescriptionMatrix
from learner.choosing.node import ScoredTest
from learner.description import ObjectDescription
from learner.position import Position
from learner.runtime import RecognitionSession
from learner.service.interface import LibrarySnapshot
from planner import MoveCost, PlanResult, Pose, Region, Scene
from tests.learner.fixtures import ANY, P, desc, four_objects, hero  # noqa: F401 - the tests here take them from this module

ROBOT = "r1"
PENDING = object()  # script this to leave a verb's future pending


class FakeLearner:
    """A LearnerService holding a fixed library; ``learn`` records what it is given."""

    def __init__(self, descriptions: Sequence[ObjectDescription]) -> None:
        self.descriptions = tuple(descriptions)
        self.learned: list[ObjectDescription] = []
        self._version = 1

    def library(self) -> LibrarySnapshot:
        return LibrarySnapshot(self._version, self.descriptions)

    def version(self) -> int:
        return self._version

    def learn(self, description: ObjectDescription) -> str:
        self.learned.append(description)
        return f"{description.object_id}#{len(self.learned)}"

    def close(self) -> None:
        pass


# -- the robot -----------------------------------------------------------------------------


class FakeDriver:
    """A Driver whose verbs return futures the test scripts, one entry per call.

    ``script(verb, *outcomes)`` queues outcomes: a result (the future resolves with it),
    a :class:`DriverError` (the future fails with it) or :data:`PENDING` (the future
    stays pending; it is kept in ``pending`` for the test to resolve).
    """

    def __init__(self, robot: str = ROBOT, pose: DriverPose = DriverPose(0.0, 0.0, 0.0)) -> None:
        self.robot = robot
        self.pose = pose
        self.calls: list[tuple[Any, ...]] = []
        self.pending: list[Future[Any]] = []
        self._script: dict[str, deque[Any]] = {}

    def script(self, verb: str, *outcomes: Any) -> FakeDriver:
        self._script.setdefault(verb, deque()).extend(outcomes)
        return self

    def verbs(self) -> list[str]:
        return [c[0] for c in self.calls]

    def _answer(self, verb: str, *args: Any) -> Future[Any]:
        self.calls.append((verb, *args))
        queue = self._script.get(verb)
        if not queue:
            raise AssertionError(f"unexpected driver call {verb}{args!r}: nothing scripted")
        outcome = queue.popleft()
        future: Future[Any] = Future()
        if outcome is PENDING:
            self.pending.append(future)
        elif isinstance(outcome, BaseException):
            future.set_exception(outcome)
        else:
            future.set_result(outcome)
        return future

    def state(self) -> RobotState:
        return RobotState(self.pose, 0.0, 1.0)

    def move(self, waypoints: Sequence[DriverPose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        return self._answer("move", tuple(waypoints), face)

    def sense(self, procedure: str) -> Future[SenseResult]:
        return self._answer("sense", procedure)

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return self._answer("grasp", procedure)

    def release(self) -> Future[RobotState]:
        return self._answer("release")

    def camera(self) -> Future[CameraImage]:
        return self._answer("camera")

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        return self._answer("reset", world, seed)

    def close(self) -> None:
        self.calls.append(("close",))


class CountedLooks:
    """The looks of a test's perception: each resolves at once with its number."""

    def __init__(self) -> None:
        self.looks = 0

    def look(self) -> Future[Any]:
        self.looks += 1
        done: Future[Any] = Future()
        done.set_result(self.looks)
        return done


def blank_scene(robot: Pose | None = None) -> Scene:
    """A scene with no regions and nothing in the way, placing the robot at ``robot``."""
    return Scene(CameraImage(np.zeros((2, 2), np.uint8), 1.0, 0.0, 2.0), (), robot,
                 np.zeros((2, 2), bool), np.zeros((2, 2), bool))


def image() -> CameraImage:
    """Any overhead image: the FakeNavigator ignores its pixels."""
    return CameraImage(np.zeros((4, 4), dtype=np.uint8), 1.0, 0.0, 4.0)


# -- the planner ---------------------------------------------------------------------------


def region(x: float = 100.0, y: float = 50.0, pixels: int = 200, round_: bool = False,
           orientation: float | None = 0.0) -> Region:
    """A square footprint at (x, y): the FakeNavigator only reads its centroid."""
    corners = ((x - 2, y - 2), (x + 2, y - 2), (x + 2, y + 2), (x - 2, y + 2))
    return Region(corners, (x, y), pixels, None if round_ else orientation, round_, 4.0, 4.0)


REGION = region()
_EMPTY_MASKS = (np.zeros((1, 1), dtype=bool), np.zeros((1, 1), dtype=bool))


@dataclass
class FakeNavigator:
    """Polar geometry around a region's centroid, 2 s per inch, scripted paths and scenes."""

    seconds_per_inch: float = 2.0
    blocked: dict[tuple[float, float], str] = field(default_factory=dict)
    plans: list[tuple[Pose, Pose]] = field(default_factory=list)
    scenes: deque[tuple[Region, ...]] = field(default_factory=deque)
    observed: int = 0
    latest: tuple[Region, ...] = ()  # what the last ``observe`` found (``scene``)
    vision_map: object = None  # one map throughout: poses never change (PlannerMoveCost keeps them per map)

    def pose_for(self, region: Region, distance_in: float, orientation_deg: float) -> Pose:
        theta = math.radians(orientation_deg)
        x = region.centroid[0] + distance_in * math.cos(theta)
        y = region.centroid[1] + distance_in * math.sin(theta)
        return Pose(round(x, 6), round(y, 6), (orientation_deg + 180.0) % 360.0)

    def position_of(self, region: Region, pose: Pose) -> tuple[float, float]:
        dx, dy = pose.x_in - region.centroid[0], pose.y_in - region.centroid[1]
        return math.hypot(dx, dy), math.degrees(math.atan2(dy, dx)) % 360.0

    def move_cost(self, start: Pose, goal: Pose, *, exact: bool = False) -> MoveCost:
        length = math.hypot(goal.x_in - start.x_in, goal.y_in - start.y_in)
        return MoveCost(self.seconds_per_inch * length, length, 0.0, exact, "ok")

    def block(self, region: Region, position: Position, reason: str = "goal in collision") -> None:
        """No path to ``position`` around ``region`` from anywhere."""
        pose = self.pose_for(region, position.distance_in or 0.0, position.orientation_deg or 0.0)
        self.blocked[(pose.x_in, pose.y_in)] = reason

    def plan(self, start: Pose, goal: Pose, *, optimise: bool = False, spacing_in: float | None = None) -> PlanResult:
        self.plans.append((start, goal))
        reason = self.blocked.get((goal.x_in, goal.y_in))
        if reason is not None:
            return PlanResult(None, reason, math.inf, math.inf, "fake")
        length = math.hypot(goal.x_in - start.x_in, goal.y_in - start.y_in)
        return PlanResult((goal,), "ok", length, 0.0, "fake")

    def see(self, *regions: Region) -> FakeNavigator:
        """Queue the regions the next ``observe`` finds."""
        self.scenes.append(tuple(regions))
        return self

    def observe(self, image: Any) -> Scene:
        self.observed += 1
        self.latest = self.scenes.popleft()
        return Scene(image, self.latest, None, *_EMPTY_MASKS)

    @property
    def scene(self) -> Scene:
        """The latest scene (the beam check reads its other regions): none seen yet, no regions."""
        return Scene(None, self.latest, None, *_EMPTY_MASKS)  # type: ignore[arg-type]


def pose_at(nav: FakeNavigator, position: Position, where: Region = REGION) -> DriverPose:
    """The driver pose of a learner position around ``where``."""
    return to_driver_pose(nav.pose_for(where, position.distance_in or 0.0, position.orientation_deg or 0.0))


# -- the episode log and the clock -----------------------------------------------------------


class RecordingLog:
    """The event sink: every event as ``{"event": kind, **data}``, kinds checked."""

    def __init__(self) -> None:
        self.events: list[dict[str, object]] = []

    def event(self, kind: str, **data: object) -> None:
        self.events.append({"event": Event(kind).value, **data})

    def of(self, kind: str) -> list[dict[str, object]]:
        return [e for e in self.events if e["event"] == kind]

    def kinds(self) -> list[str]:
        return [str(e["event"]) for e in self.events]


class Clock:
    """Each reading is a quarter second after the previous: ``timed`` work costs 0.25 s."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        self.now += 0.25
        return self.now - 0.25


# -- services, records, ticking ---------------------------------------------------------------


def make_services(*, params: Params = Params(), descriptions: Sequence[ObjectDescription] | None = None,
                  driver: FakeDriver | None = None, navigator: FakeNavigator | None = None,
                  learner: FakeLearner | None = None) -> Services:
    knowledge = hero()
    learner = learner or FakeLearner(four_objects() if descriptions is None else descriptions)
    return Services(
        driver=driver or FakeDriver(), navigator=navigator or FakeNavigator(),  # type: ignore[arg-type]
        learner=learner, knowledge=knowledge, criterion=criterion("cs-id3"), params=params,
        log=RecordingLog(), library=LibraryMatrix(learner, knowledge), clock=Clock())


def put(key: str, value: object, robot: str = ROBOT) -> None:
    py_trees.blackboard.Blackboard.set(f"{namespace(robot)}/{key}", value)


def get(key: str, robot: str = ROBOT) -> Any:
    return py_trees.blackboard.Blackboard.get(f"{namespace(robot)}/{key}")


def fresh_board(robot: str = ROBOT) -> None:
    """The blackboard as the executive resets it before an episode."""
    reset_blackboard(robot)


def start_object(services: Services, *, start: Position = P(60, 0), where: Region = REGION,
                 robot: str = ROBOT, index: int = 0,
                 matrix: DescriptionMatrix | None = None) -> tuple[ObjectRecord, Step]:
    """An ObjectRecord (session opened at ``start`` on the services' library, or on
    ``matrix``) and a fresh Step, put on ``robot``'s blackboard as StartObject would."""
    estimator = PlannerMoveCost(services.navigator, where)
    session = RecognitionSession(matrix or services.library.current(), services.criterion, estimator, start,
                                 max_alternatives=services.params.max_alternatives, orientation_free=where.round)
    record = ObjectRecord(index, where, where.pixel_count, session, estimator, first_region=where)
    step = Step()
    put("object", record, robot)
    put("step", step, robot)
    put("pose", None, robot)
    return record, step


def setup(behaviour: py_trees.behaviour.Behaviour, services: Services) -> py_trees.behaviour.Behaviour:
    """``setup(services=...)`` on the behaviour and everything below it."""
    for node in behaviour.iterate():
        node.setup(services=services)
    return behaviour


def tick(behaviour: py_trees.behaviour.Behaviour, max_ticks: int = 10) -> Status:
    """Tick until the behaviour leaves RUNNING (or ``max_ticks`` ran); its status."""
    for _ in range(max_ticks):
        behaviour.tick_once()
        if behaviour.status != Status.RUNNING:
            break
    return behaviour.status


def run(behaviour: py_trees.behaviour.Behaviour, services: Services, max_ticks: int = 10) -> Status:
    """Set one behaviour up with ``services`` and tick it until it leaves RUNNING."""
    return tick(setup(behaviour, services), max_ticks)


def refused(code: str = "out_of_range", message: str = "not within range") -> DriverError:
    return DriverError(code, message)


def moved(pose: DriverPose, seconds: float = 30.0, collided: bool = False) -> MoveResult:
    return MoveResult(pose, seconds, collided, True)


@pytest.fixture(autouse=True)
def clean_blackboard() -> Iterator[None]:
    """No key, value or client survives a test."""
    py_trees.blackboard.Blackboard.clear()
    yield
    py_trees.blackboard.Blackboard.clear()


@pytest.fixture
def services() -> Services:
    return make_services()


@pytest.fixture
def driver(services: Services) -> FakeDriver:
    return services.driver  # type: ignore[return-value]


@pytest.fixture
def nav(services: Services) -> FakeNavigator:
    return services.navigator  # type: ignore[return-value]


@pytest.fixture
def log(services: Services) -> RecordingLog:
    return services.log  # type: ignore[return-value]


# -- scenario steps on the four-object library (values worked out in four_objects) -----------

WIDTH = "Width-Degree-1°(24,0)"
HEIGHT = "Height(6,*)"


def measure(record: ObjectRecord, *values: float | None) -> list[object]:
    """Follow the session's decision with each value in turn (as ApplyTest + FollowBranch
    would); the session's answers (Matched / Unreliable)."""
    answers = []
    for value in values:
        test = record.session.decide()
        assert isinstance(test, ScoredTest), test
        answers.append(record.session.observe(test, {test.test.feature: value}, test.target))
    return answers
