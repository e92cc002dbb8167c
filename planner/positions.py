"""Learner positions ``(distance, orientation)`` to robot poses and back.

docs/conventions.md fixes the mapping: the sonar sits on the ray from the region's
centroid at world angle ``alpha + theta``, ``distance`` outside the footprint's boundary;
the base is ``sensor_offset_in`` further out, facing the object. The planner owns this
conversion because it owns the region polygons it depends on.
"""

from __future__ import annotations

import math

import numpy as np

from planner.geometry import Pose, ray_exit_distance, unit, wrap_360
from planner.vision import Region
from robot_profile import RobotGeometry


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
