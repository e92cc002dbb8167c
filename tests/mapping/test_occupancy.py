"""The occupancy grid from scans, cell by cell, worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mapping import FREE, OCCUPIED, UNKNOWN, OccupancyGrid, PlanarScan
from mapping.occupancy import HIT, MISS
from planner.geometry import Pose

FOUR_BEAMS = np.array([0.0, math.pi / 2, math.pi, 3 * math.pi / 2])


def centred_grid() -> OccupancyGrid:
    """11 x 11 cells of 10 in centred on x, y = 0, 10, ..., 100: cell (row, col) is
    centred on (10 col, 100 - 10 row), so a 100 in square room's walls run along the
    middles of rows 0 and 10 and columns 0 and 10."""
    return OccupancyGrid(-5.0, -5.0, 105.0, 105.0, 10.0)


def scan(ranges: list[float], x: float = 50.0, y: float = 50.0, heading: float = 0.0) -> PlanarScan:
    return PlanarScan(FOUR_BEAMS, np.array(ranges), x, y, heading, 0.0, 300.0)


def test_four_beams_to_the_walls_of_a_square_room() -> None:
    """From the room's centre (cell 5, 5) each beam crosses its own cell and four more
    before the wall cell it ends in: 1 + 4 x 4 = 17 free cells, 4 occupied, the rest unknown."""
    grid = centred_grid()
    grid.integrate(scan([50.0, 50.0, 50.0, 50.0]))
    expected = np.full((11, 11), UNKNOWN)
    expected[5, 1:10] = FREE
    expected[1:10, 5] = FREE
    expected[5, 10] = expected[5, 0] = expected[0, 5] = expected[10, 5] = OCCUPIED
    assert grid.states().tolist() == expected.tolist()
    assert grid.log_odds[5, 10] == pytest.approx(HIT)
    assert grid.log_odds[5, 5] == pytest.approx(MISS)  # crossed by four beams, cleared once


def test_the_corrected_pose_places_the_scan_not_the_reported_one() -> None:
    """The scan says (50, 50) heading 0; the corrected pose is (50, 50) heading 90: the
    beam at angle 0 now points up (+y) and ends in the top wall's cell (0, 5)."""
    grid = centred_grid()
    grid.integrate(scan([50.0, math.inf, math.inf, math.inf]), Pose(50.0, 50.0, 90.0))
    assert grid.states()[0, 5] == OCCUPIED
    assert grid.states()[5, 10] == UNKNOWN
    assert grid.states()[1:6, 5].tolist() == [FREE] * 5


def test_a_beam_without_return_clears_nothing() -> None:
    grid = centred_grid()
    grid.integrate(scan([math.inf] * 4))
    assert (grid.states() == UNKNOWN).all()


def test_hits_and_misses_add_up_in_log_odds() -> None:
    """A cell hit once and crossed twice: 0.85 - 2 x 0.4 = 0.05, too close to 0 to decide."""
    grid = centred_grid()
    grid.integrate(scan([30.0, math.inf, math.inf, math.inf]))  # hit in cell (5, 8)
    grid.integrate(scan([50.0, math.inf, math.inf, math.inf]))
    grid.integrate(scan([50.0, math.inf, math.inf, math.inf]))
    assert grid.log_odds[5, 8] == pytest.approx(HIT + 2 * MISS)
    assert grid.states()[5, 8] == UNKNOWN
    assert grid.states()[5, 10] == OCCUPIED


def test_returns_outside_the_grid_are_dropped_and_beams_stop_at_its_edge() -> None:
    grid = centred_grid()
    grid.integrate(scan([200.0, math.inf, math.inf, math.inf]))
    assert grid.states()[5, 5:].tolist() == [FREE] * 6
    assert not grid.occupied.any()


@pytest.mark.parametrize("field, kwargs, message", [
    ("ranges", {"ranges_in": np.array([1.0, -1.0])}, "ranges_in must be positive"),
    ("shape", {"ranges_in": np.array([1.0])}, "one length"),
    ("pose", {"x_in": math.nan}, "x_in must be finite"),
    ("range", {"max_range_in": math.inf}, "max_range_in"),
])
def test_a_bad_scan_is_refused_naming_its_field(field: str, kwargs: dict, message: str) -> None:
    values = {"angles_rad": np.array([0.0, 1.0]), "ranges_in": np.array([1.0, 2.0]), "x_in": 0.0, "y_in": 0.0,
              "heading_deg": 0.0, "stamp_s": 0.0, "max_range_in": 100.0} | kwargs
    with pytest.raises(ValueError, match=message):
        PlanarScan(**values)


def test_an_empty_extent_is_refused() -> None:
    with pytest.raises(ValueError, match="extent is empty"):
        OccupancyGrid(0.0, 0.0, 0.0, 10.0, 1.0)
