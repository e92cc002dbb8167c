"""A grasp reported held is checked by the camera: the object must have left the floor.

The finger sensor is the driver's word; a sensor stuck at "held" would have every
object reported grasped (and learned from) while it still lies where it was. The
overhead camera can check that word for free: the arm holds the object while the
ceiling camera looks, so no robot time is charged. ``GraspVerified?`` stands between
the object's steps and ``Learn``::

    approach and recognize
      RememberAppearance
      recognize and grasp
      grasp verified
        GraspVerified?   a grasp reported held: one image, the object gone from the floor
        LetGo            else: open the hand (whatever it holds is not the object), fail
      Learn
      LookForTheRest

It passes an object left (No-Grab) or not grasped untouched, and every object when
``Params.verify_grasps`` is off. When the image still shows
a region where the grasped object lay (:func:`still_on_floor`), the grasp is
unverified: event ``grasp_unverified`` naming the driver suspect, the object fails,
``LetGo`` opens the hand (a driver that believes it holds something would refuse the
next grasp), and since the sequence then stops, nothing is learned from it. The run's closing lines name the driver (``executive.exit_status``).

The image is segmented on its own (:func:`planner.look`), not made the planner's
current scene: the plans of the next object are made on the image they were made on
before this check existed.
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import Any

import py_trees
from py_trees.common import Access, Status
from py_trees.composites import Selector

from behaviours.base import DriverAction, LookAction
from behaviours.events import Event
from behaviours.sameness import CHANGED_RATIO, PUSHED_IN
from hero_driver.interface import RobotState
from planner import Region
from planner.geometry import Pose


def still_on_floor(lay: Region, regions: tuple[Region, ...] | list[Region], others: list[tuple[float, float]],
                   robot: Pose | None, base_radius_in: float) -> Region | None:
    """The region of ``regions`` that is the object once seen as ``lay``, still on the
    floor; None when there is none (it left the floor).

    A region counts when its outline reaches within a push (:data:`PUSHED_IN`) of where
    the object lay (outlines taken as discs of their lengths, so a failed grasp that
    pushed the object or knocked it over is still found there) and it is no smaller than
    the object was by :data:`CHANGED_RATIO` (a cluster the grasp took one object from
    shrinks by at least that object). Not counted: a region where another known object
    lies (``others``: their centroids), and one over the robot's own base
    (``base_radius_in`` of ``robot``: the arm and what it holds).
    """
    for region in regions:
        if robot is not None and math.dist(region.centroid, (robot.x_in, robot.y_in)) < base_radius_in:
            continue
        if any(math.dist(region.centroid, other) <= PUSHED_IN for other in others):
            continue
        reach = (lay.length_in + region.length_in) / 2 + PUSHED_IN
        if math.dist(region.centroid, lay.centroid) <= reach and \
                region.pixel_count >= (1.0 - CHANGED_RATIO) * lay.pixel_count:
            return region
    return None


class GraspVerified(LookAction):
    """Condition ``GraspVerified?``: for an object reported grasped, one overhead image
    must show it gone from the floor; else ``grasp_unverified`` and the object fails
    (module docstring). Succeeds at once for an object left or not grasped."""

    def __init__(self, robot: str, name: str = "GraspVerified?") -> None:
        super().__init__(name, robot)
        self.bb.register_key("objects", access=Access.READ)
        self.bb.register_key("results", access=Access.READ)

    def start(self) -> Future[Any] | Status:
        if self.obj.outcome != "grasped":
            self.feedback_message = "no grasp to verify"
            return Status.SUCCESS
        if not self.services.params.verify_grasps:
            self.obj.verified = True
            self.feedback_message = "check off: the driver's word"
            return Status.SUCCESS
        return self.take_look()

    def finish(self, result: Any) -> Status:
        obj, navigator = self.obj, self.services.navigator
        scene = self.timed(lambda: self.services.perception.glance(result))
        others = [r.centroid for r in self.bb.objects] + [
            r.region.centroid for r in self.bb.results if r is not obj and r.outcome not in ("grasped", "gone")]
        robot = scene.robot or self.robot_pose()
        there = still_on_floor(obj.region, scene.regions, others, robot, navigator.robot.geometry.base_radius_in)
        if there is None:
            obj.verified = True
            self.feedback_message = "the object left the floor"
            return Status.SUCCESS
        grasp = obj.grasp
        obj.finish("failed")
        self.note(Event.GRASP_UNVERIFIED, grasp=grasp, seen=[round(c, 1) for c in there.centroid],
                  pixels=there.pixel_count, driver=self.services.driver.robot,
                  reason="the driver reported the grasp held; the camera still sees the object on the floor")
        self.feedback_message = f"{grasp} reported held, the object still on the floor: driver suspect"
        return Status.FAILURE


class LetGo(DriverAction):
    """After a grasp the camera did not confirm: open the hand, then fail, so the
    object's sequence stops before ``Learn``."""

    VERB = "release"

    def __init__(self, robot: str, name: str = "LetGo") -> None:
        super().__init__(name, robot)

    def start(self) -> Future[RobotState]:
        return self.services.driver.release()

    def finish(self, result: RobotState) -> Status:
        self.feedback_message = "hand opened: the object failed"
        return Status.FAILURE


def grasp_verified(robot: str) -> py_trees.behaviour.Behaviour:
    """``GraspVerified?``, else ``LetGo``: see the module docstring."""
    return Selector("grasp verified", memory=True, children=[GraspVerified(robot), LetGo(robot)])
