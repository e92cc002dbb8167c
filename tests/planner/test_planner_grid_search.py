"""The reference grid search: 8-connected Dijkstra with √2 diagonals."""

from __future__ import annotations

import math

import numpy as np
import pytest

from planner.grid_search import descend, distance_field


def test_open_grid_distances_are_octile():
    field = distance_field(np.ones((20, 30), bool), (2, 3))
    assert field[2, 3] == 0.0
    assert field[2, 13] == pytest.approx(10.0)
    assert field[12, 13] == pytest.approx(10 * math.sqrt(2))
    assert field[7, 23] == pytest.approx(5 * math.sqrt(2) + 15)


def test_wall_forces_a_detour_and_enclosures_are_unreachable():
    free = np.ones((11, 11), bool)
    free[0:9, 5] = False  # a wall with a gap at rows 9-10
    field = distance_field(free, (0, 0))
    # Diagonally down to the gap at (9, 5), then diagonally back up: 5 diagonal and
    # 4 straight steps each way.
    assert field[0, 10] == pytest.approx(2 * (5 * math.sqrt(2) + 4))
    free[:, 5] = False
    assert np.isinf(distance_field(free, (0, 0))[0, 10])


def test_blocked_or_outside_start_reaches_nothing():
    free = np.ones((5, 5), bool)
    free[2, 2] = False
    assert np.isinf(distance_field(free, (2, 2))).all()
    assert np.isinf(distance_field(free, (9, 9))).all()


def test_descent_traces_a_shortest_path_back_to_the_source():
    free = np.ones((11, 11), bool)
    free[0:9, 5] = False
    field = distance_field(free, (0, 0))
    path = descend(field, (0, 10))
    assert path[0] == (0, 0) and path[-1] == (0, 10)
    assert all(free[cell] for cell in path)
    steps = sum(math.dist(a, b) for a, b in zip(path, path[1:]))
    assert steps == pytest.approx(field[0, 10])
    assert max(row for row, _ in path) >= 9  # through the gap
    free[:, 5] = False
    assert descend(distance_field(free, (0, 0)), (0, 10)) == []
