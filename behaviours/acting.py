"""Acting on the robot: moving to a position, applying a test, grasping.

Each is a :class:`DriverAction`: the verb runs while the behaviour reports RUNNING,
and its robot time is charged to the object's ledger when it completes.
"""

from __future__ import annotations

from concurrent.futures import Future

from py_trees.common import Status

from behaviours.base import DriverAction
from behaviours.context import GraspAttempt, Services, to_driver_pose
from hero_driver.interface import DriverError, GraspResult, MoveResult, SenseResult
from planner import PlanResult
from learner.position import Position


class MoveTo(DriverAction):
    """Plan a collision-free path to the chosen test's (or grasp's) position and drive it.

    The goal is the learner position turned into a world pose on the vision map; the
    move ends facing the object, where the driver centres on it with the sonar. A
    position with no path cannot be used: for a test that makes it unreliable here.
    """

    def __init__(self, services: Services, target: str, name: str | None = None) -> None:
        super().__init__(name or f"MoveTo {target}", services)
        if target not in ("test", "grasp"):
            raise ValueError(f"MoveTo target must be 'test' or 'grasp', got {target!r}")
        self.target = target
        self._goal: Position | None = None

    def _position(self) -> Position | None:
        obj = self.obj
        if self.target == "test":
            return obj.test.target if obj.test is not None else None
        return obj.attempt.position if obj.attempt is not None else None

    def start(self) -> Future[MoveResult] | Status:
        obj = self.obj
        goal = self._position()
        if goal is None:
            return Status.FAILURE
        self._goal = goal
        if goal == obj.session.position:
            return Status.SUCCESS  # already there: the paper's "move-to (0s)"
        plan = self._plan(goal)
        if not plan.found and self.target == "grasp":
            # A grasp approaches along an axis, and vision knows an object's reference
            # direction only up to a half turn: the other end is as good, and may be free.
            other = Position(goal.distance_in, ((goal.orientation_deg or 0.0) + 180.0) % 360.0)
            flipped = self._plan(other)
            if flipped.found:
                self.note("other_end", to=other.to_json(), instead_of=goal.to_json(), reason=plan.reason)
                assert obj.attempt is not None
                obj.attempt.position = self._goal = goal = other
                plan = flipped
        if not plan.found:
            self.note("no_path", to=goal.to_json(), reason=plan.reason)
            return self._unusable()
        return self.services.driver.move([to_driver_pose(p) for p in plan.path or ()], face=obj.region.centroid)

    def _plan(self, goal: Position) -> PlanResult:
        obj, nav = self.obj, self.services.navigator
        return obj.timed(self.services, lambda: nav.plan(
            self.services.robot_pose(), nav.pose_for(obj.region, goal.distance_in or 0.0, goal.orientation_deg or 0.0)))

    def finish(self, result: MoveResult) -> Status:
        obj = self.obj
        self.services.last_pose = result.pose
        obj.ledger.moving_s += result.duration_s
        self.note("move", to=self._goal.to_json() if self._goal else None, seconds=round(result.duration_s, 1),
                  collided=result.collided,
                  pose=[round(result.pose.x_in, 1), round(result.pose.y_in, 1), round(result.pose.heading_deg, 1)])
        if result.collided:
            return self._unusable()
        assert self._goal is not None
        obj.session.position = self._goal
        return Status.SUCCESS

    def failed(self, exc: DriverError) -> Status:
        return self._unusable()

    def _unusable(self) -> Status:
        obj = self.obj
        if self.target == "test" and obj.test is not None:
            obj.session.observe(obj.test, {obj.test.test.feature: None}, obj.session.position)
            obj.pending_unreliable = True
        elif obj.attempt is not None:
            obj.attempt.success = False  # reachable from neither end: treat it as failed
        return Status.FAILURE


class ApplyTest(DriverAction):
    """Apply the chosen test: its sensing procedure, or its grasp when a grasp is tried
    as a binary feature. A value already measured (free) needs no robot time."""

    def __init__(self, services: Services, name: str = "ApplyTest") -> None:
        super().__init__(name, services)

    def start(self) -> Future[SenseResult] | Future[GraspResult] | Status:
        obj = self.obj
        test = obj.test
        if test is None:
            return Status.FAILURE
        if test.cost == 0 and not test.test.is_grasp:
            obj.values = {}
            return Status.SUCCESS
        if test.test.is_grasp:
            obj.attempt = GraspAttempt(test.test.feature, test.target, as_feature=test)
            return self.services.driver.grasp(test.test.procedure)
        return self.services.driver.sense(test.test.procedure)

    def finish(self, result: SenseResult | GraspResult) -> Status:
        obj = self.obj
        if isinstance(result, GraspResult):
            obj.ledger.grasping_s += result.duration_s
            assert obj.attempt is not None
            obj.attempt.success = result.success
            self.note("grasp", grasp=result.procedure, as_feature=True, success=result.success,
                      seconds=round(result.duration_s, 1))
            return Status.SUCCESS
        obj.ledger.sensing_s += result.duration_s
        obj.values = dict(result.values)
        self.note("sense", procedure=result.procedure, values=_rounded(result.values),
                  seconds=round(result.duration_s, 1))
        return Status.SUCCESS

    def failed(self, exc: DriverError) -> Status:
        obj = self.obj
        if obj.test is not None and not obj.test.test.is_grasp:
            obj.values = {obj.test.test.feature: None}  # refused: no value, FollowBranch reselects
            return Status.SUCCESS
        if obj.attempt is not None:
            obj.attempt.success = False
        return Status.SUCCESS


class Grasp(DriverAction):
    """Execute the leaf's grasp; the finger infrared sensor says whether it holds.

    A grasp the finger sensor cannot confirm (No-Grab) is not executed: the robot leaves
    the object, which is that grasp's success.
    """

    def __init__(self, services: Services, name: str = "Grasp") -> None:
        super().__init__(name, services)

    def start(self) -> Future[GraspResult] | Status:
        obj = self.obj
        attempt = obj.attempt
        if attempt is None:
            return Status.FAILURE
        if not self.services.knowledge.grasp(attempt.grasp).verifiable:
            obj.outcome, obj.grasp, obj.grasp_position = "left", attempt.grasp, attempt.position
            attempt.success = True
            self.note("leave", grasp=attempt.grasp)
            return Status.SUCCESS
        return self.services.driver.grasp(attempt.grasp)

    def finish(self, result: GraspResult) -> Status:
        obj = self.obj
        assert obj.attempt is not None
        obj.ledger.grasping_s += result.duration_s
        obj.attempt.success = result.success
        self.note("grasp", grasp=result.procedure, as_feature=False, success=result.success,
                  seconds=round(result.duration_s, 1))
        if result.success:
            obj.outcome, obj.grasp, obj.grasp_position = "grasped", obj.attempt.grasp, obj.attempt.position
            return Status.SUCCESS
        return Status.FAILURE

    def failed(self, exc: DriverError) -> Status:
        if self.obj.attempt is not None:
            self.obj.attempt.success = False
        return Status.FAILURE


def _rounded(values: object) -> dict[str, float | None]:
    return {k: (None if v is None else round(float(v), 3)) for k, v in dict(values).items()}  # type: ignore[call-overload]
