"""A world that changes under the robot: the object moved, changed or gone.

The paper's CSL "assumes that objects are ... stationary" and "can not handle ... the
disappearance of an object during sensing" (docs/method.md). Here, right before each
sensing verb and each grasp, the overhead camera (cheap: one image) checks that the
object is still where the session believes: a region within
:data:`~behaviours.sameness.PUSHED_IN` of
the expected centroid whose pixel count is within :data:`~behaviours.sameness.CHANGED_RATIO` of the
expected one. Right before the verb, not before the move to its position, because a
measurement is only worth keeping if the object was in place when it was taken: the
move there may be the moment someone walks by.

``Disturbed?`` succeeds when the check fails, and one of three recoveries acts:

- **moved** (``Relocate``): a region of about the same size within :data:`~behaviours.sameness.SEARCH_IN`
  of where the object was is the same object, moved. Its region is replaced, moves are
  priced and planned around the new pose, and the session is told where the robot now
  stands relative to it. Every value measured stays: readings are relative to the
  object, and the robot re-plans its positions relative to the new pose.
- **changed** (``StartAfresh``): a region there of a clearly different size is another
  object (swapped, knocked over): nothing measured describes it, so the object starts
  over with a fresh session on the new region.
- **gone** (``ReportGone``): nothing there. The object ends ``gone``: reported, not a
  failure of the executive (docs/executive.md), and the robot goes on to the next one.

Either way the step ends there and the next step decides afresh. Since every
measurement and every grasp directly follows a check, nothing the session holds was
measured on an object that has changed since, so ``Learn`` never saves a description
from a disturbed attempt.
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import Any
from dataclasses import dataclass

import py_trees
from py_trees.common import Access, Status

from behaviours.base import CslBehaviour, LookAction
from behaviours.events import Event
from behaviours.loop import open_session
from behaviours.records import ObjectRecord
from behaviours.sameness import CHANGED_RATIO, PUSHED_IN, SEARCH_IN
from planner import Region
from planner.merging import within_push

OUTLINE_PIXELS = 1.5
"""Rasterised a fraction of a pixel elsewhere or turned, a region of N pixels counts up
to about this times sqrt(N) more or fewer (measured: 0.65-1.2 over the catalogue's
footprints): the pixel tolerance never goes below it, or a small object would read
as changed whenever it is seen anew."""
FINDING = "disturbance"  # blackboard: what the last check found (None: the object is in place)
MOVED, CHANGED, GONE = "moved", "changed", "gone"


@dataclass(frozen=True)
class Finding:
    """What the camera showed where the object should be: ``kind`` (moved, changed or
    gone), the region it is now (None when gone), how far its centroid is from the
    expected one and its pixel count's relative change."""

    kind: str
    region: Region | None
    shift_in: float
    pixel_change: float

    def to_json(self) -> dict[str, object]:
        where = None if self.region is None else [round(c, 1) for c in self.region.centroid]
        return {"found": self.kind, "at": where, "shift_in": round(self.shift_in, 2),
                "pixel_change": round(self.pixel_change, 3)}


def judge(expected: Region, pixels: float, regions: list[Region], others: list[tuple[float, float]], *,
          in_place_in: float, search_in: float, changed_ratio: float) -> Finding | None:
    """The check itself, on the regions of a new image: None when a region within
    ``in_place_in`` of the expected centroid has a pixel count within ``changed_ratio``
    of ``pixels`` (or within ``OUTLINE_PIXELS`` sqrt(pixels), if more); else what
    happened. A region sitting where another known object is (``others``: their
    centroids) is that object, never ours, unless it is a cluster reaching where ours
    was: ours was pushed against that object (changed, so started afresh on the
    cluster), not gone."""

    def distance(r: Region) -> float:
        return math.hypot(r.centroid[0] - expected.centroid[0], r.centroid[1] - expected.centroid[1])

    def change(r: Region) -> float:
        return abs(r.pixel_count - pixels) / max(pixels, 1.0)

    tolerance = max(changed_ratio, OUTLINE_PIXELS / math.sqrt(max(pixels, 1.0)))

    def theirs(r: Region) -> bool:  # a cluster over where ours was holds ours too
        return not (r.cluster and within_push(r, expected.centroid)) and any(
            math.hypot(r.centroid[0] - x, r.centroid[1] - y) <= in_place_in for x, y in others)

    mine = [r for r in regions if distance(r) <= search_in and not theirs(r)]
    if not mine:
        return Finding(GONE, None, math.inf, 1.0)
    # nearest first; of two about as near, the one of the right size
    best = min(mine, key=lambda r: (round(distance(r) / in_place_in), change(r) > tolerance, distance(r)))
    shift, changed = distance(best), change(best)
    if changed > tolerance:
        return Finding(CHANGED, best, shift, changed)
    if shift > in_place_in:
        return Finding(MOVED, best, shift, changed)
    return None


class Disturbed(LookAction):
    """Condition ``Disturbed?``: before ``what`` (a sensing or a grasp), one overhead image
    says whether the object is still in place; succeeds when it is not (moved, changed,
    gone: the finding goes on the blackboard for the recoveries). A test whose value is
    already known costs no robot time and needs no look; neither does anything when the
    check is off (``Params.check_in_place``)."""

    POSE_ACCESS = Access.WRITE  # an image may correct where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, what: str, name: str = "Disturbed?") -> None:
        super().__init__(name, robot)
        if what not in ("test", "grasp"):
            raise ValueError(f"Disturbed? guards a 'test' or a 'grasp', got {what!r}")
        self.what = what
        self.bb.register_key(FINDING, access=Access.WRITE)
        self.bb.register_key("objects", access=Access.READ)
        self.bb.register_key("results", access=Access.READ)

    def start(self) -> Future[Any] | Status:
        self.bb.set(FINDING, None)
        if not self.services.params.check_in_place:
            self.feedback_message = "check off"
            return Status.FAILURE
        test = self.step.test
        if self.what == "test" and (test is None or (test.cost == 0 and not test.test.is_grasp)):
            self.feedback_message = "nothing to measure: no look needed"
            return Status.FAILURE
        return self.take_look()

    def finish(self, result: Any) -> Status:
        obj = self.obj
        scene = self.look(result)
        others = [r.centroid for r in self.bb.objects] + [
            r.region.centroid for r in self.bb.results if r is not obj and r.outcome not in ("grasped", GONE)]
        finding = judge(obj.region, obj.pixels_before, list(scene.regions), others, in_place_in=PUSHED_IN,
                        search_in=SEARCH_IN, changed_ratio=CHANGED_RATIO)
        self.bb.set(FINDING, finding)
        if finding is None:
            self.feedback_message = "in place"
            return Status.FAILURE
        self.note(Event.DISTURBANCE, before=self.what, **finding.to_json())
        self.feedback_message = finding.kind
        return Status.SUCCESS


class _Recovery(CslBehaviour):
    """A recovery from one kind of finding; fails on the others."""

    KIND = ""

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name, robot)
        self.bb.register_key(FINDING, access=Access.WRITE)

    def update(self) -> Status:
        finding: Finding | None = self.bb.get(FINDING)
        if finding is None or finding.kind != self.KIND:
            return Status.FAILURE
        self.bb.set(FINDING, None)
        self.obj.ledger.recoveries[f"disturbed ({self.KIND})"] += 1
        self.recover(finding)
        return Status.SUCCESS

    def recover(self, finding: Finding) -> None:
        """What each kind does (every subclass names its KIND and overrides this; the
        base's empty KIND matches no finding, so it is never called here)."""


class Relocate(_Recovery):
    """The same object, moved: follow it and keep every value measured."""

    KIND = MOVED

    def __init__(self, robot: str, name: str = "Relocate") -> None:
        super().__init__(name, robot)

    def recover(self, finding: Finding) -> None:
        obj = self.obj
        assert finding.region is not None
        follow(obj, finding.region)
        obj.session.position = obj.estimator.stand_at(self.robot_pose())
        self.note(Event.RELOCATE, at=[round(c, 1) for c in finding.region.centroid],
                  position=obj.session.position.to_json(), kept=len(obj.session.path))


class StartAfresh(_Recovery):
    """Another object where ours was: start over on it with a fresh session, nothing of
    what was measured kept."""

    KIND = CHANGED

    def __init__(self, robot: str, name: str = "StartAfresh") -> None:
        super().__init__(name, robot)

    def recover(self, finding: Finding) -> None:
        obj = self.obj
        assert finding.region is not None
        follow(obj, finding.region)
        start = obj.estimator.stand_at(self.robot_pose())
        obj.session = open_session(self.services, finding.region, obj.estimator, start, obj.index)
        self.note(Event.START_AFRESH, at=[round(c, 1) for c in finding.region.centroid],
                  pixels=finding.region.pixel_count, start=obj.session.position.to_json())


class ReportGone(_Recovery):
    """Nothing where the object was: it is ``gone``, and the robot moves on."""

    KIND = GONE

    def __init__(self, robot: str, name: str = "ReportGone") -> None:
        super().__init__(name, robot)

    def recover(self, finding: Finding) -> None:
        obj = self.obj
        obj.finish(GONE)
        self.note(Event.GONE, was_at=[round(c, 1) for c in obj.region.centroid], measured=len(obj.session.path))


def follow(obj: ObjectRecord, region: Region) -> None:
    """The object is now ``region``: its expected place and size, and its move costs."""
    obj.region, obj.pixels_before = region, region.pixel_count
    obj.estimator.retarget(region)
    obj.session.orientation_free = region.round


def look_before(robot: str, what: str, act: py_trees.behaviour.Behaviour) -> py_trees.behaviour.Behaviour:
    """``act`` (a sensing or a grasp) behind the camera check: when ``Disturbed?`` finds
    the object moved, changed or gone, its recovery runs instead and the step ends."""
    return py_trees.composites.Selector(f"look before the {what}", memory=True, children=[
        py_trees.composites.Sequence("disturbed", memory=True, children=[
            Disturbed(robot, what),
            py_trees.composites.Selector("what happened", memory=True, children=[
                Relocate(robot), StartAfresh(robot), ReportGone(robot)])]),
        act])
