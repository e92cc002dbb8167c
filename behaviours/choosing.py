"""Choosing what to do next at the current node of the run-time tree.

Each control strategy of method.md §5 is its own behaviour, so the behaviour tree shows
which one acted: the best test at a fresh node; *reselection* of the next-best test
after an unreliable value; *backtracking* to choose differently at the parent; the
*nearest neighbour* branch as the last resort; and the grasp at a leaf (an ambiguous
leaf's grasps tried cheapest first).
"""

from __future__ import annotations

from py_trees.common import Status

from behaviours.base import CslBehaviour
from behaviours.context import GraspAttempt, Services
from learner.runtime import Decision, Exhausted
from learner.selection import ScoredTest
from learner.tree import AmbiguousLeaf, GraspLeaf


class _Choose(CslBehaviour):
    def decide(self) -> Decision:
        obj = self.obj
        return obj.timed(self.services, obj.session.decide)

    def nearest_now(self) -> bool:
        """The parameter saying how soon to switch to nearest neighbour has been reached
        (and nearest neighbour can act: a dropout leaves no value to be near to)."""
        after = self.services.params.nearest_after
        return after is not None and self.obj.unreliable_count >= after and self.obj.session.can_follow_nearest

    def chose(self, test: ScoredTest, how: str) -> Status:
        obj = self.obj
        obj.test = test
        obj.pending_unreliable = False
        self.feedback_message = str(test.test)
        self.note("choose", how=how, test=str(test.test), at=test.target.to_json(),
                  gain=round(test.gain, 4), move_s=round(test.move_cost, 1), sense_s=round(test.sense_cost, 1))
        return Status.SUCCESS


class BestTest(_Choose):
    """At a node with no unreliable value yet: the best-scoring test."""

    def __init__(self, services: Services, name: str = "BestTest") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        if self.obj.pending_unreliable:
            return Status.FAILURE
        decision = self.decide()
        if isinstance(decision, ScoredTest):
            return self.chose(decision, "best")
        return Status.FAILURE


class Reselect(_Choose):
    """After an unreliable value: the next-best test at the same node (up to N)."""

    def __init__(self, services: Services, name: str = "Reselect") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        if not self.obj.pending_unreliable or self.nearest_now():
            return Status.FAILURE
        decision = self.decide()
        if isinstance(decision, ScoredTest):
            self.obj.ledger.recoveries["reselect"] += 1
            return self.chose(decision, "reselect")
        return Status.FAILURE


class Backtrack(_Choose):
    """No reliable test left here (or N tried): invalidate the parent's value and choose
    a different test there; repeatable up to the root."""

    def __init__(self, services: Services, name: str = "Backtrack") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        obj = self.obj
        if self.nearest_now() or not isinstance(self.decide(), Exhausted):
            return Status.FAILURE
        while obj.session.backtrack():
            obj.ledger.recoveries["backtrack"] += 1
            self.note("backtrack", depth=obj.session.depth)
            decision = self.decide()
            if isinstance(decision, ScoredTest):
                return self.chose(decision, "backtrack")
            if not isinstance(decision, Exhausted):
                break
        obj.no_alternative = True
        self.feedback_message = "nothing left to try above"
        return Status.FAILURE


class NearestNeighbour(_Choose):
    """The last resort (or sooner, per ``nearest_after``): follow the branch nearest the
    unreliable value."""

    def __init__(self, services: Services, name: str = "NearestNeighbour") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        obj = self.obj
        grasp_failed = obj.attempt is not None and obj.attempt.success is False
        if grasp_failed or not obj.session.can_follow_nearest or not (obj.no_alternative or self.nearest_now()):
            return Status.FAILURE
        matched = obj.session.follow_nearest()
        obj.pending_unreliable = False
        obj.no_alternative = False
        obj.ledger.recoveries["nearest neighbour"] += 1
        self.note("nearest", branch=[matched.range[0], matched.range[1]], value=matched.value)
        return Status.SUCCESS


class ChooseGrasp(_Choose):
    """At a leaf: its grasp. At an ambiguous leaf, or when every strategy failed at the
    node (a classification failure): the cheapest of its grasps, tried as a binary
    feature (a failure drops that grasp and the next one comes up)."""

    def __init__(self, services: Services, name: str = "ChooseGrasp") -> None:
        super().__init__(name, services)

    def update(self) -> Status:
        obj = self.obj
        decision = self.decide()
        if isinstance(decision, Exhausted) and obj.no_alternative and not obj.session.can_follow_nearest:
            decision = obj.session.classification_failure()  # every strategy failed here
        if isinstance(decision, AmbiguousLeaf) and decision.options:
            obj.ledger.recoveries["ambiguous leaf"] += 1
            leaf = decision.options[0]
            how = "ambiguous"
        elif isinstance(decision, GraspLeaf):
            leaf, how = decision, "leaf"
        else:
            return Status.FAILURE
        obj.attempt = GraspAttempt(leaf.grasp, leaf.position)
        self.feedback_message = f"{leaf.grasp}{leaf.position}"
        self.note("choose_grasp", how=how, grasp=leaf.grasp, at=leaf.position.to_json(),
                  move_s=round(leaf.move_cost, 1), candidates=list(obj.session.candidates))
        return Status.SUCCESS
