"""Frontiers: where the known free space meets the unknown, the places to explore next.

A frontier cell is a free cell with an unknown cell among its four neighbours (sharing a
side: a free cell that only touches unknown space at a corner shows no opening to drive
through). Frontier cells that touch, sides or corners, form one frontier region; a
region's centroid is where exploration may aim, its size how much it may reveal.

Unknown space hugging a surface opens nothing: the inside of a wall or a cabinet, the
inside of a box, and the speckle a noisy range finder leaves round every surface (a
return measured long clears a cell or two behind the face, one measured short marks
one in front of it, and a cell hit and crossed about equally often stays unknown). Its
free cells are frontier cells all the same, chained along the surface into regions, and
no viewing pose can ever see into them: a robot sent to look at them comes back to them
again and again (docs/mapping.md, "Exploration time"). So an unknown neighbour may be
asked to lie more than ``surface_in`` from every occupied cell (``surface_in`` of
:func:`frontiers`; 0, the default, asks nothing): what is beyond a frontier is then
space, not the surface's own thickness.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from mapping.occupancy import OccupancyGrid


@dataclass(frozen=True)
class Frontier:
    """One frontier region: its cells (row, col), their count and centroid (world inches)."""

    cells: tuple[tuple[int, int], ...]
    centroid_x_in: float
    centroid_y_in: float

    @property
    def size(self) -> int:
        return len(self.cells)


def frontier_cells(free: np.ndarray, unknown: np.ndarray) -> np.ndarray:
    """Free cells with an unknown 4-neighbour (cells outside the grid count as not unknown)."""
    padded = np.pad(unknown, 1, constant_values=False)
    beside = padded[:-2, 1:-1] | padded[2:, 1:-1] | padded[1:-1, :-2] | padded[1:-1, 2:]
    return free & beside


def open_unknown(grid: OccupancyGrid, surface_in: float) -> np.ndarray:
    """The unknown cells whose centres lie more than ``surface_in`` from the centre of
    every occupied cell: unknown space, not a surface's inside or its noise (the module
    docstring). Every unknown cell when the grid has no occupied cell."""
    unknown = grid.unknown
    occupied = grid.occupied
    if surface_in <= 0 or not occupied.any():
        return unknown
    # distance of each cell's centre to the nearest occupied cell's centre, in cells
    cells = cv2.distanceTransform((~occupied).astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    return unknown & (cells * grid.inches_per_cell > surface_in)


def frontiers(grid: OccupancyGrid, min_cells: int = 1, surface_in: float = 0.0) -> list[Frontier]:
    """The grid's frontier regions of at least ``min_cells`` cells, largest first (ties:
    by the top-left cell, so the order is the same run to run); with ``surface_in``, only
    free cells beside unknown cells farther than that from every occupied one
    (:func:`open_unknown`)."""
    cells = frontier_cells(grid.free, open_unknown(grid, surface_in))
    count, labels = cv2.connectedComponents(cells.astype(np.uint8), connectivity=8)
    all_rows, all_cols = np.nonzero(labels)  # row-major: each region's cells come in row order
    label_of = labels[all_rows, all_cols]
    order = np.argsort(label_of, kind="stable")
    bounds = np.searchsorted(label_of[order], np.arange(1, count + 1))
    found = []
    for label in range(1, count):
        members = order[bounds[label - 1]:bounds[label]]
        rows, cols = all_rows[members], all_cols[members]
        if len(rows) < min_cells:
            continue
        centre = grid.grid.to_world(rows, cols).mean(axis=0)
        found.append(Frontier(tuple(zip(rows.tolist(), cols.tolist())), float(centre[0]), float(centre[1])))
    return sorted(found, key=lambda f: (-f.size, f.cells[0]))
