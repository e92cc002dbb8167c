"""Every recovery of the executive, and the conditions that gate them.

The control strategies for noise (docs/method.md §5): *reselection* of the next-best
test after an unreliable value, *backtracking* to choose differently at the parent,
*nearest neighbour* as the last resort, an *ambiguous leaf*'s grasps tried as binary
features. And the recoveries from a failed grasp: approaching from the object's *other
end* when the grasp position has no path, checking for *side effects* (pushed or
changed: start over), *dropping* a cleanly failed grasp, and *discriminating* the
object from the wrongly predicted class. A condition (a name ending in ``?``) that
decides whether a recovery applies is its own node, so ``csl bt`` shows the gate.
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import Any
from dataclasses import replace

from py_trees.common import Access, Status

from behaviours.actions import MoveTo, pose_json
from behaviours.appearance import appearance_of
from behaviours.base import CslBehaviour, LookAction
from behaviours.legs import LeggedMove
from behaviours.plausible import LibraryRanges, values_checked
from behaviours.bridge import other_end
from behaviours.choosing import Choose
from behaviours.events import Event
from behaviours.records import ObjectRecord
from behaviours.sameness import CHANGED_RATIO, PUSHED_IN
from hero_driver.interface import DriverError, MoveResult, SenseResult
from learner.choosing.leaf import AmbiguousLeaf
from learner.choosing.matrix import Test
from learner.choosing.node import ScoredTest
from learner.position import Position
from learner.runtime import Exhausted

# -- conditions ---------------------------------------------------------------------


class ValueUnreliable(Choose):
    """Succeeds when the node's latest value was not trusted and nearest neighbour is
    not yet due: the gate of reselection."""

    def __init__(self, robot: str, name: str = "Unreliable?") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        due = self.obj.session.awaiting_reselection and not self.nearest_due()
        return Status.SUCCESS if due else Status.FAILURE


class GraspFailed(CslBehaviour):
    """Succeeds when the step's grasp (at a leaf or as a feature) failed: the gate of
    every grasp recovery."""

    def __init__(self, robot: str, name: str = "GraspFailed?") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        attempt = self.step.attempt
        return Status.SUCCESS if attempt is not None and attempt.failed else Status.FAILURE


# -- noise: choosing again ------------------------------------------------------------


class Reselect(Choose):
    """After an unreliable value: the next-best test at the same node (up to N)."""

    def __init__(self, robot: str, name: str = "Reselect") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        decision = self.decide()
        if isinstance(decision, ScoredTest):
            self.obj.ledger.recoveries["reselect"] += 1
            return self.chose(decision, "reselect")
        return Status.FAILURE


class Backtrack(Choose):
    """No reliable test left here (or N tried): invalidate the parent's value and choose
    a different test there; repeatable up to the root."""

    def __init__(self, robot: str, name: str = "Backtrack") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        obj = self.obj
        if self.nearest_due() or not isinstance(self.decide(), Exhausted):
            return Status.FAILURE
        while obj.session.backtrack():
            obj.ledger.recoveries["backtrack"] += 1
            self.note(Event.BACKTRACK, depth=obj.session.depth)
            decision = self.decide()
            if isinstance(decision, ScoredTest):
                return self.chose(decision, "backtrack")
            if not isinstance(decision, Exhausted):
                break
        self.step.no_alternative = True
        self.feedback_message = "nothing left to try above"
        return Status.FAILURE


class NearestNeighbour(Choose):
    """The last resort (or sooner, per ``nearest_after``): follow the branch nearest the
    unreliable value."""

    def __init__(self, robot: str, name: str = "NearestNeighbour") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        obj, step = self.obj, self.step
        grasp_failed = step.attempt is not None and step.attempt.failed
        if grasp_failed or not obj.session.can_follow_nearest or not (step.no_alternative or self.nearest_due()):
            return Status.FAILURE
        matched = obj.session.follow_nearest()
        obj.ledger.recoveries["nearest neighbour"] += 1
        self.note(Event.NEAREST, branch=[matched.range[0], matched.range[1]], value=matched.value)
        return Status.SUCCESS


class AmbiguousGrasp(Choose):
    """At an ambiguous leaf, or when every strategy failed at the node (a classification
    failure): the cheapest of its grasps, tried as a binary feature (a failure drops
    that grasp and the next one comes up)."""

    def __init__(self, robot: str, name: str = "AmbiguousLeaf") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        session = self.obj.session
        decision = self.decide()
        if isinstance(decision, Exhausted) and self.step.no_alternative and not session.can_follow_nearest:
            decision = session.classification_failure()  # every strategy failed here
        if not isinstance(decision, AmbiguousLeaf) or not decision.options:
            return Status.FAILURE
        self.obj.ledger.recoveries["ambiguous leaf"] += 1
        return self.chose_grasp(decision.options[0], "ambiguous", decision.object_ids)


# -- a failed grasp -------------------------------------------------------------------


class OtherEnd(MoveTo):
    """A grasp position with no path: approach from the object's other end (vision knows
    its reference direction only up to a half turn, so that end is as good and may be
    free). Reachable from neither end, the grasp counts as failed."""

    def __init__(self, robot: str, name: str = "OtherEnd") -> None:
        super().__init__(robot, "grasp", name)

    def start(self) -> Future[MoveResult] | Status:
        step = self.step
        attempt = step.attempt
        if attempt is None or attempt.failed:
            return Status.FAILURE
        goal = other_end(attempt.position)
        plan = self.plan(goal)
        if not plan.found:
            self.note(Event.NO_PATH, to=goal.to_json(), reason=plan.reason)
            step.attempt = replace(attempt, success=False)
            return Status.FAILURE
        self.note(Event.OTHER_END, to=goal.to_json(), instead_of=attempt.position.to_json())
        step.attempt = replace(attempt, position=goal)
        self._goal = goal
        return self.drive(plan)


class CheckSideEffects(LookAction):
    """After a failed grasp, look again: was the object pushed, or changed (knocked over)?

    The pixel count tells them apart (docs/method.md §5): about the same area means the
    same object, moved; a clearly different area means it changed and all sensing is
    void, and the object is known from now on by the footprint the camera sees (none when
    its region is lost). Succeeds when there were side effects.
    """

    POSE_ACCESS = Access.WRITE  # an image may correct where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, name: str = "SideEffects?") -> None:
        super().__init__(name, robot)

    def start(self) -> Future[Any]:
        return self.take_look()

    def finish(self, result: Any) -> Status:
        obj, step = self.obj, self.step
        scene = self.look(result)
        old = obj.region
        near = [r for r in scene.regions
                if math.hypot(r.centroid[0] - old.centroid[0], r.centroid[1] - old.centroid[1]) < 18.0]
        if not near:  # rolled out of sight or merged with something: nothing sensed holds
            step.side_effect = "changed"
            obj.session.appearance = None  # and how it looks now, the camera cannot say
            self.note(Event.SIDE_EFFECT, effect="changed", reason="region lost")
            return Status.SUCCESS
        new = min(near, key=lambda r: math.hypot(r.centroid[0] - old.centroid[0], r.centroid[1] - old.centroid[1]))
        shift = math.hypot(new.centroid[0] - old.centroid[0], new.centroid[1] - old.centroid[1])
        change = abs(new.pixel_count - obj.pixels_before) / max(obj.pixels_before, 1)
        if change > CHANGED_RATIO:
            effect: str | None = "changed"
        elif shift > PUSHED_IN:
            effect = "pushed"
        else:
            effect = None
        step.side_effect = effect
        self.note(Event.SIDE_EFFECT, effect=effect or "none", shift_in=round(shift, 2), pixels=new.pixel_count)
        if effect is None:
            return Status.FAILURE
        obj.region, obj.pixels_before = new, new.pixel_count
        obj.estimator.retarget(new)
        obj.session.orientation_free = new.round
        if effect == "changed":
            obj.session.appearance = appearance_of(new)
        return Status.SUCCESS


class StartOver(CslBehaviour):
    """A failed grasp had side effects: restore every description and start over from
    here; if the object changed, everything sensed so far is void too, and the new
    object is known by the footprint the camera saw after the grasp (none when its
    region was lost), never by the one the original had (docs/method.md §5.8)."""

    def __init__(self, robot: str, name: str = "StartOver") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        obj, step = self.obj, self.step
        assert step.attempt is not None and step.side_effect is not None
        here = obj.estimator.stand_at(self.robot_pose())
        changed = step.side_effect == "changed"
        try:  # a changed object keeps the appearance SideEffects? saw of it
            obj.session.grasp_failed(step.attempt.grasp, side_effects=True, changed=changed, position=here,
                                     appearance=obj.session.appearance)
        except ValueError:  # a grasp pushing it twice was the last one left
            obj.finish("failed")
            self.note(Event.GAVE_UP, reason="every grasp in the library failed")
            return Status.SUCCESS
        obj.ledger.recoveries["start over (changed)" if changed else "start over (pushed)"] += 1
        self.note(Event.START_OVER, changed=changed, at=here.to_json())
        return Status.SUCCESS


class DropFailedGrasp(CslBehaviour):
    """A grasp failed without side effects. Tried as a feature: follow its 'failure'
    branch. At a leaf: drop the descriptions labelled with it and rebuild from the
    current position, keeping every value measured."""

    def __init__(self, robot: str, name: str = "DropFailedGrasp") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        obj, attempt = self.obj, self.step.attempt
        assert attempt is not None
        if attempt.as_feature is not None:
            obj.session.grasp_as_feature(attempt.as_feature, False, attempt.position)
            obj.ledger.recoveries["grasp feature failed"] += 1
            self.note(Event.GRASP_FEATURE_FAILED, grasp=attempt.grasp)
            return Status.SUCCESS
        try:
            self.timed(lambda: obj.session.grasp_failed(attempt.grasp, side_effects=False))
        except ValueError:
            obj.finish("failed")
            self.note(Event.GAVE_UP, reason="every grasp in the library failed")
            return Status.SUCCESS
        obj.ledger.recoveries["drop failed grasp"] += 1
        self.note(Event.DROP_GRASP, grasp=attempt.grasp, candidates=list(obj.session.candidates))
        return Status.SUCCESS


class Discriminate(LeggedMove):
    """After a wrong prediction, measure until the object is told apart from the wrongly
    predicted grasp's descriptions (docs/method.md §5, "discriminating features added"):
    the cheapest feature they have and this object lacks, here where the robot stands,
    then the next, until a value falls outside theirs or nothing is left to measure here.
    Each procedure is one driver verb; the behaviour stays RUNNING between them. A test
    is tried once per object, not once per wrong prediction, and a procedure that gave
    nothing on this object is not asked again from another side: a deaf sonar must not
    cost one more sweep after every failed grasp.

    Where nothing at all was sensed on the object (the camera's appearance left one
    grasp, and it failed), the cheapest discriminating test is worth a move: without one
    value the object would be learned with none, nothing would tell it from the wrongly
    predicted descriptions next time, and the same grasp would fail again
    (docs/method.md §5.8). The move is one more driver verb before the sense (or more: a
    long one is driven in legs, ``behaviours.legs``).

    Its values are checked as ``Plausible?`` checks a test's (``behaviours.plausible``):
    an implausible one is an ``implausible`` event and is not recorded, since a value
    recorded here is believed by every later test of the object (a deaf sonar's -1
    would be followed, or called unreliable, at the next node)."""

    POSE_ACCESS = Access.WRITE  # the move to a discriminating test changes where the robot stands

    VERB = "sense"

    def __init__(self, robot: str, name: str = "Discriminate") -> None:
        super().__init__(name, robot)
        self._test: ScoredTest | None = None
        self._wrong: str | None = None
        self._tried: set[Test] = set()
        self._silent: set[str] = set()  # procedures that gave no value on this object
        self._tried_on: ObjectRecord | None = None
        self._may_move = False
        self._ranges = LibraryRanges()

    def start(self) -> Future[SenseResult] | Status:
        obj, attempt = self.obj, self.step.attempt
        if self._tried_on is not obj:
            self._tried, self._silent, self._tried_on = set(), set(), obj
        if attempt is None or attempt.as_feature is not None or obj.done:
            return Status.SUCCESS
        if self.timed(lambda: obj.session.told_apart(attempt.grasp)):
            self.note(Event.DISCRIMINATE, already=True, wrong=attempt.grasp)
            return Status.SUCCESS  # what was measured already tells the two apart
        self._wrong = attempt.grasp
        # one move for a value, on an object nothing was sensed on and not yet discriminated
        self._may_move = not obj.session.measurements and not self._tried
        return self._next()

    def _next(self) -> Future[SenseResult] | Status:
        obj = self.obj
        assert self._wrong is not None
        wrong = self._wrong
        while True:
            tried = frozenset(self._tried)
            self._test = self.timed(lambda: obj.session.discriminating_test(wrong, tried))
            if self._test is None or self._test.test.procedure not in self._silent:
                break
            self._tried.add(self._test.test)
        if self._test is None:
            return Status.SUCCESS  # nothing left to add
        self._tried.add(self._test.test)  # each test once: a dropout is not retried forever
        if self._test.move_cost > 0:
            if not self._may_move:
                return Status.SUCCESS  # what was sensed goes into the description: no move for more
            self._may_move = False
            return self._move_to(self._test.target)
        return self.services.driver.sense(self._test.test.procedure)

    def _move_to(self, target: Position) -> Future[MoveResult] | Status:
        """Drive to ``target`` for the one discriminating value (no path: give it up)."""
        obj, nav = self.obj, self.services.navigator
        plan = self.timed(lambda: nav.plan(self.robot_pose(), obj.estimator.pose(target)))
        if not plan.found:
            self.note(Event.NO_PATH, to=target.to_json(), reason=plan.reason)
            return Status.SUCCESS
        return self.drive_path(plan.path or (), face=obj.region.centroid, standoff_in=target.distance_in)

    def finish(self, result: Any) -> Status:
        if not isinstance(result, SenseResult):  # a leg of the move, or a look between two
            whole = self.leg_done(result)
            return Status.RUNNING if whole is None else self._moved(whole)
        obj = self.obj
        assert self._test is not None and self._wrong is not None
        obj.ledger.sensing_s += result.duration_s
        bad = values_checked(self, self._ranges, str(self._test.test), result.values)
        if bad:  # checked as Plausible? checks a test's values: never recorded, never asked again here
            self.note(Event.DISCRIMINATE, procedure=result.procedure, values=dict(result.values.items()),
                      seconds=round(result.duration_s, 1), told_apart=False, implausible=sorted(bad))
            self._silent.add(result.procedure)
            return Status.SUCCESS
        obj.session.record(result.values, self._test.target)
        told_apart = obj.session.discriminates(self._test, self._wrong)
        self.note(Event.DISCRIMINATE, procedure=result.procedure, values=dict(result.values.items()),
                  seconds=round(result.duration_s, 1), told_apart=told_apart)
        if result.values.get(self._test.test.feature) is None:
            self._silent.add(result.procedure)
            return Status.SUCCESS  # the sonar gave nothing: leave it there
        if told_apart:
            return Status.SUCCESS
        nxt = self._next()
        if isinstance(nxt, Status):
            return nxt
        self._future = nxt  # the next procedure, watched by update()
        return Status.RUNNING

    def _moved(self, result: MoveResult) -> Status:
        obj = self.obj
        assert self._test is not None
        self.bb.pose = result.pose
        obj.ledger.moving_s += result.duration_s
        self.note(Event.MOVE, to=self._test.target.to_json(), seconds=round(result.duration_s, 1),
                  collided=result.collided, pose=pose_json(result.pose), path=[pose_json(p) for p in self.sent])
        if result.collided:
            return Status.SUCCESS  # not where the value was wanted: learn without it
        obj.session.position = self._test.target
        self._future = self.services.driver.sense(self._test.test.procedure)
        return Status.RUNNING

    def failed(self, exc: DriverError) -> Status:
        return Status.SUCCESS  # a discriminating value is a bonus, not a requirement
