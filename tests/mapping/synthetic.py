"""Synthetic planar scans for the mapping's tests and bench: a world of wall segments,
a numpy ray caster over it, and odometry that drifts.

The simulator casts its own rays in pymunk; this caster exists so that the mapping can be
measured and tested on its own, with a truth known exactly (a beam's range is the
distance to the first wall segment it crosses).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Segments = np.ndarray  # (N, 4): x0, y0, x1, y1 in inches


def box(x0: float, y0: float, x1: float, y1: float) -> list[tuple[float, float, float, float]]:
    """The four sides of an axis-aligned rectangle."""
    return [(x0, y0, x1, y0), (x1, y0, x1, y1), (x1, y1, x0, y1), (x0, y1, x0, y0)]


def square_room(side_in: float = 100.0) -> Segments:
    """A ``side_in`` square room with its corner at the origin."""
    return np.array(box(0.0, 0.0, side_in, side_in), dtype=float)


def apartment() -> Segments:
    """Four 240 x 180 in rooms in a 480 x 360 in outline, joined in a ring by 36 in
    doorways, with four pieces of furniture (solid boxes)."""
    walls = box(0.0, 0.0, 480.0, 360.0)
    walls += [(240.0, 0.0, 240.0, 60.0), (240.0, 96.0, 240.0, 260.0), (240.0, 296.0, 240.0, 360.0)]
    walls += [(0.0, 180.0, 100.0, 180.0), (136.0, 180.0, 340.0, 180.0), (376.0, 180.0, 480.0, 180.0)]
    for furniture in ((30.0, 20.0, 80.0, 60.0), (270.0, 120.0, 330.0, 150.0),
                      (40.0, 280.0, 90.0, 330.0), (400.0, 220.0, 450.0, 250.0)):
        walls += box(*furniture)
    return np.array(walls, dtype=float)


# The apartment's loop: room to room through the four doorways, back to the start.
APARTMENT_LOOP = ((120.0, 90.0), (200.0, 78.0), (280.0, 78.0), (358.0, 80.0), (358.0, 200.0),
                  (358.0, 280.0), (280.0, 278.0), (200.0, 278.0), (118.0, 260.0), (118.0, 200.0),
                  (118.0, 150.0), (120.0, 90.0))


def cast(walls: Segments, x_in: float, y_in: float, heading_rad: float, angles_rad: np.ndarray,
         max_range_in: float) -> np.ndarray:
    """The range of each beam to the nearest wall segment (``inf`` beyond ``max_range_in``
    or when it meets none). Beam ``i`` leaves at ``heading_rad + angles_rad[i]``."""
    directions = heading_rad + np.asarray(angles_rad, dtype=float)
    dx, dy = np.cos(directions)[:, None], np.sin(directions)[:, None]
    ex, ey = (walls[:, 2] - walls[:, 0])[None, :], (walls[:, 3] - walls[:, 1])[None, :]
    qx, qy = (walls[:, 0] - x_in)[None, :], (walls[:, 1] - y_in)[None, :]
    denominator = dx * ey - dy * ex
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (qx * ey - qy * ex) / denominator  # along the beam
        u = (qx * dy - qy * dx) / denominator  # along the segment
    hit = (np.abs(denominator) > 1e-12) & (t > 1e-9) & (u >= 0.0) & (u <= 1.0)
    ranges = np.where(hit, t, np.inf).min(axis=1)
    return np.where(ranges <= max_range_in, ranges, np.inf)


@dataclass(frozen=True)
class Lidar:
    """A planar range finder: ``beams`` evenly spaced over 360°, Gaussian range noise,
    a share of beams that return nothing (``inf``)."""

    beams: int = 360
    max_range_in: float = 300.0
    sigma_in: float = 1.0
    dropout: float = 0.1

    @property
    def angles_rad(self) -> np.ndarray:
        return np.arange(self.beams) * (2.0 * math.pi / self.beams)

    def scan(self, walls: Segments, pose: tuple[float, float, float], rng: np.random.Generator) -> np.ndarray:
        """Noisy ranges from ``pose`` (x_in, y_in, heading_rad)."""
        ranges = cast(walls, pose[0], pose[1], pose[2], self.angles_rad, self.max_range_in)
        ranges = ranges + rng.normal(0.0, self.sigma_in, ranges.shape)
        ranges[rng.random(ranges.shape) < self.dropout] = np.inf
        return ranges


def loop_poses(waypoints: tuple[tuple[float, float], ...], step_in: float = 4.0,
               turn_step_deg: float = 15.0) -> list[tuple[float, float, float]]:
    """True poses (x_in, y_in, heading_rad) along a polyline: drive ``step_in`` at a time
    facing along it, turn in place ``turn_step_deg`` at a time at each corner."""
    poses: list[tuple[float, float, float]] = []
    heading = math.atan2(waypoints[1][1] - waypoints[0][1], waypoints[1][0] - waypoints[0][0])
    for (x0, y0), (x1, y1) in zip(waypoints, waypoints[1:]):
        direction = math.atan2(y1 - y0, x1 - x0)
        turn = math.remainder(direction - heading, 2.0 * math.pi)
        steps = max(1, math.ceil(abs(math.degrees(turn)) / turn_step_deg))
        poses += [(x0, y0, heading + turn * k / steps) for k in range(1, steps + 1)]
        heading = direction
        pieces = max(1, math.ceil(math.dist((x0, y0), (x1, y1)) / step_in))
        poses += [(x0 + (x1 - x0) * k / pieces, y0 + (y1 - y0) * k / pieces, heading) for k in range(1, pieces)]
    poses.append((waypoints[-1][0], waypoints[-1][1], heading))
    return poses


@dataclass(frozen=True)
class Drift:
    """Wheel odometry's errors: translation scale (bias and per-step noise), heading
    drift per inch driven, turn scale, and per-step heading noise."""

    scale_bias: float = 0.03
    scale_sigma: float = 0.02
    heading_deg_per_in: float = 0.03
    turn_scale_bias: float = 0.02
    heading_sigma_deg: float = 0.2


def relative(a: tuple[float, float, float], b: tuple[float, float, float]) -> tuple[float, float, float]:
    """Pose ``b`` in the frame of pose ``a`` (x, y, heading_rad)."""
    c, s = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return c * dx + s * dy, -s * dx + c * dy, math.remainder(b[2] - a[2], 2.0 * math.pi)


def compose(a: tuple[float, float, float], d: tuple[float, float, float]) -> tuple[float, float, float]:
    """Pose ``a`` moved by ``d`` given in ``a``'s frame."""
    c, s = math.cos(a[2]), math.sin(a[2])
    return a[0] + c * d[0] - s * d[1], a[1] + s * d[0] + c * d[1], a[2] + d[2]


def drifting_odometry(truth: list[tuple[float, float, float]], drift: Drift,
                      rng: np.random.Generator) -> list[tuple[float, float, float]]:
    """The poses a drifting odometry reports along ``truth`` (starting right)."""
    reported = [truth[0]]
    for a, b in zip(truth, truth[1:]):
        dx, dy, dtheta = relative(a, b)
        distance = math.hypot(dx, dy)
        scale = 1.0 + drift.scale_bias + rng.normal(0.0, drift.scale_sigma)
        heading_error = math.radians(drift.heading_deg_per_in * distance + rng.normal(0.0, drift.heading_sigma_deg))
        step = (dx * scale, dy * scale, dtheta * (1.0 + drift.turn_scale_bias) + heading_error)
        reported.append(compose(reported[-1], step))
    return reported


# -- Objects on the floor (mapping/outline.py, mapping/candidates.py) --------------------------
def scene(*parts: list[tuple[float, float, float, float]]) -> Segments:
    """Wall segments and objects' sides together, as the ray caster takes them."""
    return np.array([segment for part in parts for segment in part], dtype=float)


def polygon(corners: list[tuple[float, float]]) -> list[tuple[float, float, float, float]]:
    """The sides of a closed polygon."""
    return [(*a, *b) for a, b in zip(corners, corners[1:] + corners[:1])]


def circle(x_in: float, y_in: float, radius_in: float, sides: int = 24) -> list[tuple[float, float, float, float]]:
    """A round object's outline (a can, a cup) as a ``sides``-gon through its rim (90
    sides stand off the circle by ``r (1 - cos 2°)``, under 0.002 in for a 3.5 in can)."""
    return polygon([(x_in + radius_in * math.cos(2 * math.pi * k / sides),
                     y_in + radius_in * math.sin(2 * math.pi * k / sides)) for k in range(sides)])


def rect(x_in: float, y_in: float, length_in: float, width_in: float,
         yaw_deg: float = 0.0) -> list[tuple[float, float, float, float]]:
    """A rectangular footprint centred at (x, y): ``length_in`` along its heading ``yaw_deg``."""
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    a, b = length_in / 2, width_in / 2
    return polygon([(x_in + c * u - s * v, y_in + s * u + c * v) for u, v in ((a, b), (-a, b), (-a, -b), (a, -b))])


def table_legs(x_in: float, y_in: float, width_in: float, depth_in: float,
               leg_in: float = 2.0) -> list[tuple[float, float, float, float]]:
    """A table as a planar sensor sees it: four square legs flush with its top's corners
    (as the simulator's tables, hero_driver/sim/home.py)."""
    u, v = width_in / 2 - leg_in / 2, depth_in / 2 - leg_in / 2
    return [side for a, b in ((u, v), (-u, v), (-u, -v), (u, -v)) for side in rect(x_in + a, y_in + b, leg_in, leg_in)]
