"""Whether a straight piece of outline is a face of the home's structure: it lies on a
straight run of occupied cells of the map longer than any object's face.

One scan often sees only part of a wall or of a piece of furniture: the back of a nook
between a wall and a wardrobe, the end face of a counter seen past its corner, the side
of a bed at a grazing angle. Each such piece is object-sized, and the scan alone cannot
tell it from a box's face. The map can: it holds every scan's returns, and a piece of
wall continues, in a straight line, into the occupied cells of the rest of the wall
(across a dropout or the end of a wall joining it); an object's face ends where the
object ends. So a straight outline is followed in the grid beyond its ends, and the run
of occupied cells it lies on is measured.

A wall that *crosses* the outline's line (a box standing square against a wall) is not
a continuation: there the occupied cells run on across both sides of the line, where a
continuing face is thin. Pure numpy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from mapping.occupancy import OccupancyGrid


@dataclass(frozen=True)
class Face:
    """A straight stretch of outline from ``a`` to ``b`` (world inches)."""

    a: tuple[float, float]
    b: tuple[float, float]

    @property
    def length_in(self) -> float:
        return math.dist(self.a, self.b)


def straight_face(points: np.ndarray, min_length_in: float, straight_in: float) -> Face | None:
    """The face ``points`` lie along: their principal axis between their extreme
    projections on it, when they are at least ``min_length_in`` long along it and nine in
    ten lie within ``straight_in`` of it; None otherwise (too short to have a direction a
    round object's arc could not have, or not straight: two faces of a box, a can)."""
    points = np.asarray(points, dtype=float).reshape(-1, 2)
    if len(points) < 2:
        return None
    centre = points.mean(axis=0)
    _, _, vt = np.linalg.svd(points - centre, full_matrices=False)
    along, across = (points - centre) @ vt[0], (points - centre) @ vt[1]
    if along.max() - along.min() < min_length_in or float(np.quantile(np.abs(across), 0.9)) > straight_in:
        return None
    a, b = centre + along.min() * vt[0], centre + along.max() * vt[0]
    return Face((float(a[0]), float(a[1])), (float(b[0]), float(b[1])))


def run_along(grid: OccupancyGrid, face: Face, band_in: float, gap_in: float, reach_in: float,
              side_in: float, max_turn_deg: float = 10.0) -> float:
    """The length (inches) of the straight run of occupied cells ``face`` lies on: the
    face itself and, beyond each end up to ``reach_in``, as far as the line meets
    occupied cells within ``band_in`` of it with no stretch longer than ``gap_in``
    without (a dropout, a place no beam reached, the end of a wall joining this one).
    A place where occupied cells fill at least half of the ``side_in`` beyond the band
    on *both* sides of the line is a wall crossing it, not the face going on (the
    returns a wall's range noise puts behind it, never crossed by a beam, are a cell
    or two, not a wall). Nor does a wall met at a shallow angle (the occupied cells
    beyond an end lie along a line more than ``max_turn_deg`` off the face's): the arc
    of a can against a wall, seen as a short straight outline at 20° to the wall, meets
    the wall within the band for inches on end."""
    a, b = np.array(face.a), np.array(face.b)
    length = float(np.hypot(*(b - a)))
    if length <= 0.0:
        return 0.0
    u = (b - a) / length
    n = np.array([-u[1], u[0]])
    step = grid.inches_per_cell / 2.0  # half a cell: no cell along the line is stepped over
    across = np.arange(-(band_in + side_in), band_in + side_in + step / 2, step)
    in_band = np.abs(across) <= band_in
    total = length
    for start, direction in ((b, u), (a, -u)):
        steps = np.arange(step, reach_in + step / 2, step)
        centres = start[None, :] + steps[:, None] * direction[None, :]
        samples = centres[:, None, :] + across[None, :, None] * n[None, None, :]
        occupied = _occupied_at(grid, samples.reshape(-1, 2)).reshape(len(steps), len(across))
        crossing = ((occupied[:, across < -band_in].mean(axis=1) >= 0.5)
                    & (occupied[:, across > band_in].mean(axis=1) >= 0.5))
        hit = occupied[:, in_band].any(axis=1) & ~crossing
        last = 0.0
        for distance, seen in zip(steps, hit):
            if distance - last > gap_in:
                break
            if seen:
                last = float(distance)
        if last > 0.0 and _turns_away(occupied[:, in_band] & hit[:, None] & (steps <= last)[:, None],
                                      steps, across[in_band], max_turn_deg):
            last = 0.0
        total += last
    return total


def _turns_away(cells: np.ndarray, steps: np.ndarray, across: np.ndarray, max_turn_deg: float) -> bool:
    """Whether the occupied samples ``cells[step, offset]`` found beyond an end lie along
    a line more than ``max_turn_deg`` off the face's (fitted by least squares, offset on
    distance, when they span 3 in or more along it): a wall met at a shallow angle runs
    across the band, where the face going on stays in it at one offset."""
    rows, cols = np.nonzero(cells)
    if len(rows) < 3:
        return False
    along, off = steps[rows], across[cols]
    if along.max() - along.min() < 3.0:
        return False
    slope = np.polyfit(along, off, 1)[0]
    return bool(math.degrees(math.atan(abs(slope))) > max_turn_deg)


def _occupied_at(grid: OccupancyGrid, points: np.ndarray) -> np.ndarray:
    """Whether each world point lies in an occupied cell (outside the grid: no)."""
    rows, cols = (np.floor(v).astype(int) for v in grid.grid.to_cell(points[:, 0], points[:, 1]))
    height, width = grid.shape
    inside = (rows >= 0) & (rows < height) & (cols >= 0) & (cols < width)
    out = np.zeros(len(points), dtype=bool)
    out[inside] = grid.occupied[rows[inside], cols[inside]]
    return out
