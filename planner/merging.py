"""Objects that came to touch since the last image: one region where two were.

One image cannot always tell two touching objects from one bigger object: two round
footprints merged side by side, or a small box against a long side, make a blob that
is nearly convex and has no pinch to cut at (:func:`planner.vision.split_touching`),
so :func:`planner.vision.look` reports it as one region, not a cluster. Objects on a
floor do not start out touching that often; they are pushed together (a failed grasp
moves an object an inch or two) or knocked over onto a neighbour. The camera saw them
apart before, and that is what tells a merge from a big object. Each region of the
previous image became the new region its centroid lies in or is nearest to, within a
push (:data:`PUSHED_IN` of its outline; further from all, it went). A new region that
two earlier regions became, and that covers about their joint area, is two objects
that now touch: a cluster (``Region.cluster``: no sonar reading of it is the object's
alone; docs/planner.md "Clutter").

A long push can carry an object further than :data:`PUSHED_IN` into its neighbour (the
simulator's default push is up to 4.2 in, and a pushed object shoves what it meets):
its region then has no successor within a push, and the neighbour's region grows by
its area. So a region that went counts as a part of the nearest new region within
:data:`LONG_PUSH_IN` of its outline for the joint-area test (never for a cluster seen
again), unless the robot now stands where it was (hidden, not moved). Objects do not
vanish beside a neighbour that grows by their area: one grasped or taken away leaves
the neighbour as it was.

Two guards keep a lone object from being called a cluster:
- the two earlier regions must have been apart for real, not only because the robot
  hid what lay between them (vision drops object pixels next to the robot's body, so
  the robot standing over a long object's middle can leave two pieces of it): their
  centroids' segment must pass clear of the robot's disc in the earlier image;
- the new region must cover the larger part and at least half the smaller
  (:data:`JOINT_AREA_SHARE`), so an object next to a neighbour that was grasped and
  taken away, the neighbour's centroid within a push of it, is not two objects.

A cluster stays one in the next image while the region it became keeps most of its
area (:data:`KEPT_AREA_SHARE`) and no new region turns up within a push of it:
touching objects do not come apart by themselves; an object taken out of the pair
leaves a region clearly smaller than the pair, and one pushed off it is a region no
earlier one became.
"""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np

from planner.geometry import Pose
from planner.vision import Region, Scene

JOINT_AREA_SHARE = 0.5  # a merged region covers the larger part and at least this share of the smaller
PUSHED_IN = 3.0  # an earlier region's centroid this far outside a new region's outline may have been pushed into it
LONG_PUSH_IN = 6.0  # a region with no successor within a push may have been pushed this far into a neighbour
KEPT_AREA_SHARE = 0.85  # a cluster seen again keeps at least this share of its area
HIDDEN_MARGIN_IN = 2.0  # beyond the base radius: the rim of object pixels vision drops next to the robot


def flag_merged(before: Scene | None, now: Scene, base_radius_in: float) -> Scene:
    """``now`` with every region that merged since ``before`` (or is a cluster seen
    again) marked ``cluster``; ``now`` itself when nothing merged or there is no
    earlier image."""
    if before is None or not before.regions or not now.regions:
        return now
    parts: dict[int, list[Region]] = {}
    pushed_far: dict[int, list[Region]] = {}
    for earlier in before.regions:
        at, reach = _nearest(earlier, now.regions)
        if reach >= -PUSHED_IN:
            parts.setdefault(at, []).append(earlier)
        elif reach >= -LONG_PUSH_IN and not _near(earlier.centroid, now.robot, base_radius_in + HIDDEN_MARGIN_IN):
            pushed_far.setdefault(at, []).append(earlier)
    newcomers = [r for i, r in enumerate(now.regions) if i not in parts]
    flagged = tuple(dataclasses.replace(r, cluster=True)
                    if not r.cluster and _merged(r, parts.get(i, []), pushed_far.get(i, []), newcomers,
                                                 before.robot, base_radius_in) else r
                    for i, r in enumerate(now.regions))
    if all(a is b for a, b in zip(flagged, now.regions)):
        return now
    return dataclasses.replace(now, regions=flagged)


def _nearest(earlier: Region, regions: tuple[Region, ...]) -> tuple[int, float]:
    """The index of the new region an earlier one's centroid lies in or is nearest to,
    and how far inside its outline the centroid lies (negative: outside). Within
    :data:`PUSHED_IN` that region is what the earlier one became (a push moves an object
    an inch or two); further, the object went, or a long push carried it there."""
    reach = [_reach(r, earlier.centroid) for r in regions]
    best = max(range(len(regions)), key=reach.__getitem__)
    return best, reach[best]


def _reach(region: Region, point: tuple[float, float]) -> float:
    """How far ``point`` lies inside ``region``'s outline (negative: outside)."""
    return float(cv2.pointPolygonTest(region.polygon_array().astype(np.float32), point, True))


def within_push(region: Region, point: tuple[float, float]) -> bool:
    """Whether ``point`` lies inside ``region``'s outline or within a push (:data:`PUSHED_IN`) of it."""
    return _reach(region, point) >= -PUSHED_IN


def _merged(region: Region, parts: list[Region], pushed_far: list[Region], newcomers: list[Region],
            robot: Pose | None, base_radius_in: float) -> bool:
    """Whether ``region`` is the earlier ``parts`` (the earlier regions it became) touching,
    or a cluster seen again; ``pushed_far``: earlier regions that went, perhaps pushed
    into it from beyond a push; ``newcomers``: the new image's regions no earlier one became."""
    if any(p.cluster and region.pixel_count >= KEPT_AREA_SHARE * p.pixel_count
           and not any(within_push(p, r.centroid) for r in newcomers) for p in parts):
        return True
    joined = parts + pushed_far
    return any(region.pixel_count >= max(a.pixel_count, b.pixel_count) + JOINT_AREA_SHARE * min(a.pixel_count, b.pixel_count)
               and not _hidden_between(a, b, robot, base_radius_in + HIDDEN_MARGIN_IN)
               for i, a in enumerate(joined) for b in joined[i + 1:])


def _near(point: tuple[float, float], robot: Pose | None, radius_in: float) -> bool:
    """Whether ``point`` lies within ``radius_in`` of the robot (None: no robot seen)."""
    return robot is not None and math.hypot(point[0] - robot.x_in, point[1] - robot.y_in) < radius_in


def _hidden_between(a: Region, b: Region, robot: Pose | None, radius_in: float) -> bool:
    """True when the segment between the two centroids passes within ``radius_in`` of
    the robot: the gap between them may be the robot's shadow on one object."""
    if robot is None:
        return False
    (ax, ay), (bx, by) = a.centroid, b.centroid
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0 else min(max(((robot.x_in - ax) * dx + (robot.y_in - ay) * dy) / length2, 0.0), 1.0)
    return math.hypot(ax + t * dx - robot.x_in, ay + t * dy - robot.y_in) < radius_in
