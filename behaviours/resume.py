"""After the driver came back: where the objects are now, and what is left to do.

A driver process that dies and is restarted under the same robot name (``csl run
--wait-driver``) may have lost track of the world, or the world may have been put back
(a restarted simulator starts from its world file). So the executive looks again with
the overhead camera and rebuilds its queue: an object already dealt with stays dealt
with (its region, if still seen, is not queued again), the object in hand is found
again near where it was and resumed from where the robot now stands (its recognition
session keeps every value measured), and every other region seen is queued, nearest
first. Where the robot stands is asked of the driver afresh.
"""

from __future__ import annotations

import math
from typing import Any, Protocol, runtime_checkable

import py_trees
from py_trees.common import Access

from behaviours.bridge import to_planner_pose
from behaviours.events import Event
from behaviours.records import ObjectRecord, Step
from behaviours.services import Services, namespace
from hero_driver.interface import UNAVAILABLE, DriverError
from planner import Pose as PlannerPose, Region
from robot_profile import ProfileStamp

SAME_OBJECT_IN = 18.0  # a region this close to where an object was is that object (as SideEffects? judges)


@runtime_checkable
class Reconnecting(Protocol):
    """A driver that can tell whether one serves the robot now (the zenoh client
    follows the driver's liveliness token); the in-process simulator cannot be lost."""

    @property
    def alive(self) -> bool: ...

    def wait_ready(self, timeout_s: float) -> bool: ...


def same_robot(services: Services, robot: str) -> None:
    """Raise ``DriverError(unavailable)`` when the driver that came back says it serves
    another robot profile than the one at the start (a larger base or other procedure
    times would make every plan and cost wrong without an error); a driver that does
    not say is taken at its word, as at the start."""
    served = getattr(services.driver, "profile", None)
    before = services.served
    if before is not None and isinstance(served, ProfileStamp) and served.sha256 != before.sha256:
        raise DriverError(UNAVAILABLE, f"the driver that came back for robot {robot} serves robot profile "
                          f"{served.name} (sha256 {served.sha256[:12]}), not {before.name} "
                          f"(sha256 {before.sha256[:12]})")


def relocate(services: Services, robot: str, observation: Any, reason: str) -> list[Region]:
    """Rebuild the object queue from a look (``observation``: the module docstring says how); the
    regions queued, nearest first. Logs a ``located`` event with ``again`` = ``reason``."""
    board = py_trees.blackboard.Client(name="relocate", namespace=namespace(robot))
    for key in ("objects", "object", "step", "pose"):
        board.register_key(key, access=Access.WRITE)
    board.register_key("results", access=Access.READ)
    scene = services.perception.scene(observation)
    board.pose = None  # where the robot stands: the driver says, not the end of our last move
    here = to_planner_pose(services.driver.state().pose)
    seen = list(scene.regions)
    for record in board.results:
        if record.done:  # where it was last seen, or where it lay first (a world put back)
            if _take_nearest(seen, record.region) is None:
                _take_nearest(seen, record.first_region)
    obj: ObjectRecord | None = board.object
    if obj is not None and not obj.done:
        found = _take_nearest(seen, obj.region)
        if found is not None:
            obj.region, obj.pixels_before = found, found.pixel_count
            obj.estimator.retarget(found)
        obj.session.position = obj.estimator.stand_at(here)
        board.step = Step()  # the step under way when the driver went starts again
    queue = sorted(seen, key=lambda r: (_distance(r.centroid, here), r.centroid))
    board.objects = queue
    services.log.event(Event.LOCATED, behaviour="relocate", again=reason, regions=[
        {"centroid": [round(c, 1) for c in r.centroid], "pixels": r.pixel_count,
         "orientation": None if r.orientation_deg is None else round(r.orientation_deg, 1)} for r in queue])
    return queue


def _take_nearest(regions: list[Region], near: Region) -> Region | None:
    """Remove and return the region of ``regions`` nearest ``near`` if it is the same object."""
    if not regions:
        return None
    best = min(regions, key=lambda r: _distance(r.centroid, near.centroid))
    if _distance(best.centroid, near.centroid) >= SAME_OBJECT_IN:
        return None
    regions.remove(best)
    return best


def _distance(a: tuple[float, float], b: tuple[float, float] | PlannerPose) -> float:
    bx, by = (b.x_in, b.y_in) if isinstance(b, PlannerPose) else b
    return math.hypot(a[0] - bx, a[1] - by)
