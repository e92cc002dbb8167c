"""The seven sonar procedures, computed from the world's geometry.

Each procedure is a small model of what the HERO's arm does with its wrist sonar:
sweeps rotate the sonar at the sonar point and count the beam directions whose first
echo comes from the object (so an angular size is a multiple of the step); scans
translate it in 0.3 in steps and count the positions that see the object. The exact
("ideal") values are derived here; :mod:`hero_driver.sim.noise` turns them into
measurements. What each value means is the driver contract's (docs/driver-protocol.md,
"Sensing features"); what the simulator adds to it, docs/simulator.md ("Sensing").
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from hero_driver.sim.physics import Physics, SimObject

SCAN_STEP_IN = 0.3
SCAN_HALF_SPAN_IN = 30.0  # how far to each side an H-Scan translates the sonar
FACE_NORMALS = {"+x": (1.0, 0.0), "-x": (-1.0, 0.0), "+y": (0.0, 1.0), "-y": (0.0, -1.0)}
END_ON_COS = math.cos(math.radians(45.0))


@dataclass(frozen=True)
class Aim:
    """Where the sonar is and what it points at: the geometry every procedure needs."""

    sonar: tuple[float, float]
    heading_deg: float
    target: SimObject
    distance_in: float  # sonar to the target's footprint along the heading
    sensor_height_in: float
    max_range_in: float
    raised_height_in: float  # the wrist raised to look down across the top (S-Sweep)

    @property
    def u(self) -> tuple[float, float]:
        h = math.radians(self.heading_deg)
        return math.cos(h), math.sin(h)


def find_target(physics: Physics, sonar: tuple[float, float], heading_deg: float,
                reach_in: float) -> tuple[SimObject | None, float]:
    """The object whose footprint the heading ray meets first, and the ray's length
    (docs/conventions.md's distance); (None, length) when a wall or nothing is first."""
    h = math.radians(heading_deg)
    end = (sonar[0] + reach_in * math.cos(h), sonar[1] + reach_in * math.sin(h))
    hit = physics.ray(sonar, end)
    if hit is None:
        return None, reach_in
    return physics.owner(hit.shape), float(hit.alpha) * reach_in


def approach_is_end_on(heading_deg: float, obj: SimObject) -> bool:
    """Whether the robot looks along the object's major axis (within 45°)."""
    return abs(math.cos(math.radians(heading_deg - obj.yaw_deg))) >= END_ON_COS


def incidence_deg(aim: Aim) -> float | None:
    """Angle between the heading and the normal of the target's face where the heading
    ray meets it, for the specular effect; None for a round (circular) footprint, whose
    curved side always has a patch square to the beam."""
    if aim.target.entry.footprint.shape == "circle":
        return None
    ux, uy = aim.u
    reach = aim.distance_in + 2.0 * aim.max_range_in
    hit = aim.target.shape.segment_query(aim.sonar, (aim.sonar[0] + reach * ux, aim.sonar[1] + reach * uy), 0.0)
    if hit.shape is None:
        return None
    cos = -(hit.normal.x * ux + hit.normal.y * uy)
    return math.degrees(math.acos(max(-1.0, min(1.0, cos))))


def _grid_count(lo_deg: float, hi_deg: float, step: float) -> int:
    """Beam directions k*step (k integer) within [lo, hi]."""
    return max(0, math.floor(hi_deg / step + 1e-9) - math.ceil(lo_deg / step - 1e-9) + 1)


def _central_chord(aim: Aim) -> float:
    """Length of the heading line inside the footprint, sampled every scan step (the
    D-Scan's positions over the top); also the depth a vertical sweep sees."""
    ux, uy = aim.u
    start = aim.distance_in + SCAN_STEP_IN / 2
    inside, k = 0, 0
    while True:
        s = start + k * SCAN_STEP_IN
        p = (aim.sonar[0] + s * ux, aim.sonar[1] + s * uy)
        if aim.target.shape.point_query(p).distance <= 0:
            inside += 1
        elif k > 0 and inside > 0:
            break
        k += 1
        if k * SCAN_STEP_IN > 200:
            break
    return inside * SCAN_STEP_IN


def horizontal_sweep(physics: Physics, aim: Aim, step_deg: float) -> float:
    """Width-Degree: beams k*step around the heading whose first echo is the target."""
    hits = 0
    for k in range(-math.floor(90 / step_deg), math.floor(90 / step_deg) + 1):
        a = math.radians(aim.heading_deg + k * step_deg)
        end = (aim.sonar[0] + aim.max_range_in * math.cos(a), aim.sonar[1] + aim.max_range_in * math.sin(a))
        hit = physics.ray(aim.sonar, end)
        if hit is not None and physics.owner(hit.shape) is aim.target:
            hits += 1
    return hits * step_deg


def vertical_sweep(aim: Aim, step_deg: float) -> float:
    """Height-Degree: elevations from the front face's foot to its top edge (or, for an
    object lower than the sonar, to the far edge of its top)."""
    h, hs, d = aim.target.entry.height_in, aim.sensor_height_in, aim.distance_in
    lo = math.degrees(math.atan2(-hs, d))
    far = d if h >= hs else d + _central_chord(aim)
    hi = math.degrees(math.atan2(h - hs, far))
    return _grid_count(lo, hi, step_deg) * step_deg


def depth_sweep(aim: Aim, step_deg: float) -> float:
    """Depth-Degree: from the wrist raised to the profile's ``raised_sensor_height_in``, the depression angles
    between the near and the far edge of the object's top."""
    drop = aim.raised_height_in - aim.target.entry.height_in
    if drop <= 0:
        return 0.0
    near = math.degrees(math.atan2(drop, aim.distance_in))
    far = math.degrees(math.atan2(drop, aim.distance_in + _central_chord(aim)))
    return _grid_count(far, near, step_deg) * step_deg


def horizontal_scan_width(physics: Physics, aim: Aim) -> float:
    """Width: sonar positions, 0.3 in apart across the heading (centred on half steps
    so the count rounds the width to the nearest step), whose straight-ahead echo comes
    from the target."""
    ux, uy = aim.u
    px, py = -uy, ux
    reach = aim.distance_in + 40.0
    hits = 0
    k_max = math.ceil(SCAN_HALF_SPAN_IN / SCAN_STEP_IN)
    for k in range(-k_max, k_max):
        o = (k + 0.5) * SCAN_STEP_IN
        start = (aim.sonar[0] + o * px, aim.sonar[1] + o * py)
        hit = physics.ray(start, (start[0] + reach * ux, start[1] + reach * uy))
        if hit is not None and physics.owner(hit.shape) is aim.target:
            hits += 1
    return hits * SCAN_STEP_IN


def front_hole(aim: Aim) -> bool:
    """An opening is seen when its face turns to the sonar (normal within 45°)."""
    face = aim.target.entry.front_hole
    if face is None:
        return False
    nx, ny = FACE_NORMALS[face]
    yaw = aim.target.body.angle
    wx, wy = nx * math.cos(yaw) - ny * math.sin(yaw), nx * math.sin(yaw) + ny * math.cos(yaw)
    ux, uy = aim.u
    return -(wx * ux + wy * uy) >= END_ON_COS


def scan_height(aim: Aim) -> float:
    """Height: scan positions 0.3 in apart from the floor up that see the object."""
    return math.floor(aim.target.entry.height_in / SCAN_STEP_IN + 0.5) * SCAN_STEP_IN


# Ideal feature values per procedure: feature name -> (value, quantum for noise).
Ideal = dict[str, tuple[float, float]]
PROCEDURES: dict[str, Callable[[Physics, Aim], Ideal]] = {
    "H-Sweep-1°": lambda ph, aim: {"Width-Degree-1°": (horizontal_sweep(ph, aim, 1.0), 1.0)},
    "H-Sweep-5°": lambda ph, aim: {"Width-Degree-5°": (horizontal_sweep(ph, aim, 5.0), 5.0)},
    "V-Sweep-1°": lambda ph, aim: {"Height-Degree-1°": (vertical_sweep(aim, 1.0), 1.0)},
    "V-Sweep-5°": lambda ph, aim: {"Height-Degree-5°": (vertical_sweep(aim, 5.0), 5.0)},
    "S-Sweep-1°": lambda ph, aim: {"Depth-Degree-1°": (depth_sweep(aim, 1.0), 1.0)},
    "H-Scan-0.3": lambda ph, aim: {"Width": (horizontal_scan_width(ph, aim), 0.0),
                                   "Front-Hole?": (float(front_hole(aim)), 0.0)},
    "D-Scan-0.3": lambda ph, aim: {"Height": (scan_height(aim), 0.0),
                                   "Depth": (_central_chord(aim), 0.0),
                                   "Top-Hole?": (float(aim.target.entry.top_hole), 0.0)},
}

# Procedures whose beam meets the object's side (the S-Sweep looks down on its top), so
# a flat side met at a grazing angle can reflect their echo away.
SIDE_LOOKING = frozenset(PROCEDURES) - {"S-Sweep-1°"}
