"""The onboard episode's measures against the truth (experiments.onboard_truth), each
on inputs made by hand with the values worked out here: the records found on a floor
of three objects, a 4 x 4 cell map against a wall, and the errors of three scans."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from experiments.onboard_truth import (Found, TruthAtScans, found_and_right, localisation,
                                       map_accuracy, on_truth_cells)
from hero_driver.interface import Pose as DriverPose
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.truth_map import TruthMap
from mapping import OccupancyGrid
from planner.geometry import Pose
from reporting.report import FOUND_WITHIN_IN, Truth

TRUTHS = [Truth("box", ("Grab",), 0.0, 0.0), Truth("cup", ("Grab",), 100.0, 0.0), Truth("can", ("Grab",), 0.0, 100.0)]


def judged(x: float, y: float, correct: bool | None) -> tuple[SimpleNamespace, SimpleNamespace]:
    """A record first seen at (x, y) and its report row (only what the count reads)."""
    return SimpleNamespace(first_region=SimpleNamespace(centroid=(x, y)), region=None), SimpleNamespace(correct=correct)


def test_a_record_finds_the_nearest_object_within_the_tolerance_once() -> None:
    records = [judged(3.0, 4.0, True),  # the box, 5 in off: found, right
               judged(100.0, FOUND_WITHIN_IN + 1, True),  # nearest the cup but 13 in off: false
               judged(1.0, 1.0, True),  # the box again: a second record is false
               judged(0.0, 95.0, False)]  # the can, 5 in off: found, handled wrong
    assert found_and_right(records, TRUTHS) == Found(found=2, right=1, false=2)


def test_an_object_is_right_by_its_first_record_and_nothing_is_found_on_an_empty_floor() -> None:
    assert found_and_right([judged(0.0, 0.0, False), judged(0.0, 0.0, True)], TRUTHS) == Found(1, 0, 1)
    assert found_and_right([judged(0.0, 0.0, True)], []) == Found(0, 0, 1)


def test_the_built_grid_comes_to_the_truths_cells_whatever_its_extent_and_resolution() -> None:
    truth = TruthMap(np.zeros((4, 4), bool), 0.0, 0.0, 2.0)  # x and y 0 to 8 in, row 0 at y 0 to 2
    fine = OccupancyGrid(0.0, 0.0, 8.0, 8.0, 1.0)  # 8 x 8, row 0 at y 7 to 8
    mask = np.zeros(fine.shape, bool)
    mask[1, 5] = True  # centred at (5.5, 6.5): truth row 3, col 2
    assert np.argwhere(on_truth_cells(mask, fine, truth)).tolist() == [[3, 2]]
    wide = OccupancyGrid(-4.0, -4.0, 12.0, 12.0, 2.0)  # 8 x 8, row 0 at y 10 to 12
    mask = np.zeros(wide.shape, bool)
    mask[0, 0] = True  # centred at (-3, 11): off the truth's cells, left out
    mask[2, 3] = True  # centred at (3, 7): truth row 3, col 1
    assert np.argwhere(on_truth_cells(mask, wide, truth)).tolist() == [[3, 1]]


def test_map_accuracy_of_a_wall_drawn_short_with_one_spurious_cell() -> None:
    # the truth: a wall along the top row (y 6 to 8); rows 0-2 free floor, the start among them
    wall = np.zeros((4, 4), bool)
    wall[3, :] = True
    truth = TruthMap(wall, 0.0, 0.0, 2.0)
    footprint = TruthMap(wall.copy(), 0.0, 0.0, 2.0)
    grid = OccupancyGrid(0.0, 0.0, 8.0, 8.0, 2.0)  # the grid's row 0 is the truth's row 3
    grid.log_odds[0, :3] = 5.0  # three of the wall's four cells
    grid.log_odds[3, 3] = 5.0  # a cell at (7, 1) that is floor: truth row 0, col 3
    grid.log_odds[1:3, :] = -5.0  # truth rows 1 and 2 known free
    accuracy = map_accuracy(grid, truth, footprint, (1.0, 1.0))
    assert accuracy.iou == pytest.approx(3 / 5)  # 3 shared of 5 occupied in either
    assert accuracy.coverage == pytest.approx(8 / 12)  # 8 of the 12 free cells known free
    # visible: the wall's 4 cells, each within a cell of a built one; built: the 3 wall
    # cells are within a cell of the wall, the spurious one is not: (4 + 3) / (4 + 4)
    assert accuracy.surface_iou == pytest.approx(7 / 8)


def test_localisation_errors_at_the_scans_the_truth_was_noted_for() -> None:
    poses = [(1.0, Pose(0.0, 2.0, 0.0), Pose(1.0, 0.0, 0.0)),  # corrected 1 in off, the odometry 2
             (2.0, Pose(16.0, 8.0, 0.0), Pose(13.0, 4.0, 0.0)),  # 5 in (3, 4), the odometry 10 in (6, 8)
             (3.0, Pose(0.0, 0.0, 0.0), Pose(0.0, 0.0, 0.0))]  # no truth for this scan: left out
    true_at = {1.0: Pose(0.0, 0.0, 0.0), 2.0: Pose(10.0, 0.0, 350.0)}
    located = localisation(poses, true_at)
    assert located is not None
    assert located.corrected.position_in == pytest.approx((1.0, 5.0))
    assert (located.median_in, located.corrected.max_in, located.corrected.final_in) == pytest.approx((3.0, 5.0, 5.0))
    assert located.corrected.final_deg == pytest.approx(10.0)  # 0 against 350: 10 degrees round
    assert (located.odometry.max_in, located.odometry.final_in) == pytest.approx((10.0, 10.0))
    assert localisation(poses, {}) is None and localisation([], true_at) is None


def test_the_simulator_notes_where_it_really_stood_at_each_scan_not_where_its_odometry_said() -> None:
    hero = TruthAtScans("t", world="apartment", seed=0, noise=NoiseConfig.preset("paper"))  # odometry drifts
    try:
        hero.move([DriverPose(110.0, 50.0, 0.0)]).result()  # 60 in east, across the first room
        scan = hero.scan().result()
        now = hero.world.pose
        assert hero.true_at == {scan.clock_s: Pose(now.x_in, now.y_in, now.heading_deg)}
        assert (scan.pose.x_in, scan.pose.y_in) != pytest.approx((now.x_in, now.y_in))  # the reply's pose drifted
    finally:
        hero.close()
