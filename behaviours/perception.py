"""Seeing: finding objects with the overhead camera, and checking after a failed grasp."""

from __future__ import annotations

import math
from concurrent.futures import Future

from py_trees.common import Access, Status

from behaviours.base import CslBehaviour, DriverAction
from behaviours.context import ObjectRecord, PlannerMoveCost, Services, relative_position
from hero_driver.interface import CameraImage
from learner.runtime import RecognitionSession
from planner import OverheadImage, Region


def overhead(image: CameraImage) -> OverheadImage:
    """The driver's camera image as the planner's input (same fields)."""
    return OverheadImage(image.pixels, image.inches_per_pixel, image.origin_x_in, image.origin_y_in,
                         image.camera_matrix, image.fisheye)


class LocateObjects(DriverAction):
    """Take an overhead image and queue every object region, nearest first."""

    def __init__(self, services: Services, name: str = "LocateObjects") -> None:
        super().__init__(name, services)
        self.bb.register_key("objects", access=Access.WRITE)

    def start(self) -> Future[CameraImage]:
        return self.services.driver.camera()

    def finish(self, result: CameraImage) -> Status:
        scene = self.services.navigator.observe(overhead(result))
        robot = self.services.robot_pose()
        regions = sorted(scene.regions, key=lambda r: (math.hypot(r.centroid[0] - robot.x_in,
                                                                  r.centroid[1] - robot.y_in), r.centroid))
        self.bb.objects = list(regions)
        self.services.log.event("located", behaviour=self.name, regions=[
            {"centroid": [round(c, 1) for c in r.centroid], "pixels": r.pixel_count,
             "orientation": None if r.orientation_deg is None else round(r.orientation_deg, 1)} for r in regions])
        self.feedback_message = f"{len(regions)} objects"
        return Status.SUCCESS


class RememberAppearance(CslBehaviour):
    """Start on the next object: remember its pixel count and open its run-time tree
    from where the robot stands."""

    def __init__(self, services: Services, name: str = "RememberAppearance") -> None:
        super().__init__(name, services)
        self.bb.register_key("objects", access=Access.WRITE)
        self.bb.register_key("results", access=Access.WRITE)

    def update(self) -> Status:
        if not self.bb.objects:
            return Status.FAILURE
        region: Region = self.bb.objects.pop(0)
        index = len(self.bb.results)
        services = self.services
        began = services.clock()
        start = relative_position(services.navigator, region, services.robot_pose())
        estimator = PlannerMoveCost(services.navigator, region)
        session = RecognitionSession(services.matrix(), services.criterion, estimator, start,
                                     max_alternatives=services.params.max_alternatives,
                                     orientation_free=region.round)
        record = ObjectRecord(index, region, region.pixel_count, session, estimator, first_region=region)
        record.ledger.computing_s += services.clock() - began
        self.bb.object = record
        self.bb.results.append(record)
        self.note("object", centroid=[round(c, 1) for c in region.centroid], pixels=region.pixel_count,
                  start=start.to_json())
        return Status.SUCCESS


class CheckSideEffects(DriverAction):
    """After a failed grasp, look again: was the object pushed, or changed (knocked over)?

    The pixel count tells them apart (method.md §5): about the same area means the same
    object, moved; a clearly different area means it changed and all sensing is void.
    Succeeds when there were side effects.
    """

    def __init__(self, services: Services, name: str = "SideEffects?") -> None:
        super().__init__(name, services)

    def start(self) -> Future[CameraImage] | Status:
        attempt = self.obj.attempt
        if attempt is None or attempt.success is not False:
            return Status.FAILURE
        return self.services.driver.camera()

    def finish(self, result: CameraImage) -> Status:
        obj, services = self.obj, self.services
        scene = obj.timed(services, lambda: services.navigator.observe(overhead(result)))
        old = obj.region
        near = [r for r in scene.regions
                if math.hypot(r.centroid[0] - old.centroid[0], r.centroid[1] - old.centroid[1]) < 18.0]
        if not near:  # rolled out of sight or merged with something: nothing sensed holds
            obj.side_effect = "changed"
            self.note("side_effect", effect="changed", reason="region lost")
            return Status.SUCCESS
        new = min(near, key=lambda r: math.hypot(r.centroid[0] - old.centroid[0], r.centroid[1] - old.centroid[1]))
        shift = math.hypot(new.centroid[0] - old.centroid[0], new.centroid[1] - old.centroid[1])
        change = abs(new.pixel_count - obj.pixels_before) / max(obj.pixels_before, 1)
        if change > services.params.changed_ratio:
            effect = "changed"
        elif shift > services.params.pushed_in:
            effect = "pushed"
        else:
            effect = None
        obj.side_effect = effect
        self.note("side_effect", effect=effect or "none", shift_in=round(shift, 2), pixels=new.pixel_count)
        if effect is None:
            return Status.FAILURE
        obj.region, obj.pixels_before = new, new.pixel_count
        obj.estimator.retarget(new)
        obj.session.orientation_free = new.round
        return Status.SUCCESS
