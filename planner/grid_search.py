"""Shortest paths on the inflated occupancy grid: a reference and a cheap distance field.

Dijkstra over 8-connected cells, diagonal steps costing √2. It serves twice: as the
benchmark's reference for OMPL path lengths, and as a distance field from the robot's
cell so that pricing dozens of candidate positions costs one lookup each. An
8-connected grid path overestimates the any-angle shortest path by at most ~8 % (for
headings halfway between two of its eight directions); callers that want the latter
may scale by :data:`GRID_TO_EUCLIDEAN`.

The search itself is SciPy's compiled Dijkstra on the grid as a sparse graph, built
once per map (:class:`GridGraph`): a field over the lab's 67,000 cells takes about
10 ms instead of the ~90 ms of a Python priority queue.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

SQRT2 = math.sqrt(2.0)
# Mean ratio of the any-angle length to the 8-connected length over uniformly random
# headings: (4/π)·∫₀^{π/4} cosθ / (cosθ + (√2-1) sinθ) dθ ≈ 0.948.
GRID_TO_EUCLIDEAN = 0.948

# The four "forward" neighbour offsets; with an undirected graph they give all eight.
_STEPS = ((0, 1, 1.0), (1, 0, 1.0), (1, 1, SQRT2), (1, -1, SQRT2))


class GridGraph:
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
        forward = csr_matrix((np.concatenate(weights), (np.concatenate(sources), np.concatenate(targets))),
                             shape=(n, n))
        # every step both ways, once: an undirected search would transpose the graph at
        # every call (each step is stored once, from the lower index, so none is doubled)
        self._graph = (forward + forward.T).tocsr()

    def distances_from(self, start: tuple[int, int], limit: float = math.inf) -> np.ndarray:
        """Grid distance (in cells) from ``start`` to every cell; ``inf`` where unreachable
        or, with a finite ``limit``, farther than it.

        Within the limit the distances are those of the whole search to the last bit: a
        cell's distance is the least over its neighbours of theirs plus the step, and
        every neighbour nearer than the cell is within the limit too. The search stops
        there, so a field of a few yards of a large floor costs a fraction of the whole.
        A blocked or outside start gives an all-``inf`` field: nothing is reachable from
        inside an obstacle.
        """
        rows, cols = self.free.shape
        r0, c0 = start
        if not (0 <= r0 < rows and 0 <= c0 < cols) or not self.free[r0, c0]:
            return np.full(self.free.shape, np.inf)
        field = dijkstra(self._graph, directed=True, indices=r0 * cols + c0, limit=limit).reshape(rows, cols)
        field[~self.free] = np.inf
        return field


def distance_field(free: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """One field on a grid not seen before (builds its graph; see :class:`GridGraph`)."""
    return GridGraph(free).distances_from(start)


def descend(field: np.ndarray, goal: tuple[int, int]) -> list[tuple[int, int]]:
    """The grid's shortest path from the field's source to ``goal`` (cells, source first).

    Follows the steepest descent of a :func:`distance_field` back from the goal (the
    first of the lowest neighbours, row by row, while it is lower); empty when the goal
    is unreachable. Cells are read as Python floats (``item``): a detour's turns are
    priced by a descent, and numpy's scalar indexing would be most of its time.
    """
    rows, cols = field.shape
    if not np.isfinite(field[goal]):
        return []
    value = field.item
    path = [goal]
    row, col = goal
    here = value(row, col)
    while here > 0:
        best, best_row, best_col = here, row, col
        for r in (row - 1, row, row + 1):
            if not 0 <= r < rows:
                continue
            for c in (col - 1, col, col + 1):
                if (r != row or c != col) and 0 <= c < cols and value(r, c) < best:
                    best, best_row, best_col = value(r, c), r, c
        if (best_row, best_col) == (row, col):
            break
        row, col, here = best_row, best_col, best
        path.append((row, col))
    path.reverse()
    return path
