"""Plane geometry in world inches and degrees: poses, angles, rays against polygons.

The planner keeps its own :class:`Pose` (same fields as the driver's) so that it depends
on nothing of ``hero_driver``; the executive converts between the two field by field.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Pose:
    """A robot base's centre and heading: world inches, degrees counter-clockwise from +x."""

    x_in: float
    y_in: float
    heading_deg: float

    def require_finite(self, what: str) -> None:
        """Raise ValueError naming ``what`` when a coordinate is NaN or infinite."""
        if not all(math.isfinite(v) for v in (self.x_in, self.y_in, self.heading_deg)):
            raise ValueError(f"{what} pose is not finite: {self}")


def wrap_360(angle_deg: float) -> float:
    """An angle in [0, 360): the paper writes orientations as 0, 90, 181, 272."""
    wrapped = angle_deg % 360.0
    return 0.0 if wrapped >= 360.0 else wrapped


def angle_between(a_deg: float, b_deg: float) -> float:
    """The unsigned smallest rotation from ``a_deg`` to ``b_deg``, in [0, 180]."""
    diff = abs((b_deg - a_deg) % 360.0)
    return min(diff, 360.0 - diff)


def unit(angle_deg: float) -> np.ndarray:
    """The unit vector at a world angle."""
    rad = math.radians(angle_deg)
    return np.array([math.cos(rad), math.sin(rad)])


def ray_exit_distance(origin: np.ndarray, direction: np.ndarray, polygon: np.ndarray) -> float:
    """Distance from ``origin`` along unit ``direction`` to the polygon's last boundary crossing.

    The last crossing (not the first) is used so that a point placed beyond it is
    outside the footprint even for a concave outline; an origin outside a polygon the
    ray misses gives 0.
    """
    edges = np.roll(polygon, -1, axis=0) - polygon
    # Solve origin + t * direction = start + s * edge for every edge not parallel to
    # the ray, all at once.
    denom = direction[0] * edges[:, 1] - direction[1] * edges[:, 0]
    crossing = np.abs(denom) > 1e-12
    rel = polygon[crossing] - origin
    edges, denom = edges[crossing], denom[crossing]
    t = (rel[:, 0] * edges[:, 1] - rel[:, 1] * edges[:, 0]) / denom
    s = (rel[:, 0] * direction[1] - rel[:, 1] * direction[0]) / denom
    hits = (s >= -1e-9) & (s <= 1 + 1e-9) & (t >= 0)
    return float(t[hits].max()) if hits.any() else 0.0


def counter_clockwise(polygon: np.ndarray) -> np.ndarray:
    """An Nx2 polygon's corners in counter-clockwise order (reversed when clockwise)."""
    x, y = polygon[:, 0], polygon[:, 1]
    signed_area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    return polygon if signed_area >= 0 else polygon[::-1]
