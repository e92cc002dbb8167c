"""Objects close together: a sonar reading a neighbour contaminates is never used.

The paper's CSL "assumes that objects are apart" (docs/method.md). With a neighbour
within a base width, a sensing procedure aimed at the object may hear the neighbour
first: a sweep's rays that meet it never reach the object, a scan counts its echo, and
a neighbour squarely in the way is measured instead. ``BeamClear?`` stands between the
choice of a test and the move to its position: from the planner's beam corridor
(:func:`planner.positions.beam_blockers`: the footprint, the sonar point and the scan's
swath, an inch of margin) and the latest image's other regions, it succeeds when no
other object is in or near the sound's way. When one is, the test is unusable from
there, as a position with no path is (``session.unusable``), logged as ``beam_blocked`` with
the neighbours' centroids: the learner reselects
among the other tests and positions, and nothing is measured, so no contaminated value
ever reaches a description. A region vision reports as a cluster (objects touching
that it could not cut apart, ``Region.cluster``) has its neighbour inside it: no
sensing of it is used at all, and the learner is left with its grasps (tried as
features or at a leaf), so the cluster is still handled, without sonar. Grasps (no sound) and values already measured (no new
reading) pass unchecked, and so does everything with the check off
(``Params.beam_check``: the study's "off" arm). The same test priced up front is
``PlannerMoveCost.sensing_move_cost`` (behaviours/bridge.py, given ``Params.beam_check``
by the object loop): the learner never picks such a position, and this check stays for
a scene seen anew since (docs/executive.md "Clutter").
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import Any

from py_trees.common import Access, Status

from behaviours.base import CslBehaviour, LookAction
from behaviours.events import Event
from behaviours.sameness import PUSHED_IN
from planner import Region
from planner.merging import within_push
from planner.positions import beam_blockers, neighbours


class BeamClear(CslBehaviour):
    """Condition ``BeamClear?``: the chosen test's sound reaches the object before any
    neighbour's echo; else the test is unusable from its position (fails)."""

    def __init__(self, robot: str, name: str = "BeamClear?") -> None:
        super().__init__(name, robot)

    def update(self) -> Status:
        test = self.step.test
        if not self.services.params.beam_check:
            self.feedback_message = "check off"
            return Status.SUCCESS
        if test is None or test.test.is_grasp or test.cost == 0:
            self.feedback_message = "no sound to check"
            return Status.SUCCESS
        obj = self.obj
        target = test.target
        if obj.region.cluster:
            self.obj.session.unusable(test)
            self.feedback_message = "a cluster: no reading would be the object's alone"
            self.note(Event.BEAM_BLOCKED, to=target.to_json(), cluster=True,
                      blockers=[[round(c, 1) for c in obj.region.centroid]])
            return Status.FAILURE
        blockers = self.timed(lambda: beam_blockers(obj.region, target.distance_in or 0.0,
                                                    target.orientation_deg or 0.0, self.others()))
        if not blockers:
            self.feedback_message = "beam clear"
            return Status.SUCCESS
        self.obj.session.unusable(test)
        self.feedback_message = f"beam meets {len(blockers)} other object(s)"
        self.note(Event.BEAM_BLOCKED, to=target.to_json(), cluster=False,
                  blockers=[[round(c, 1) for c in r.centroid] for r in blockers])
        return Status.FAILURE

    def others(self) -> list[Region]:
        """Every region of the latest image but the object's own (the one within
        :data:`~behaviours.sameness.PUSHED_IN` of its centroid: the same object seen anew)."""
        return neighbours(self.obj.region, self.services.navigator.scene.regions, PUSHED_IN)


class LookForTheRest(LookAction):
    """``LookForTheRest``: after a grasp held one object of a cluster and it was put
    away, look again and queue, next, what is left of the cluster.

    The object list comes from the first image, where the cluster was one region: the
    objects still lying where it was are in no list, and the run would end with them
    on the floor, unreported. Every region of the new image within a push
    (:func:`planner.merging.within_push`) of the cluster's outline, and not one already
    queued, goes to the front of the list (``rest_of_cluster`` with their centroids);
    each is then worked on as any object. Succeeds at once for any other object.
    """

    POSE_ACCESS = Access.WRITE  # an image may correct where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, name: str = "LookForTheRest") -> None:
        super().__init__(name, robot)
        self.bb.register_key("objects", access=Access.WRITE)

    def start(self) -> Future[Any] | Status:
        obj = self.obj
        if not obj.clustered or obj.outcome != "grasped":
            self.feedback_message = "not a cluster grasped"
            return Status.SUCCESS
        return self.take_look()

    def finish(self, result: Any) -> Status:
        scene = self.look(result)
        queued = list(self.bb.objects)
        near = PUSHED_IN
        rest = [r for r in scene.regions if within_push(self.obj.region, r.centroid)
                and not any(math.dist(r.centroid, q.centroid) <= near for q in queued)]
        self.bb.objects = rest + queued
        self.note(Event.REST_OF_CLUSTER, regions=[[round(c, 1) for c in r.centroid] for r in rest])
        self.feedback_message = f"{len(rest)} left of the cluster"
        return Status.SUCCESS
