"""Shortest paths on the inflated occupancy grid: a reference and a cheap distance field.

Dijkstra over 8-connected cells, diagonal steps costing √2. It serves twice: as the
benchmark's reference for OMPL path lengths, and as a distance field from the robot's
cell so that pricing dozens of candidate positions costs one lookup each. An
8-connected grid path overestimates the any-angle shortest path by at most ~8 % (for
headings halfway between two of its eight directions); callers that want the latter
may scale by :data:`GRID_TO_EUCLIDEAN`.
"""

from __future__ import annotations

import heapq
import math

import numpy as np

SQRT2 = math.sqrt(2.0)
# Mean ratio of the any-angle length to the 8-connected length over uniformly random
# headings: (4/π)·∫₀^{π/4} cosθ / (cosθ + (√2-1) sinθ) dθ ≈ 0.948.
GRID_TO_EUCLIDEAN = 0.948


def distance_field(free: np.ndarray, start: tuple[int, int]) -> np.ndarray:
    """Grid distance (in cells) from ``start`` to every cell; ``inf`` where unreachable.

    A blocked start gives an all-``inf`` field: nothing is reachable from inside an
    obstacle.
    """
    rows, cols = free.shape
    distances = np.full(free.shape, np.inf)
    r0, c0 = start
    if not (0 <= r0 < rows and 0 <= c0 < cols) or not free[r0, c0]:
        return distances
    # Pad with a blocked border so that neighbours never need a bounds check.
    width = cols + 2
    open_cells = np.zeros((rows + 2, width), dtype=bool)
    open_cells[1:-1, 1:-1] = free
    passable = open_cells.ravel().tolist()
    best = [math.inf] * ((rows + 2) * width)
    steps = [(1, 1.0), (-1, 1.0), (width, 1.0), (-width, 1.0),
             (width + 1, SQRT2), (width - 1, SQRT2), (-width + 1, SQRT2), (-width - 1, SQRT2)]
    source = (r0 + 1) * width + c0 + 1
    best[source] = 0.0
    queue = [(0.0, source)]
    pop, push = heapq.heappop, heapq.heappush
    while queue:
        dist, cell = pop(queue)
        if dist > best[cell]:
            continue
        for offset, cost in steps:
            nxt = cell + offset
            if passable[nxt]:
                candidate = dist + cost
                if candidate < best[nxt]:
                    best[nxt] = candidate
                    push(queue, (candidate, nxt))
    distances[:] = np.asarray(best).reshape(rows + 2, width)[1:-1, 1:-1]
    return distances


def descend(field: np.ndarray, goal: tuple[int, int]) -> list[tuple[int, int]]:
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
