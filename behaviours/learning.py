"""Following the tree, recovering from failed grasps, and learning from the outcome."""

from __future__ import annotations

from concurrent.futures import Future

from py_trees.common import Status

from behaviours.base import CslBehaviour, DriverAction
from behaviours.context import Services, relative_position
from hero_driver.interface import DriverError, RobotState, SenseResult
from learner.runtime import Matched
from learner.matrix import Test
from learner.selection import ScoredTest


class FollowBranch(CslBehaviour):
    """Follow the branch the measured value matches. Fails when the value is unreliable
    (between or beyond the branches), or when a grasp tried as a feature failed (the
    recovery branch then checks for side effects)."""

    def __init__(self, services: Services, name: str = "FollowBranch") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        obj = self.obj
        test = obj.test
        if test is None:
            return Status.FAILURE
        if test.test.is_grasp:
            attempt = obj.attempt
            if attempt is None or not attempt.success:
                return Status.FAILURE
            obj.session.grasp_as_feature(test, True, test.target)
            obj.outcome, obj.grasp, obj.grasp_position = "grasped", test.test.feature, test.target
            obj.ledger.tests.append(f"{test.test}=1")
            return Status.SUCCESS
        result = obj.timed(self.services, lambda: obj.session.observe(test, obj.values or {}, test.target))
        value = getattr(result, "value", None)
        if test.cost > 0:  # a free re-use of a value measured earlier is not a new test
            obj.ledger.tests.append(f"{test.test}={'-' if value is None else round(value, 2)}")
        if isinstance(result, Matched):
            obj.pending_unreliable = False
            self.note("branch", test=str(test.test), value=value, range=list(result.range))
            return Status.SUCCESS
        obj.pending_unreliable = True
        obj.unreliable_count += 1
        self.note("unreliable", test=str(test.test), value=value,
                  ranges=[list(r) for r in test.ranges])
        return Status.FAILURE


class StartOver(CslBehaviour):
    """A failed grasp had side effects: restore every description and start over from
    here; if the object changed, everything sensed so far is void too."""

    def __init__(self, services: Services, name: str = "StartOver") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        obj = self.obj
        if obj.attempt is None or obj.side_effect is None:
            return Status.FAILURE
        here = relative_position(self.services.navigator, obj.region, self.services.robot_pose())
        changed = obj.side_effect == "changed"
        obj.session.grasp_failed(obj.attempt.grasp, side_effects=True, changed=changed, position=here)
        if changed:
            obj.unreliable_count = 0  # a new object as far as sensing goes
        obj.ledger.recoveries["start over (changed)" if changed else "start over (pushed)"] += 1
        self.note("start_over", changed=changed, at=here.to_json())
        obj.attempt, obj.side_effect, obj.pending_unreliable = None, None, False
        return Status.SUCCESS


class DropFailedGrasp(CslBehaviour):
    """A grasp failed without side effects. Tried as a feature: follow its 'failure'
    branch. At a leaf: drop the descriptions labelled with it and rebuild from the
    current position, keeping every value measured."""

    def __init__(self, services: Services, name: str = "DropFailedGrasp") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        obj = self.obj
        attempt = obj.attempt
        if attempt is None or attempt.success is not False:
            return Status.FAILURE
        if attempt.as_feature is not None:
            obj.session.grasp_as_feature(attempt.as_feature, False, attempt.position)
            obj.ledger.recoveries["grasp feature failed"] += 1
            self.note("grasp_feature_failed", grasp=attempt.grasp)
            obj.attempt = None
            return Status.SUCCESS
        try:
            obj.timed(self.services, lambda: obj.session.grasp_failed(attempt.grasp, side_effects=False))
        except ValueError:
            obj.outcome = "failed"
            self.note("gave_up", reason="every grasp in the library failed")
            return Status.SUCCESS
        obj.ledger.recoveries["drop failed grasp"] += 1
        obj.pending_unreliable = False  # a new tree: no value awaits reselection there
        self.note("drop_grasp", grasp=attempt.grasp, candidates=list(obj.session.candidates))
        return Status.SUCCESS


class Discriminate(DriverAction):
    """After a wrong prediction, measure until the object is told apart from the wrongly
    predicted grasp's descriptions (method.md §5.3, "discriminating features added"):
    the cheapest feature they have and this object lacks, here where the robot stands,
    then the next, until a value falls outside theirs or nothing is left to measure here.
    Each procedure is one driver verb; the behaviour stays RUNNING between them."""

    def __init__(self, services: Services, name: str = "Discriminate") -> None:
        super().__init__(name, services)
        self._test: ScoredTest | None = None
        self._wrong: str | None = None
        self._tried: set[Test] = set()

    def start(self) -> Future[SenseResult] | Status:
        obj = self.obj
        attempt = obj.attempt
        obj.attempt = None
        self._tried = set()
        if attempt is None or attempt.as_feature is not None or obj.done:
            return Status.SUCCESS
        if obj.timed(self.services, lambda: obj.session.told_apart(attempt.grasp)):
            self.note("discriminate", already=True, wrong=attempt.grasp)
            return Status.SUCCESS  # what was measured already tells the two apart
        self._wrong = attempt.grasp
        return self._next()

    def _next(self) -> Future[SenseResult] | Status:
        obj = self.obj
        assert self._wrong is not None
        wrong, tried = self._wrong, frozenset(self._tried)
        self._test = obj.timed(self.services, lambda: obj.session.discriminating_test(wrong, tried))
        if self._test is None or self._test.move_cost > 0:
            return Status.SUCCESS  # nothing left to add from here; moving for it is not worth it
        self._tried.add(self._test.test)  # each test once: a dropout is not retried forever
        return self.services.driver.sense(self._test.test.procedure)

    def finish(self, result: SenseResult) -> Status:
        obj = self.obj
        assert self._test is not None and self._wrong is not None
        obj.ledger.sensing_s += result.duration_s
        obj.session.record(result.values, self._test.target)
        told_apart = obj.session.discriminates(self._test, self._wrong)
        self.note("discriminate", procedure=result.procedure, values={k: v for k, v in result.values.items()},
                  seconds=round(result.duration_s, 1), told_apart=told_apart)
        if told_apart or result.values.get(self._test.test.feature) is None:
            return Status.SUCCESS  # told apart, or the sonar gave nothing: leave it there
        nxt = self._next()
        if isinstance(nxt, Status):
            return nxt
        self._future = nxt  # the next procedure, watched by update()
        return Status.RUNNING

    def failed(self, exc: DriverError) -> Status:
        return Status.SUCCESS  # a discriminating value is a bonus, not a requirement


class Learn(DriverAction):
    """Save the new object description after a successful grasp (with every feature
    measured, discriminating ones included) and put the object away."""

    def __init__(self, services: Services, name: str = "Learn") -> None:
        super().__init__(name, services)

    def start(self) -> Future[RobotState] | Status:
        obj = self.obj
        if obj.outcome == "left":
            return Status.SUCCESS
        if obj.outcome != "grasped" or obj.grasp is None or obj.grasp_position is None:
            return Status.FAILURE
        description = obj.session.description(f"learned/{obj.grasp}", obj.grasp, obj.grasp_position)
        if description.observations:  # a description with no features would match anything
            obj.learned_id = obj.timed(self.services, lambda: self.services.learner.learn(description))
            self.note("learn", id=obj.learned_id, grasp=obj.grasp, features=len(description.observations),
                      wrong=list(obj.session.wrong_predictions))
        else:
            self.note("learn", id=None, grasp=obj.grasp, features=0, reason="nothing was measured")
        return self.services.driver.release()

    def finish(self, result: RobotState) -> Status:
        return Status.SUCCESS
