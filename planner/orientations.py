"""Training orientations (method.md §4, phase 1): where sonar meets object faces squarely.

Sonar works best perpendicular to a face, so every edge of every object's overhead
polygon proposes the orientation of its outward normal, measured from the object's
reference axis and weighted by the edge's length; the proposals of all objects are
clustered into a few. A round footprint has no faces: it proposes 0° only (Table 3's
upright cups alone give just 0°).
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np

from planner.geometry import wrap_360
from planner.vision import Region

# A cluster lighter than this share of all edge length is a corner artefact of the
# pixel staircase, not a face.
MIN_CLUSTER_SHARE = 0.05


def face_normals(region: Region) -> list[tuple[float, float]]:
    """(orientation in degrees relative to the reference axis, weight) per face.

    The weight is the edge length in inches; a round region gives one proposal, 0°,
    weighted by its perimeter so that it counts like a box of the same size.
    """
    polygon = region.polygon_array()
    edges = np.roll(polygon, -1, axis=0) - polygon
    lengths = np.hypot(edges[:, 0], edges[:, 1])
    if region.round:
        return [(0.0, float(lengths.sum()))]
    alpha = region.reference_axis_deg
    # Polygons are counter-clockwise, so the outward normal is the edge turned by -90°.
    normals = np.degrees(np.arctan2(-edges[:, 0], edges[:, 1]))
    return [(wrap_360(float(n) - alpha), float(w)) for n, w in zip(normals, lengths) if w > 0]


def training_orientations(regions: Iterable[Region], tolerance_deg: float = 20.0) -> list[float]:
    """Cluster the face normals of all regions into a few orientations, in [0, 360).

    Greedy peak picking on the circle: the orientation whose ±``tolerance_deg``
    neighbourhood carries the most edge length becomes a cluster (centred on the
    weighted circular mean of its members), its members are removed, and so on until
    what is left is lighter than ``MIN_CLUSTER_SHARE`` of the total. Unlike chaining
    nearby angles, this cannot merge a whole staircase of corner edges into one blob.
    """
    if not (math.isfinite(tolerance_deg) and 0 < tolerance_deg < 180):
        raise ValueError(f"tolerance_deg must be in (0, 180), got {tolerance_deg}")
    proposals = [p for region in regions for p in face_normals(region)]
    if not proposals:
        return []
    angles = np.array([a for a, _ in proposals])
    weights = np.array([w for _, w in proposals])
    total = float(weights.sum())
    remaining = np.ones(len(angles), dtype=bool)
    centres: list[float] = []
    while remaining.any() and weights[remaining].sum() >= MIN_CLUSTER_SHARE * total:
        near = _circular_distance(angles[:, None], angles[None, :]) <= tolerance_deg
        support = (near & remaining[None, :]) @ weights
        support[~remaining] = -1.0
        peak = int(np.argmax(support))
        members = near[peak] & remaining
        if weights[members].sum() >= MIN_CLUSTER_SHARE * total:
            centres.append(_circular_mean(angles[members], weights[members]))
        remaining &= ~members
    return sorted(centres)


def _circular_distance(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    diff = np.abs((a - b) % 360.0)
    return np.minimum(diff, 360.0 - diff)


def _circular_mean(angles_deg: np.ndarray, weights: np.ndarray) -> float:
    rad = np.radians(angles_deg)
    mean = math.degrees(math.atan2(float(weights @ np.sin(rad)), float(weights @ np.cos(rad))))
    return round(wrap_360(mean), 1)
