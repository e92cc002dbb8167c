"""Frontiers: where the known free space meets the unknown, the places to explore next.

A frontier cell is a free cell with an unknown cell among its four neighbours (sharing a
side: a free cell that only touches unknown space at a corner shows no opening to drive
through). Frontier cells that touch, sides or corners, form one frontier region; a
region's centroid is where exploration may aim, its size how much it may reveal.
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


def frontiers(grid: OccupancyGrid, min_cells: int = 1) -> list[Frontier]:
    """The grid's frontier regions of at least ``min_cells`` cells, largest first (ties:
    by the top-left cell, so the order is the same run to run)."""
    cells = frontier_cells(grid.free, grid.unknown)
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
