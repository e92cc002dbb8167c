"""The validity checker OMPL calls for every state: the map's cell, read from bytes."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from ompl import base as ob

from planner import build_vision_map, look
from planner.paths import _cells, _validity_checker
from tests.planner.drawing import WALL, Canvas
from tests.planner.test_planner_move_cost import HERO

VISION_MAP = build_vision_map(look(Canvas(60.0, 40.0).rect(30.0, 20.0, 4.0, 30.0, 0.0, WALL).robot(10.0, 10.0, 0.0)
                                   .image()), HERO)
SPACE = ob.RealVectorStateSpace(2)


@settings(max_examples=200, deadline=None)
@given(fx=st.floats(0.0, 1.0), fy=st.floats(0.0, 1.0), seed=st.integers(0, 3))
def test_a_state_is_valid_exactly_when_its_cell_is_set(fx: float, fy: float, seed: int) -> None:
    """Any point of the map, its far edges included (the cell index clamps there): the
    checker answers what the grid holds at the point's cell."""
    grid = VISION_MAP.free_strict if seed == 0 else np.random.default_rng(seed).random(VISION_MAP.free.shape) < 0.5
    x_min, x_max, y_min, y_max = VISION_MAP.bounds
    x, y = x_min + fx * (x_max - x_min), y_min + fy * (y_max - y_min)
    state = SPACE.allocState()
    state[0], state[1] = x, y
    rows, cols = grid.shape
    inv = 1.0 / VISION_MAP.image.inches_per_pixel  # the grid's cell size, as OMPL's states are binned
    row = min(int((VISION_MAP.image.origin_y_in - y) * inv), rows - 1)
    col = min(int((x - VISION_MAP.image.origin_x_in) * inv), cols - 1)
    assert _validity_checker(VISION_MAP, [_cells(grid)])(state) == bool(grid[row, col])
