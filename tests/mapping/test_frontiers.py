"""Frontiers of a half-explored room, worked out by hand."""

from __future__ import annotations

import numpy as np

from mapping import OccupancyGrid, frontiers
from mapping.frontiers import open_unknown
from mapping.occupancy import HIT, MISS


def half_explored(blocked_rows: range = range(0)) -> OccupancyGrid:
    """The 100 in room of 10 in cells centred on (10 col, 100 - 10 row): walls (rows 0
    and 10, columns 0 and 10) occupied, columns 1-4 free, columns 5-9 unknown; in column
    5 the ``blocked_rows`` are occupied too (furniture at the edge of what was seen)."""
    grid = OccupancyGrid(-5.0, -5.0, 105.0, 105.0, 10.0)
    grid.log_odds[[0, 10], :] = HIT
    grid.log_odds[:, [0, 10]] = HIT
    grid.log_odds[1:10, 1:5] = MISS
    grid.log_odds[list(blocked_rows), 5] = HIT
    return grid


def test_the_edge_of_the_explored_half_is_one_frontier() -> None:
    """Column 4, rows 1-9: nine cells centred on x = 40, y = 100 - 10 x 5 = 50."""
    found = frontiers(half_explored())
    assert len(found) == 1
    assert found[0].cells == tuple((row, 4) for row in range(1, 10))
    assert (found[0].centroid_x_in, found[0].centroid_y_in) == (40.0, 50.0)


def test_an_obstacle_on_the_edge_splits_it_in_two() -> None:
    """Rows 4-6 of column 5 occupied: frontiers rows 1-3 (y = 80) and 7-9 (y = 20),
    three cells each, the top one first (equal sizes: by first cell)."""
    found = frontiers(half_explored(range(4, 7)))
    assert [(f.size, f.centroid_x_in, f.centroid_y_in) for f in found] == [(3, 40.0, 80.0), (3, 40.0, 20.0)]


def test_small_frontiers_are_left_out() -> None:
    assert frontiers(half_explored(range(4, 7)), min_cells=4) == []


def test_a_fully_explored_room_has_none() -> None:
    grid = half_explored()
    grid.log_odds[1:10, 5:10] = MISS
    assert frontiers(grid) == []


def wall_with_an_opening() -> OccupancyGrid:
    """30 x 12 in of 1 in cells (cell (row, col) centred on x = col + 0.5, y = 11.5 - row):
    rows 4-11 free; row 3 a wall's face, occupied in columns 0-14 but for column 5 (a
    return measured long cleared it), unknown in columns 15-29 (an opening); rows 0-2
    unknown (the wall's inside, and what lies beyond the opening)."""
    grid = OccupancyGrid(0.0, 0.0, 30.0, 12.0, 1.0)
    grid.log_odds[4:, :] = MISS
    grid.log_odds[3, :15] = HIT
    grid.log_odds[3, 5] = MISS
    return grid


def test_unknown_hugging_a_surface_opens_nothing() -> None:
    """Every unknown cell counted: the opening's edge (row 4, columns 15-29: 15 cells,
    centroid x = 22.5, y = 7.5) and the cleared face cell (3, 5) at (5.5, 8.5), beside
    the wall's inside. Only unknown cells more than 3 in from every occupied cell: the
    cell above the face's gap is 1.4 in from the face cells beside it, and the opening's
    cells in columns 15-17 lie 1-3 in from the face's end (3, 14): the opening's edge from
    column 18 on, 12 cells centred on x = 24.0."""
    grid = wall_with_an_opening()
    assert [(f.size, f.centroid_x_in, f.centroid_y_in) for f in frontiers(grid)] == [(15, 22.5, 7.5), (1, 5.5, 8.5)]
    found = frontiers(grid, surface_in=3.0)
    assert [(f.size, f.centroid_x_in, f.centroid_y_in) for f in found] == [(12, 24.0, 7.5)]
    assert found[0].cells == tuple((4, col) for col in range(18, 30))


def test_with_no_occupied_cell_all_unknown_is_open() -> None:
    grid = OccupancyGrid(0.0, 0.0, 10.0, 10.0, 1.0)
    grid.log_odds[5:, :] = MISS
    assert np.array_equal(open_unknown(grid, 6.0), grid.unknown)
