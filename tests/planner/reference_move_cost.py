"""The estimate mode and its grid search as they were before the distance fields were
kept per coarse block, without their copies on the map's grid, searched on a graph
made symmetric once and at first only as far as the learner's moves reach, and before
the descent read its cells as Python floats (issue 32): kept, unchanged but for this
note and their names, as the reference that
tests/planner/test_move_cost_fast.py compares the cheaper estimator with (the same
price, length, turning and reason for every move). Not used by the product.
"""

from __future__ import annotations

import math

import cv2
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from planner.cache import LruCache
from planner.geometry import Pose
from planner.grid_search import _STEPS, GRID_TO_EUCLIDEAN
from planner.move_cost import DETOUR_RATIO, DETOUR_SIMPLIFY_CELLS, FIELD_COARSENING, MoveCost, _turning, arrived, \
    move_seconds
from planner.paths import ESCAPE_LIMIT_IN, GOAL_BLOCKED, GOAL_OUTSIDE, OK, START_BLOCKED, START_OUTSIDE, UNREACHABLE
from planner.vision_map import VisionMap
from robot_profile import RobotMotion


class ReferenceGridGraph:
    """The free cells of a grid as an undirected graph of 8-connected moves."""

    def __init__(self, free: np.ndarray) -> None:
        self.free = np.asarray(free, dtype=bool)
        rows, cols = self.free.shape
        index = np.arange(rows * cols).reshape(rows, cols)
        sources, targets, weights = [], [], []
        for dr, dc, cost in _STEPS:
            r0, r1 = 0, rows - dr
            c0, c1 = max(0, -dc), cols - max(0, dc)
            here = (slice(r0, r1), slice(c0, c1))
            there = (slice(r0 + dr, r1 + dr), slice(c0 + dc, c1 + dc))
            both = self.free[here] & self.free[there]
            sources.append(index[here][both])
            targets.append(index[there][both])
            weights.append(np.full(int(both.sum()), cost))
        n = rows * cols
        self._graph = csr_matrix((np.concatenate(weights), (np.concatenate(sources), np.concatenate(targets))),
                                 shape=(n, n))

    def distances_from(self, start: tuple[int, int]) -> np.ndarray:
        """Grid distance (in cells) from ``start`` to every cell; ``inf`` where unreachable."""
        rows, cols = self.free.shape
        r0, c0 = start
        if not (0 <= r0 < rows and 0 <= c0 < cols) or not self.free[r0, c0]:
            return np.full(self.free.shape, np.inf)
        field = dijkstra(self._graph, directed=False, indices=r0 * cols + c0).reshape(rows, cols)
        field[~self.free] = np.inf
        return field


def reference_descend(field: np.ndarray, goal: tuple[int, int]) -> list[tuple[int, int]]:
    """The grid's shortest path from the field's source to ``goal`` (cells, source first).

    Follows the steepest descent of a :func:`distance_field` back from the goal; empty
    when the goal is unreachable.
    """
    rows, cols = field.shape
    if not np.isfinite(field[goal]):
        return []
    path = [goal]
    row, col = goal
    while field[row, col] > 0:
        best = (field[row, col], row, col)
        for dr in (-1, 0, 1):
            for dc in (-1, 0, 1):
                r, c = row + dr, col + dc
                if (dr or dc) and 0 <= r < rows and 0 <= c < cols and field[r, c] < best[0]:
                    best = (field[r, c], r, c)
        if (best[1], best[2]) == (row, col):
            break
        row, col = best[1], best[2]
        path.append((row, col))
    path.reverse()
    return path


class ReferenceCostEstimator:
    """Estimate mode on one vision map: distance fields cached per start cell."""

    def __init__(self, vision_map: VisionMap, model: RobotMotion, cache_size: int = 8) -> None:
        self.map = vision_map
        self.model = model
        self._fields: LruCache[tuple[np.ndarray, np.ndarray]] = LruCache(cache_size)
        self._graph: ReferenceGridGraph | None = None  # built on the first field: a map may never be priced

    def _field(self, cell: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
        """The field on the map's grid (inches) and on the coarse grid it was searched on."""
        k = FIELD_COARSENING
        rows, cols = self.map.free.shape
        if self._graph is None:
            padded = np.zeros((-(-rows // k) * k, -(-cols // k) * k), dtype=bool)
            padded[:rows, :cols] = self.map.free
            self._graph = ReferenceGridGraph(padded.reshape(padded.shape[0] // k, k, padded.shape[1] // k, k).any(axis=(1, 3)))
        graph = self._graph

        def make() -> tuple[np.ndarray, np.ndarray]:
            coarse = graph.distances_from((cell[0] // k, cell[1] // k)) * (k * self.map.image.inches_per_pixel
                                                                           * GRID_TO_EUCLIDEAN)
            fine = np.repeat(np.repeat(coarse, k, axis=0), k, axis=1)[:rows, :cols]
            fine[~self.map.free] = np.inf
            return fine, coarse

        return self._fields.get_or_make(cell, make)

    def estimate(self, start: Pose, goal: Pose) -> MoveCost:
        """The estimated cost of moving from ``start`` to ``goal``."""
        start.require_finite("start")
        goal.require_finite("goal")
        if arrived(start, goal):
            return MoveCost(0.0, 0.0, 0.0, False, OK)
        goal_cell = self.map.cell_of(goal.x_in, goal.y_in)
        exit_point = self.map.nearest_free(start.x_in, start.y_in, ESCAPE_LIMIT_IN)
        reason = (START_OUTSIDE if not self.map.contains(start.x_in, start.y_in)
                  else GOAL_OUTSIDE if goal_cell is None
                  else GOAL_BLOCKED if not self.map.free[goal_cell]
                  else START_BLOCKED if exit_point is None else None)
        if reason is not None:
            return MoveCost(math.inf, math.inf, math.inf, False, reason)
        escape = math.hypot(exit_point[0] - start.x_in, exit_point[1] - start.y_in)
        field, coarse = self._field(self.map.cell_of(*exit_point))
        length = float(field[goal_cell]) + escape
        if not math.isfinite(length):
            return MoveCost(math.inf, math.inf, math.inf, False, UNREACHABLE)
        # The field measures cell to cell; the straight line is a floor on the length.
        straight = math.hypot(goal.x_in - start.x_in, goal.y_in - start.y_in)
        if length <= straight * DETOUR_RATIO + self.map.image.inches_per_pixel:
            length = max(length, straight)
            turning = _turning(start, goal, [(start.x_in, start.y_in), (goal.x_in, goal.y_in)])
        else:
            turning = _turning(start, goal, self._detour(coarse, start, goal, goal_cell))
        return MoveCost(move_seconds(self.model, length, turning), length, turning, False, OK)

    def _detour(self, coarse: np.ndarray, start: Pose, goal: Pose, goal_cell: tuple[int, int]
                ) -> list[tuple[float, float]]:
        """The grid's shortest path as a few straight legs (for its turns), descended on
        the coarse field it was searched on."""
        k = FIELD_COARSENING
        cells = np.array([(col, row) for row, col in reference_descend(coarse, (goal_cell[0] // k, goal_cell[1] // k))],
                         np.float32)
        corners = cv2.approxPolyDP(cells.reshape(-1, 1, 2), DETOUR_SIMPLIFY_CELLS / k, False).reshape(-1, 2)
        centres = corners * k + (k - 1) / 2.0
        points = [tuple(p) for p in self.map.image.to_world(centres[:, 1], centres[:, 0])]
        return [(start.x_in, start.y_in)] + points[1:-1] + [(goal.x_in, goal.y_in)]
