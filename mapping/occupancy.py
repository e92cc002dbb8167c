"""An occupancy grid built from planar scans at corrected poses.

Each cell holds the log-odds that it is occupied (0: nothing known). A scan adds
:data:`HIT` to the cell each return falls in and :data:`MISS` to every cell a beam
crosses before it (a cell is updated once per scan however many beams cross it, and a
cell a return falls in is not also cleared by that scan). Log-odds are clamped so that a
cell that changes (a door opened, an object picked up) can change back within a few
scans.

A beam that returned nothing (``inf``, or beyond the scan's range) changes nothing: it
is a dropout, glass or a specular miss as often as open space, and clearing up to the
maximum range would clear through the wall behind a missed return and leak free space
outside the home. Open space beyond the range stays unknown until the robot comes closer.

The grid has a fixed extent, given when it is made (the home's outline and a margin):
beams are followed only as far as its edge, and returns outside it are dropped. Cells
are squares of ``inches_per_cell`` on the same frame as the overhead image's pixels
(:class:`camera_model.floor_grid.FloorGrid`: row 0 at the high-y edge), so the planner
reads either alike.
"""

from __future__ import annotations

import math

import numpy as np

from camera_model.floor_grid import FloorGrid
from mapping.scan import PlanarScan
from planner.geometry import Pose

HIT = 0.85  # log-odds of p = 0.7 occupied, for a return in the cell
MISS = -0.4  # log-odds of p = 0.4, for a beam crossing the cell
CLAMP = (-2.0, 3.5)
# A cell is free or occupied once its log-odds are this far from 0; a cell both hit and
# crossed about equally often stays unknown.
DECIDED = 0.2
# Beams are followed in steps of this share of a cell: a beam may miss a cell whose
# corner it clips by less than that.
STEP_CELLS = 0.25

UNKNOWN, FREE, OCCUPIED = -1, 0, 1


class OccupancyGrid:
    """Log-odds occupancy over a fixed extent; cell ``(row, col)`` covers the floor square
    whose top-left corner is ``inches_per_cell`` times ``(col, row)`` right of and below
    ``(x_min_in, y_max_in)``."""

    def __init__(self, x_min_in: float, y_min_in: float, x_max_in: float, y_max_in: float,
                 inches_per_cell: float) -> None:
        if not all(math.isfinite(v) for v in (x_min_in, y_min_in, x_max_in, y_max_in)):
            raise ValueError("occupancy grid extent must be finite")
        if not (math.isfinite(inches_per_cell) and inches_per_cell > 0):
            raise ValueError(f"occupancy grid inches_per_cell must be positive, got {inches_per_cell}")
        if x_max_in <= x_min_in or y_max_in <= y_min_in:
            raise ValueError(f"occupancy grid extent is empty: x {x_min_in}..{x_max_in}, y {y_min_in}..{y_max_in}")
        cols = math.ceil((x_max_in - x_min_in) / inches_per_cell - 1e-9)
        rows = math.ceil((y_max_in - y_min_in) / inches_per_cell - 1e-9)
        self.grid = FloorGrid(inches_per_cell, x_min_in, y_min_in + rows * inches_per_cell)
        self.log_odds = np.zeros((rows, cols), dtype=float)

    @property
    def inches_per_cell(self) -> float:
        return self.grid.inches_per_pixel

    @property
    def shape(self) -> tuple[int, int]:
        rows, cols = self.log_odds.shape
        return rows, cols

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """World extent ``(x_min, x_max, y_min, y_max)`` in inches."""
        return self.grid.extent(*self.shape)

    def cell_of(self, x_in: float, y_in: float) -> tuple[int, int] | None:
        """The (row, col) containing a world point, or None outside the grid."""
        row, col = (math.floor(v) for v in self.grid.to_cell(x_in, y_in))
        rows, cols = self.shape
        return (row, col) if 0 <= row < rows and 0 <= col < cols else None

    def occupied_within(self, x_in: float, y_in: float, reach_in: float) -> bool:
        """Whether any occupied cell's centre lies within ``reach_in`` of a world point."""
        rows, cols = self.shape
        row, col = self.grid.to_cell(x_in, y_in)
        k = reach_in / self.inches_per_cell
        r0, r1 = max(0, math.floor(row - k)), min(rows, math.ceil(row + k) + 1)
        c0, c1 = max(0, math.floor(col - k)), min(cols, math.ceil(col + k) + 1)
        if r0 >= r1 or c0 >= c1:
            return False
        rr, cc = np.mgrid[r0:r1, c0:c1]
        near = np.hypot(rr + 0.5 - row, cc + 0.5 - col) <= k
        return bool(((self.log_odds[r0:r1, c0:c1] > DECIDED) & near).any())

    def states(self) -> np.ndarray:
        """Each cell's :data:`UNKNOWN`, :data:`FREE` or :data:`OCCUPIED` (int8)."""
        states = np.full(self.shape, UNKNOWN, dtype=np.int8)
        states[self.log_odds < -DECIDED] = FREE
        states[self.log_odds > DECIDED] = OCCUPIED
        return states

    @property
    def occupied(self) -> np.ndarray:
        return self.log_odds > DECIDED

    @property
    def free(self) -> np.ndarray:
        """Known to be free (not merely unobserved)."""
        return self.log_odds < -DECIDED

    @property
    def unknown(self) -> np.ndarray:
        return np.abs(self.log_odds) <= DECIDED

    def integrate(self, scan: PlanarScan, pose: Pose | None = None) -> None:
        """Add a scan taken at ``pose`` (the corrected pose; default: the scan's own)."""
        x0, y0, heading_deg = (scan.x_in, scan.y_in, scan.heading_deg) if pose is None else (
            pose.x_in, pose.y_in, pose.heading_deg)
        rows, cols = self.shape
        directions = math.radians(heading_deg) + scan.angles_rad
        returned = scan.returned
        ranges = np.where(returned, scan.ranges_in, 0.0)
        ends_x, ends_y = x0 + ranges * np.cos(directions), y0 + ranges * np.sin(directions)
        hit_rows, hit_cols = (np.floor(v).astype(int) for v in self.grid.to_cell(ends_x[returned], ends_y[returned]))
        inside = (hit_rows >= 0) & (hit_rows < rows) & (hit_cols >= 0) & (hit_cols < cols)
        hits = np.unique(hit_rows[inside] * cols + hit_cols[inside])

        step = STEP_CELLS * self.inches_per_cell
        counts = np.ceil(ranges / step).astype(int)  # samples along each returned beam, its end excluded
        beam = np.repeat(np.arange(len(ranges)), counts)
        along = (np.arange(len(beam)) - np.repeat(np.cumsum(counts) - counts, counts)) * step
        xs, ys = x0 + along * np.cos(directions[beam]), y0 + along * np.sin(directions[beam])
        crossed_rows, crossed_cols = (np.floor(v).astype(int) for v in self.grid.to_cell(xs, ys))
        inside = (crossed_rows >= 0) & (crossed_rows < rows) & (crossed_cols >= 0) & (crossed_cols < cols)
        crossed = np.setdiff1d(np.unique(crossed_rows[inside] * cols + crossed_cols[inside]), hits)

        flat = self.log_odds.reshape(-1)
        flat[crossed] += MISS
        flat[hits] += HIT
        np.clip(self.log_odds, *CLAMP, out=self.log_odds)
