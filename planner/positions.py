"""Learner positions ``(distance, orientation)`` to robot poses and back.

docs/conventions.md fixes the mapping: the sonar sits on the ray from the region's
centroid at world angle ``alpha + theta``, ``distance`` outside the footprint's boundary;
the base is ``sensor_offset_in`` further out, facing the object. The planner owns this
conversion because it owns the region polygons it depends on.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence

import cv2
import numpy as np

from planner.geometry import Pose, ray_exit_distance, unit, wrap_360
from planner.vision import Region
from robot_profile import RobotGeometry

# docs/conventions.md: every driver accepts a procedure within 1.5 in of its range, so a
# sonar up to this far from the asked distance still applies the procedure.
RANGE_TOLERANCE_IN = 1.5
# Distances tried, nearest to the asked one first, when its pose is blocked.
TOLERANCE_STEP_IN = 0.1


def face_distance_in(region: Region, orientation_deg: float) -> float:
    """``r_face``: centroid to footprint boundary along ``alpha + orientation``."""
    direction = unit(region.reference_axis_deg + orientation_deg)
    return ray_exit_distance(np.asarray(region.centroid), direction, region.polygon_array())


def pose_for_position(region: Region, distance_in: float, orientation_deg: float,
                      robot: RobotGeometry) -> Pose:
    """The base pose that puts the sonar at ``(distance_in, orientation_deg)`` of ``region``."""
    if not (math.isfinite(distance_in) and math.isfinite(orientation_deg)):
        raise ValueError(f"position must be finite, got ({distance_in}, {orientation_deg})")
    world_deg = region.reference_axis_deg + orientation_deg
    u = unit(world_deg)
    r_face = face_distance_in(region, orientation_deg)
    base = np.asarray(region.centroid) + (r_face + distance_in + robot.sensor_offset_in) * u
    return Pose(float(base[0]), float(base[1]), wrap_360(world_deg + 180.0))


def position_of(region: Region, pose: Pose, robot: RobotGeometry) -> tuple[float, float]:
    """The ``(distance_in, orientation_deg)`` of a robot pose's sonar relative to ``region``.

    The sonar is ``sensor_offset_in`` ahead of the base along its heading; its direction
    from the centroid gives the orientation (in [0, 360), from the reference axis) and
    its distance beyond the footprint boundary on that ray gives the distance. For any
    pose :func:`pose_for_position` returns this is its exact inverse; for a robot not
    facing the object it still says where the sensor is.
    """
    pose.require_finite("robot")
    sonar = np.array([pose.x_in, pose.y_in]) + robot.sensor_offset_in * unit(pose.heading_deg)
    rel = sonar - np.asarray(region.centroid)
    world_deg = math.degrees(math.atan2(rel[1], rel[0]))
    orientation = wrap_360(world_deg - region.reference_axis_deg)
    distance = float(np.hypot(rel[0], rel[1])) - face_distance_in(region, orientation)
    return distance, orientation


def free_pose_for_position(region: Region, distance_in: float, orientation_deg: float, robot: RobotGeometry,
                           is_free: Callable[[float, float], bool]) -> Pose:
    """The pose for ``(distance_in, orientation_deg)``, or, when its base would stand in
    an (inflated) obstacle, the nearest one on the same ray whose sonar distance stays
    within :data:`RANGE_TOLERANCE_IN` of it and whose base ``is_free``.

    A wall or another object just behind a test position need not rule the test out:
    the procedure still applies an inch nearer or farther (the range tolerance every
    driver grants), on the same face, so its value is recorded for the asked position.
    Distances are tried in :data:`TOLERANCE_STEP_IN` steps, nearest first, farther
    before nearer at equal shifts; when none is free the asked pose is returned and the
    move costs price it as blocked, so the learner does not use the test.
    """
    pose = pose_for_position(region, distance_in, orientation_deg, robot)
    if is_free(pose.x_in, pose.y_in):
        return pose
    u = unit(region.reference_axis_deg + orientation_deg)  # the ray the base stands on, outwards
    asked = np.array([pose.x_in, pose.y_in])
    steps = int(round(RANGE_TOLERANCE_IN / TOLERANCE_STEP_IN))
    for k in range(1, steps + 1):
        for shift in (k * TOLERANCE_STEP_IN, -k * TOLERANCE_STEP_IN):
            if distance_in + shift < 0:
                continue
            base = asked + shift * u
            if is_free(float(base[0]), float(base[1])):
                return Pose(float(base[0]), float(base[1]), pose.heading_deg)
    return pose


# A neighbour this close to the beam's corridor still echoes into it (the footprint is
# known to a pixel or so, docs/planner.md "Clutter"): the beam is not clear.
BEAM_MARGIN_IN = 1.0
# Beyond the margin by more than this, a neighbour's bounding box needs no closer look:
# far above any rounding in the gap's arithmetic, far below anything a footprint shows.
_BOX_SLACK_IN = 1e-6


def beam_corridor(region: Region, distance_in: float, orientation_deg: float) -> np.ndarray:
    """Where a sensing procedure's sound travels from ``(distance_in, orientation_deg)``
    to ``region``: the convex hull of the object's footprint, the sonar point and the
    sonar point shifted either way across the heading by the footprint's half width.

    It covers what every procedure's first echo could come from: a sweep's rays fan
    from the sonar point to the footprint (the hull of the point and the footprint),
    a scan translates the sonar across the face (the corridor as wide as the object).
    Anything inside it can echo before the target does (docs/planner.md "Clutter").
    """
    u = unit(region.reference_axis_deg + orientation_deg)
    across = np.array([-u[1], u[0]])
    centre = np.asarray(region.centroid)
    polygon = region.polygon_array()
    half_width = float(np.max(np.abs((polygon - centre) @ across)))
    sonar = centre + (face_distance_in(region, orientation_deg) + max(distance_in, 0.0)) * u
    points = np.vstack([polygon, sonar, sonar + half_width * across, sonar - half_width * across])
    return _convex_hull(points)


def beam_blockers(region: Region, distance_in: float, orientation_deg: float,
                  others: Sequence[Region], margin_in: float = BEAM_MARGIN_IN) -> list[Region]:
    """The regions of ``others`` (any object but ``region``) within ``margin_in`` of the
    beam's corridor from this position: each would echo into the procedure, so a
    reading taken there may describe the neighbour, not the object."""
    corridor = beam_corridor(region, distance_in, orientation_deg)
    # Two shapes are at least as far apart as their bounding boxes: a neighbour whose box
    # lies beyond the margin of the corridor's is no blocker, and most of a floor's are
    # (the beam check is asked at every position the learner prices). The boxes are of
    # the points the hulls are made of, with a hair to spare, so the gap alone decides
    # every neighbour it ever did.
    reach = margin_in + _BOX_SLACK_IN
    low, high = corridor.min(axis=0) - reach, corridor.max(axis=0) + reach
    blockers = []
    for o in others:
        if o.centroid == region.centroid:
            continue
        points = _hull_points(o.polygon_array())
        if (points.max(axis=0) < low).any() or (points.min(axis=0) > high).any():
            continue
        if _convex_gap(corridor, _convex_hull(points)) <= margin_in:
            blockers.append(o)
    return blockers


def neighbours(region: Region, regions: Sequence[Region], same_within_in: float) -> list[Region]:
    """Every region of ``regions`` but ``region`` itself (the one whose centroid lies
    within ``same_within_in`` of its own: the same object seen anew in a later image)."""
    cx, cy = region.centroid
    return [r for r in regions if math.hypot(r.centroid[0] - cx, r.centroid[1] - cy) > same_within_in]


def _hull_points(points: np.ndarray) -> np.ndarray:
    """``points`` as :func:`_convex_hull` takes them (OpenCV's hull is of 32-bit floats)."""
    return np.asarray(points, dtype=np.float32)


def _convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise hull of ``points`` (Nx2 floats), as an Mx2 array."""
    hull = cv2.convexHull(_hull_points(points)).reshape(-1, 2)
    return hull.astype(float)


def _convex_gap(a: np.ndarray, b: np.ndarray) -> float:
    """The distance between two convex polygons (0 when they overlap)."""
    if _overlap(a, b):
        return 0.0
    return min(_points_to_edges(a, b), _points_to_edges(b, a))


def _overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Separating-axis test: convex ``a`` and ``b`` overlap unless an edge normal parts them."""
    for poly in (a, b):
        edges = np.roll(poly, -1, axis=0) - poly
        for edge in edges:
            normal = np.array([-edge[1], edge[0]])
            pa, pb = a @ normal, b @ normal
            if pa.max() < pb.min() or pb.max() < pa.min():
                return False
    return True


def _points_to_edges(points: np.ndarray, polygon: np.ndarray) -> float:
    """The distance from the nearest of ``points`` to the nearest edge of ``polygon``:
    every point against every edge in one array (a beam's blockers are asked of every
    neighbour at every position the learner prices)."""
    start, end = polygon, np.roll(polygon, -1, axis=0)
    edge = end - start
    length2 = np.maximum((edge ** 2).sum(axis=1), 1e-12)
    offset = points[:, None, :] - start[None, :, :]  # point by edge by (x, y)
    t = np.clip((offset * edge).sum(axis=2) / length2, 0.0, 1.0)
    nearest = start + t[..., None] * edge
    return float(np.min(np.hypot(*(points[:, None, :] - nearest).transpose(2, 0, 1))))
