"""Following the run-time tree: the best test at a fresh node, the branch its value
matches, and the grasp at a leaf (docs/method.md §5, Table 7 steps 1-2).

What to do when this fails (reselection, backtracking, nearest neighbour, an ambiguous
leaf, a failed grasp) is in :mod:`behaviours.recovery`.
"""

from __future__ import annotations

import math

from py_trees.common import Status

from behaviours.base import CslBehaviour
from behaviours.bridge import other_end
from behaviours.events import Event
from behaviours.records import GraspAttempt
from learner.choosing.leaf import GraspLeaf
from learner.choosing.node import ScoredTest
from learner.position import Position
from learner.runtime import Decision, Matched


class Choose(CslBehaviour):
    """A behaviour that asks the session what to do and may choose the step's test."""

    def decide(self) -> Decision:
        return self.timed(self.obj.session.decide)

    def nearest_due(self) -> bool:
        """The parameter saying how soon to switch to nearest neighbour has been reached
        (and nearest neighbour can act: a dropout leaves no value to be near to)."""
        after = self.services.params.nearest_after
        session = self.obj.session
        return after is not None and session.unreliable_count >= after and session.can_follow_nearest

    def chose(self, test: ScoredTest, how: str) -> Status:
        """The step's test; a grasp tried as a feature is also the step's grasp attempt."""
        step = self.step
        step.test = test
        if test.test.is_grasp:
            step.attempt = GraspAttempt(test.test.feature, test.target, as_feature=test)
        self.feedback_message = str(test.test)
        self.note(Event.CHOOSE, how=how, test=str(test.test), at=test.target.to_json(),
                  gain=round(test.gain, 4), move_s=round(test.move_cost, 1), sense_s=round(test.sense_cost, 1))
        return Status.SUCCESS

    def chose_grasp(self, leaf: GraspLeaf, how: str, candidates: tuple[str, ...] | None = None) -> Status:
        """Attempt ``leaf``'s grasp; ``candidates``: the descriptions it is chosen among,
        when they are not the session's node (an ambiguous leaf offered after a guess)."""
        position, move_s = self.reachable_end(leaf.position, leaf.move_cost)
        self.step.attempt = GraspAttempt(leaf.grasp, position)
        self.feedback_message = f"{leaf.grasp}{position}"
        self.note(Event.CHOOSE_GRASP, how=how, grasp=leaf.grasp, at=position.to_json(),
                  move_s=round(move_s, 1), candidates=list(candidates or self.obj.session.candidates))
        return Status.SUCCESS

    def reachable_end(self, position: Position, move_s: float) -> tuple[Position, float]:
        """The grasp position, or its other end when the planner has no path to it and
        has one there (vision knows the object's reference direction only up to a half
        turn, so both ends are as good): the robot then drives to the free end at once
        instead of failing a plan first (``OtherEnd`` stays the recovery for a plan that
        fails when driven)."""
        if math.isfinite(move_s) or position.orientation_deg is None:
            return position, move_s
        flipped = other_end(position)
        flipped_s = self.obj.estimator.move_cost(self.obj.session.position, flipped)
        return (flipped, flipped_s) if math.isfinite(flipped_s) else (position, move_s)


class BestTest(Choose):
    """At a node with no unreliable value yet: the best-scoring test."""

    def __init__(self, robot: str, name: str = "BestTest") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        if self.obj.session.awaiting_reselection:
            return Status.FAILURE
        decision = self.decide()
        if isinstance(decision, ScoredTest):
            return self.chose(decision, "best")
        return Status.FAILURE


class FollowBranch(CslBehaviour):
    """Follow the branch the measured value matches. Fails when the value is unreliable
    (between or beyond the branches), or when a grasp tried as a feature failed (the
    recovery branch then checks for side effects)."""

    def __init__(self, robot: str, name: str = "FollowBranch") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        obj, step = self.obj, self.step
        test = step.test
        if test is None:
            return Status.FAILURE
        if test.test.is_grasp:
            if step.attempt is None or not step.attempt.success:
                if step.attempt is not None and step.attempt.success is False:  # tried: a test with value 0
                    obj.ledger.tests.append(f"{test.test}=0")
                return Status.FAILURE
            obj.session.grasp_as_feature(test, True, test.target)
            obj.finish("grasped", test.test.feature, test.target)
            obj.ledger.tests.append(f"{test.test}=1")
            return Status.SUCCESS
        result = self.timed(lambda: obj.session.observe(test, step.values or {}, test.target))
        value = getattr(result, "value", None)
        if test.cost > 0:  # a free re-use of a value measured earlier is not a new test
            obj.ledger.tests.append(f"{test.test}={'-' if value is None else round(value, 2)}")
        if isinstance(result, Matched):
            self.note(Event.BRANCH, test=str(test.test), value=value, range=list(result.range))
            return Status.SUCCESS
        self.note(Event.UNRELIABLE, test=str(test.test), value=value, ranges=[list(r) for r in test.ranges])
        return Status.FAILURE


class ChooseGrasp(Choose):
    """At a leaf: its grasp (Table 7 step 1)."""

    def __init__(self, robot: str, name: str = "ChooseGrasp") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        decision = self.decide()
        if isinstance(decision, GraspLeaf):
            return self.chose_grasp(decision, "leaf")
        return Status.FAILURE
