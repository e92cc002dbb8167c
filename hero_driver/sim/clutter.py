"""Clutter: objects placed close together, drawn from a seed.

The paper's CSL "assumes that objects are apart" (docs/method.md). A cluttered floor
breaks that on purpose: a share ``rate`` of the floor's objects each get a neighbour,
another object of the floor moved next to it, ``gap_in`` inches from it edge to edge
(footprint to footprint, at a random bearing and turn). Objects closer than the HERO's
base width (docs/simulator.md "Clutter") are what the camera must still separate, the
planner must reach a test position between, and whose sonar echoes may contaminate
each other's readings. The layout stays a world file's JSON, so the simulator's
loader checks it as any other (nothing overlaps, nothing outside the room).
"""

from __future__ import annotations

import copy
import math
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from hero_driver.interface import DriverError
from hero_driver.sim.catalogue import CatalogueEntry
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import Placement, footprint_polygon

BEARINGS_TRIED = 36  # bearings (and turns) tried per neighbour before it stays where it was
WALL_CLEARANCE_IN = 2.0  # a moved neighbour keeps this far from the room's walls


@dataclass(frozen=True)
class Clutter:
    """How cluttered a floor is: the share of objects given a neighbour and how far
    apart the two stand, edge to edge."""

    rate: float
    gap_in: float

    def __post_init__(self) -> None:
        if not 0.0 <= self.rate <= 1.0:
            raise ValueError(f"clutter rate must be within 0..1, got {self.rate}")
        if not (math.isfinite(self.gap_in) and self.gap_in > 0.0):
            raise ValueError(f"clutter gap_in must be a positive number of inches, got {self.gap_in}")


def cluttered(world: Mapping[str, object], catalogue: Mapping[str, CatalogueEntry], clutter: Clutter,
              seed: int) -> dict[str, object]:
    """``world`` (a world file's JSON) with neighbours placed: objects are drawn in a
    seeded order; each, with probability ``rate``, takes the next undrawn object as its
    neighbour, put ``gap_in`` from it where it overlaps nothing and keeps ``gap_in``
    from every other object too (a pair, not a heap). The others stay where they were.
    The result names the clutter in its ``about``."""
    out = copy.deepcopy(dict(world))
    objects: list[dict[str, object]] = out["objects"]  # type: ignore[assignment]
    room = out["room"]  # type: ignore[assignment]
    rng = np.random.default_rng(seed)
    order = [int(i) for i in rng.permutation(len(objects))]
    paired: set[int] = set()
    for at, anchor in enumerate(order):
        if anchor in paired or float(rng.uniform()) >= clutter.rate:
            continue
        partner = next((j for j in order[at + 1:] if j not in paired), None)
        if partner is None:
            break
        if _place_beside(objects, anchor, partner, catalogue, clutter.gap_in, room, rng):  # type: ignore[arg-type]
            paired.update((anchor, partner))
    out["about"] = f"{out.get('about', '')} Cluttered: {len(paired) // 2} pairs {clutter.gap_in:g} in apart " \
                   f"(rate {clutter.rate:g}, seed {seed}).".strip()
    return out


def pairs_of(world: Mapping[str, object], catalogue: Mapping[str, CatalogueEntry],
             within_in: float) -> list[tuple[int, int]]:
    """Indices of the objects whose footprints are within ``within_in`` of each other."""
    polygons = [_polygon(o, catalogue) for o in world["objects"]]  # type: ignore[union-attr]
    return [(i, j) for i in range(len(polygons)) for j in range(i + 1, len(polygons))
            if footprint_gap(polygons[i], polygons[j]) <= within_in]


def footprint_gap(a: np.ndarray, b: np.ndarray) -> float:
    """The distance between two convex outlines (0 when they touch or overlap)."""
    if _overlap(a, b):
        return 0.0
    return min(_to_edges(a, b), _to_edges(b, a))


def _place_beside(objects: list[dict[str, object]], anchor: int, partner: int,
                  catalogue: Mapping[str, CatalogueEntry], gap_in: float, room: Mapping[str, float],
                  rng: np.random.Generator) -> bool:
    """Move ``partner`` to ``gap_in`` from ``anchor`` at the first of several random
    bearings where it fits; False (nothing moved) when none does."""
    a = objects[anchor]
    a_poly = _polygon(a, catalogue)
    others = [_polygon(o, catalogue) for k, o in enumerate(objects) if k not in (anchor, partner)]
    for _ in range(BEARINGS_TRIED):
        bearing, yaw = float(rng.uniform(0.0, 360.0)), round(float(rng.uniform(0.0, 360.0)), 1)
        u = np.array([math.cos(math.radians(bearing)), math.sin(math.radians(bearing))])
        centre = _at_gap(a_poly, np.array([a["x_in"], a["y_in"]], float), u, objects[partner], yaw, catalogue, gap_in)
        candidate = {**objects[partner], "x_in": round(float(centre[0]), 2), "y_in": round(float(centre[1]), 2),
                     "yaw_deg": yaw}
        poly = _polygon(candidate, catalogue)
        inside = (poly.min(axis=0) >= WALL_CLEARANCE_IN).all() and poly[:, 0].max() <= room["width_in"] - \
            WALL_CLEARANCE_IN and poly[:, 1].max() <= room["depth_in"] - WALL_CLEARANCE_IN
        if inside and all(footprint_gap(poly, o) > gap_in for o in others):
            objects[partner] = candidate
            return True
    return False


def _at_gap(a_poly: np.ndarray, a_centre: np.ndarray, u: np.ndarray, partner: Mapping[str, object], yaw: float,
            catalogue: Mapping[str, CatalogueEntry], gap_in: float) -> np.ndarray:
    """The partner's centre on the ray from the anchor's centre along ``u`` at which the
    two outlines are ``gap_in`` apart (bisection: the gap grows along the ray)."""
    def gap(r: float) -> float:
        c = a_centre + r * u
        return footprint_gap(a_poly, _polygon({**partner, "x_in": c[0], "y_in": c[1], "yaw_deg": yaw}, catalogue))

    lo, hi = 0.0, 1.0
    while gap(hi) < gap_in:
        hi *= 2.0
    for _ in range(40):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if gap(mid) < gap_in else (lo, mid)
    return a_centre + hi * u


def _polygon(placed: Mapping[str, object], catalogue: Mapping[str, CatalogueEntry]) -> np.ndarray:
    entry = catalogue[str(placed["id"])]
    return np.asarray(footprint_polygon(entry.footprint, float(placed["x_in"]), float(placed["y_in"]),  # type: ignore[arg-type]
                                        float(placed.get("yaw_deg", 0.0))), float)  # type: ignore[arg-type]


def _overlap(a: np.ndarray, b: np.ndarray) -> bool:
    """Separating-axis test: convex outlines overlap unless an edge normal parts them."""
    for poly in (a, b):
        for edge in np.roll(poly, -1, axis=0) - poly:
            normal = np.array([-edge[1], edge[0]])
            pa, pb = a @ normal, b @ normal
            if pa.max() < pb.min() or pb.max() < pa.min():
                return False
    return True


def _to_edges(points: np.ndarray, polygon: np.ndarray) -> float:
    """The distance from the nearest of ``points`` to the nearest edge of ``polygon``,
    every point against every edge in one array (placing a pair bisects on it)."""
    start, edge = polygon, np.roll(polygon, -1, axis=0) - polygon
    offset = points[:, None, :] - start[None, :, :]  # point by edge by (x, y)
    t = np.clip((offset * edge).sum(axis=2) / np.maximum((edge ** 2).sum(axis=1), 1e-12), 0.0, 1.0)
    return float(np.min(np.hypot(*(offset - t[..., None] * edge).transpose(2, 0, 1))))


def contaminated(sim: SimWorld, procedure: str, target: int) -> bool:
    """Ground truth for the clutter study: whether ``procedure`` from where the robot
    truly stands now reads, noise off, anything other than what it would read were
    object ``target`` alone on the floor (a neighbour's echo changed it, or the
    neighbour was measured instead). False when the full floor gives no reading."""
    spec, pose = sim.spec, sim.pose
    placed = [Placement(t.entry_id, t.x_in, t.y_in, t.yaw_deg) for t in sim.truth() if not (t.held or t.binned)]
    alone = [Placement(t.entry_id, t.x_in, t.y_in, t.yaw_deg) for t in sim.truth() if t.index == target]

    def reading(objects: list[Placement]) -> tuple[float, dict[str, float | None]] | None:
        world = SimWorld(replace(spec, objects=tuple(objects), events=(), movers=()), 0, profile=sim.profile,
                         noise=NoiseConfig.off())
        world.pose = pose
        try:
            result = world.sense(procedure)
        except DriverError:
            return None
        return round(result.distance_in, 6), dict(result.values)

    full = reading(placed)
    return full is not None and full != reading(alone)
