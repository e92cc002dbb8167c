"""Acting on the robot: looking, moving to a position, applying a test, grasping, and
putting a learned object away.

Each is a :class:`DriverAction`: the verb runs while the behaviour reports RUNNING, and
its robot time is charged to the object's ledger when it completes.
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import Any
from dataclasses import dataclass, replace

from py_trees.common import Access, Status

from behaviours.base import DriverAction, LookAction
from behaviours.legs import LeggedMove
from behaviours.events import Event
from behaviours.records import ObjectRecord, Step
from hero_driver.interface import DriverError, GraspResult, MoveResult, Obstacle, RobotState, SenseResult
from hero_driver.interface import Pose as DriverPose  # noqa: I001 (the planner has a Pose too)
from learner.position import Position
from planner import PlanResult


class LocateObjects(LookAction):
    """Take an overhead image and queue every object region, nearest first."""

    POSE_ACCESS = Access.WRITE  # an image may correct where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, name: str = "LocateObjects") -> None:
        super().__init__(name, robot)
        self.bb.register_key("objects", access=Access.WRITE)

    def start(self) -> Future[Any]:
        return self.take_look()

    def finish(self, result: Any) -> Status:
        scene = self.look(result)
        robot = self.robot_pose()
        regions = sorted(scene.regions, key=lambda r: (math.hypot(r.centroid[0] - robot.x_in,
                                                                  r.centroid[1] - robot.y_in), r.centroid))
        self.bb.objects = list(regions)
        self.services.log.event(Event.LOCATED, behaviour=self.name, regions=[
            {"centroid": [round(c, 1) for c in r.centroid], "pixels": r.pixel_count,
             "orientation": None if r.orientation_deg is None else round(r.orientation_deg, 1)} for r in regions])
        self.feedback_message = f"{len(regions)} objects"
        return Status.SUCCESS


BLOCKED = "blocked"  # blackboard: the Blockage a move under the blocked-move branch last met (None: none)


@dataclass(frozen=True)
class Blockage:
    """A move stopped short of ``obstacle``; ``rounds`` of the blocked-move branch
    (look, re-plan or wait, retry) have been spent on this move so far."""

    obstacle: Obstacle
    rounds: int


class MoveTo(LeggedMove):
    """Plan a collision-free path to the chosen test's (or grasp's) position and drive it.

    The goal is the learner position turned into a world pose on the vision map; the
    move ends facing the object, where the driver centres on it with the sonar. A test
    position with no path (or a move that collided) is unusable: the session reselects.
    A grasp position with no path fails here and the "other end" recovery takes over; a
    grasp move that collided or was refused counts as a failed grasp. After a procedure
    was refused for range there (``ObjectRecord.off_position``), the robot is not where
    the session says, so the move is driven even to the position it believes it stands
    at (``behaviours.reapproach``).

    A move a moving obstacle stopped short (the driver's ``blocked_moves`` feature)
    fails with the obstacle on the blackboard (``BLOCKED``) for the blocked-move branch
    (``behaviours.blocked``) when this move is one of that branch's (``role``: the
    ``first`` try, a re-plan ``around`` the obstacle, a ``retry`` after waiting);
    anywhere else, or with the branch off, it counts as a collision.

    A long move is driven in legs with a look after each when the perception asks for
    it (``behaviours.legs``: the onboard scan matcher); the camera's moves are whole.
    """

    POSE_ACCESS = Access.WRITE  # a move changes where the robot stands
    ROLES = ("first", "around", "retry")

    VERB = "move"

    def __init__(self, robot: str, target: str, name: str | None = None, role: str = "first") -> None:
        super().__init__(name or f"MoveTo {target}", robot)
        if target not in ("test", "grasp"):
            raise ValueError(f"MoveTo target must be 'test' or 'grasp', got {target!r}")
        if role not in self.ROLES:
            raise ValueError(f"MoveTo role must be one of {', '.join(self.ROLES)}, got {role!r}")
        self.target, self.role = target, role
        self.in_branch = False  # set by behaviours.blocked.around_movers
        self.bb.register_key(BLOCKED, access=Access.WRITE)
        self._goal: Position | None = None

    def goal(self) -> Position | None:
        """Where to go: the step's test position, or its grasp's."""
        step = self.step
        if self.target == "test":
            return step.test.target if step.test is not None else None
        return step.attempt.position if step.attempt is not None and not step.attempt.failed else None

    def start(self) -> Future[MoveResult] | Status:
        goal = self._goal = self.goal()
        if goal is None:
            return Status.FAILURE
        if goal == self.obj.session.position and not self.obj.off_position:
            return Status.SUCCESS  # already there: the paper's "move-to (0s)"
        plan = self.plan(goal)
        if not plan.found:
            return self.no_path(goal, plan)
        return self.drive(plan)

    def plan(self, goal: Position) -> PlanResult:
        obj, nav = self.obj, self.services.navigator
        return self.timed(lambda: nav.plan(self.robot_pose(), obj.estimator.pose(goal)))

    def drive(self, plan: PlanResult) -> Future[MoveResult]:
        goal = self._goal
        return self.drive_path(plan.path or (), face=self.obj.region.centroid,
                               standoff_in=None if goal is None else goal.distance_in)

    def no_path(self, goal: Position, plan: PlanResult) -> Status:
        self.note(Event.NO_PATH, to=goal.to_json(), reason=plan.reason)
        if self.in_branch and self.role == "around":
            return Status.FAILURE  # the obstacle drawn in closes the way: wait for it instead
        self._clear_blockage()
        if self.target == "test":
            return self._unusable()
        return Status.FAILURE

    def finish(self, result: Any) -> Status:
        whole = self.leg_done(result)
        if whole is None:
            return Status.RUNNING  # the look between two legs, or the next leg
        result, obj = whole, self.obj
        self.bb.pose = result.pose
        obj.ledger.moving_s += result.duration_s
        blocked = None if result.blocked is None else [round(result.blocked.x_in, 1), round(result.blocked.y_in, 1),
                                                       round(result.blocked.radius_in, 1)]
        self.note(Event.MOVE, to=self._goal.to_json() if self._goal else None, seconds=round(result.duration_s, 1),
                  collided=result.collided, pose=pose_json(result.pose),
                  path=[pose_json(p) for p in self.sent],  # as planned: the map draws it as driven
                  **({"legs": self.legs} if self.legs > 1 else {}),
                  **({} if self.approach_in is None else {"approach_in": self.approach_in}),
                  **({} if blocked is None else {"blocked": blocked}))
        if result.blocked is not None and self.in_branch and self.services.params.blocked_tries > 0:
            return self._blockage(result.blocked)
        self._clear_blockage()
        if result.collided or result.blocked is not None:
            return self._unusable()
        assert self._goal is not None
        obj.session.position = self._goal
        obj.off_position, obj.arrived = False, result.pose
        return Status.SUCCESS


    def failed(self, exc: DriverError) -> Status:
        self._clear_blockage()
        return self._unusable()

    def _blockage(self, obstacle: Obstacle) -> Status:
        """Stopped short of a moving obstacle: the branch takes over (rounds carried on)."""
        before = self.bb.get(BLOCKED) if self.role != "first" and self.bb.exists(BLOCKED) else None
        self.bb.set(BLOCKED, Blockage(obstacle, 0 if before is None else before.rounds))
        return Status.FAILURE

    def _clear_blockage(self) -> None:
        self.bb.set(BLOCKED, None)

    def _unusable(self) -> Status:
        step = self.step
        if self.target == "test" and step.test is not None:
            self.obj.session.unusable(step.test)
        elif step.attempt is not None:
            step.attempt = replace(step.attempt, success=False)  # cannot be reached: a failed grasp
        return Status.FAILURE



def count_verb_failed(step: Step, obj: ObjectRecord, grasp: bool) -> None:
    """A verb the robot refused or failed, as the recoveries read it: the step's grasp
    (executed, or tried as a feature) failed; a sensing test is unusable here, so the
    next choice reselects. Shared by the actions and by ``RefusedForRange?`` when it
    counts a refusal for range as the verb failing."""
    if grasp:
        assert step.attempt is not None
        step.attempt = replace(step.attempt, success=False)
    else:
        assert step.test is not None
        obj.session.unusable(step.test)

class ApplyTest(DriverAction):
    """Apply the chosen test: its sensing procedure, or its grasp when a grasp is tried
    as a binary feature. A value already measured (free) needs no robot time."""

    VERB = "sense"

    def __init__(self, robot: str, name: str = "ApplyTest") -> None:
        super().__init__(name, robot)

    def verb(self) -> str:
        test = self.step.test
        return "grasp" if test is not None and test.test.is_grasp else "sense"

    def start(self) -> Future[SenseResult] | Future[GraspResult] | Status:
        step = self.step
        test = step.test
        if test is None:
            return Status.FAILURE
        if test.test.is_grasp:
            return self.services.driver.grasp(test.test.procedure)
        if test.cost == 0:
            step.values = {}
            return Status.SUCCESS
        return self.services.driver.sense(test.test.procedure)

    def finish(self, result: SenseResult | GraspResult) -> Status:
        obj, step = self.obj, self.step
        if isinstance(result, GraspResult):
            obj.ledger.grasping_s += result.duration_s
            assert step.attempt is not None
            step.attempt = replace(step.attempt, success=result.success)
            self.note(Event.GRASP, grasp=result.procedure, as_feature=True, success=result.success,
                      seconds=round(result.duration_s, 1))
            return Status.SUCCESS
        obj.ledger.sensing_s += result.duration_s
        step.values = dict(result.values)
        self.note(Event.SENSE, procedure=result.procedure, values=_rounded(result.values),
                  seconds=round(result.duration_s, 1))
        return Status.SUCCESS

    def failed(self, exc: DriverError) -> Status:
        step = self.step
        assert step.test is not None
        grasp = step.test.test.is_grasp
        if self.refused_for_range(exc, step.test.test.procedure, grasp):
            return Status.FAILURE  # nothing tried: the re-approach branch judges (behaviours.reapproach)
        count_verb_failed(step, self.obj, grasp)
        return Status.SUCCESS if grasp else Status.FAILURE  # a grasp: FollowBranch fails on it, recovery looks


class Grasp(DriverAction):
    """Execute the leaf's grasp; the finger infrared sensor says whether it holds.

    A grasp the finger sensor cannot confirm (No-Grab) is not executed: the robot leaves
    the object, which is that grasp's success.
    """

    VERB = "grasp"

    def __init__(self, robot: str, name: str = "Grasp") -> None:
        super().__init__(name, robot)

    def start(self) -> Future[GraspResult] | Status:
        step, obj = self.step, self.obj
        attempt = step.attempt
        if attempt is None or attempt.failed:
            return Status.FAILURE
        if not self.services.knowledge.grasp(attempt.grasp).verifiable:
            obj.finish("left", attempt.grasp, attempt.position)
            step.attempt = replace(attempt, success=True)
            self.note(Event.LEAVE, grasp=attempt.grasp)
            return Status.SUCCESS
        return self.services.driver.grasp(attempt.grasp)

    def finish(self, result: GraspResult) -> Status:
        obj, step = self.obj, self.step
        assert step.attempt is not None
        obj.ledger.grasping_s += result.duration_s
        attempt = step.attempt = replace(step.attempt, success=result.success)
        self.note(Event.GRASP, grasp=result.procedure, as_feature=False, success=result.success,
                  seconds=round(result.duration_s, 1))
        if result.success:
            obj.finish("grasped", attempt.grasp, attempt.position)
            return Status.SUCCESS
        return Status.FAILURE

    def failed(self, exc: DriverError) -> Status:
        attempt = self.step.attempt
        if attempt is not None and not self.refused_for_range(exc, attempt.grasp, True):
            count_verb_failed(self.step, self.obj, grasp=True)
        return Status.FAILURE


class Learn(DriverAction):
    """Save the new object description after a successful grasp (with every feature
    measured, discriminating ones included) and put the object away. Nothing is saved
    for a cluster: its grasps were tried on touching objects, not on the one held.

    An object held with nothing sensed is saved by its appearance and grasp when the
    library was wrong about it (a grasp failed first): that is a lesson, and without it
    the next object like it fails the same grasps (docs/method.md §5.3, §5.8); its event
    says ``by="appearance"``. The grasps tried as features are not features of it (they
    say what the object is not, which the grasp that held already says). One the camera's
    appearance alone got right first time teaches nothing new and is not saved: with no
    sensed value it would be unknown on every test, follow every branch of every later
    tree, and leave an ambiguous leaf for every later object that looks alike. Nor is a
    lesson the camera gave no appearance for: a description with neither a feature nor
    an appearance could never be told apart from anything. Each unsaved object's event
    says why."""

    VERB = "release"

    def __init__(self, robot: str, name: str = "Learn") -> None:
        super().__init__(name, robot)

    def start(self) -> Future[RobotState] | Status:
        obj = self.obj
        if obj.outcome == "left":
            return Status.SUCCESS
        if obj.outcome != "grasped" or obj.grasp is None or obj.grasp_position is None:
            return Status.FAILURE
        description = obj.session.description(f"learned/{obj.grasp}", obj.grasp, obj.grasp_position)
        if obj.clustered:  # what was tried on touching objects is no one object's
            self.note(Event.LEARN, id=None, grasp=obj.grasp, features=0, reason="a cluster of touching objects")
        elif description.observations:
            obj.learned_id = self.timed(lambda: self.services.learner.learn(description))
            self.note(Event.LEARN, id=obj.learned_id, grasp=obj.grasp, features=len(description.observations),
                      wrong=list(obj.session.wrong_predictions))
        elif not obj.session.wrong_predictions:
            self.note(Event.LEARN, id=None, grasp=obj.grasp, features=0,
                      reason="nothing was measured and no grasp failed: nothing to learn")
        elif description.appearance is None:
            self.note(Event.LEARN, id=None, grasp=obj.grasp, features=0,
                      reason="nothing was measured and the camera gave no appearance: it would match every object")
        else:  # a lesson with nothing sensed: its appearance is what tells it apart
            obj.learned_id = self.timed(lambda: self.services.learner.learn(description))
            self.note(Event.LEARN, id=obj.learned_id, grasp=obj.grasp, features=0, by="appearance",
                      wrong=list(obj.session.wrong_predictions))
        return self.services.driver.release()

    def finish(self, result: RobotState) -> Status:
        return Status.SUCCESS


def pose_json(pose: DriverPose) -> list[float]:
    """A pose as the log writes it: ``[x_in, y_in, heading_deg]`` to a tenth."""
    return [round(pose.x_in, 1), round(pose.y_in, 1), round(pose.heading_deg, 1)]


def _rounded(values: object) -> dict[str, float | None]:
    return {k: (None if v is None else round(float(v), 3)) for k, v in dict(values).items()}  # type: ignore[call-overload]
