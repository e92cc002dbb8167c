"""The scan-built map read as a look (mapping/scene.py): the scene's masks, its crop, the
gaps between beams bridged, a candidate's region, and a place seen through."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mapping import OccupancyGrid, PlanarScan
from mapping.candidates import Candidate
from mapping.scene import (BRIDGED_LOG_ODDS, PIXEL_IN2, bridged, candidate_region, map_scene, refit, seen_through,
                           with_keep_out)
from planner.geometry import Pose
from planner.vision import Region
from tests.mapping.synthetic import Lidar, box

EXACT = Lidar(sigma_in=0.0, dropout=0.0)


def scan_at(walls: list[tuple[float, float, float, float]], x: float, y: float, heading: float = 0.0,
            lidar: Lidar = EXACT) -> PlanarScan:
    ranges = lidar.scan(np.array(walls, dtype=float), (x, y, math.radians(heading)), np.random.default_rng(0))
    return PlanarScan(lidar.angles_rad, ranges, x, y, heading, 0.0, lidar.max_range_in)


def square(cx: float, cy: float, half: float) -> list[tuple[float, float, float, float]]:
    return box(cx - half, cy - half, cx + half, cy + half)


def test_the_scene_blocks_unknown_and_occupied_cells_and_keeps_objects_apart() -> None:
    grid = OccupancyGrid(0.0, 0.0, 100.0, 100.0, 1.0)
    grid.log_odds[:, :] = -1.0  # all seen free ...
    grid.log_odds[10:20, 10:20] = 0.0  # ... but a patch never seen
    grid.log_odds[50, 50] = 2.0  # and one occupied cell (row 50 is y 49-50, col 50 is x 50-51)
    region = Region(((70.0, 70.0), (74.0, 70.0), (74.0, 74.0), (70.0, 74.0)), (72.0, 72.0), 25, 0.0, False, 4.0, 4.0)
    scene = map_scene(grid, [region], Pose(40.0, 40.0, 0.0), margin_in=0.0)
    assert scene.image.shape == (100, 100)  # everything seen: nothing cropped
    assert scene.furniture[10:20, 10:20].all() and scene.furniture[50, 50]
    assert np.count_nonzero(scene.furniture) == 101  # the unknown patch and the one hit
    # the region's cells are the objects mask: x 70-74, y 70-74 is rows 26-29, cols 70-73 (4 x 4 cells)
    assert np.count_nonzero(scene.objects) == pytest.approx(16, abs=9)  # polygon edges may take a cell more
    assert scene.objects[27:29, 71:73].all() and not (scene.objects & scene.furniture).any()
    assert scene.robot == Pose(40.0, 40.0, 0.0) and scene.regions == (region,)


def test_a_kept_out_place_is_furniture_but_never_over_an_object() -> None:
    """A keep-out square x 20-30, y 60-70 (rows 30-39, cols 20-29) on floor seen free,
    and one over the region's corner: furniture, except the region's own cells."""
    grid = OccupancyGrid(0.0, 0.0, 100.0, 100.0, 1.0)
    grid.log_odds[:, :] = -1.0
    region = Region(((70.0, 70.0), (74.0, 70.0), (74.0, 74.0), (70.0, 74.0)), (72.0, 72.0), 25, 0.0, False, 4.0, 4.0)
    square_out = np.array([(20.0, 60.0), (30.0, 60.0), (30.0, 70.0), (20.0, 70.0)])
    over = np.array([(68.0, 68.0), (72.0, 68.0), (72.0, 72.0), (68.0, 72.0)])
    plain = map_scene(grid, [region], None, margin_in=0.0)
    scene = map_scene(grid, [region], None, margin_in=0.0, keep_out=[square_out, over])
    assert not plain.furniture.any()
    assert scene.furniture[31:39, 21:29].all() and not scene.furniture[45:55, 45:55].any()
    assert np.array_equal(scene.objects, plain.objects) and not (scene.objects & scene.furniture).any()
    assert scene.furniture[31, 68:73].all() and scene.furniture[28:31, 68:70].all()  # the second square off the region
    assert np.array_equal(with_keep_out(plain, [square_out, over]).furniture, scene.furniture)


def test_occupied_within_measures_from_the_point_to_cell_centres() -> None:
    """One occupied cell, x 50-51, y 49-50 (centre 50.5, 49.5): 3.5 in from (50.5, 53)."""
    grid = OccupancyGrid(0.0, 0.0, 100.0, 100.0, 1.0)
    grid.log_odds[50, 50] = 2.0
    assert grid.occupied_within(50.5, 53.0, 3.6) and not grid.occupied_within(50.5, 53.0, 3.4)
    assert not grid.occupied_within(-500.0, 53.0, 10.0)  # off the grid: nothing


def test_the_scene_is_cropped_to_what_was_seen_and_a_margin() -> None:
    grid = OccupancyGrid(0.0, 0.0, 200.0, 200.0, 2.0)  # 100 x 100 cells, all unknown ...
    grid.log_odds[40:50, 30:40] = -1.0  # ... but a 20 x 20 in patch, x 60-80, y 100-120
    scene = map_scene(grid, [], None, margin_in=10.0)  # 5 cells round it
    assert scene.image.shape == (20, 20)
    assert scene.image.grid.origin_x_in == pytest.approx(50.0) and scene.image.grid.origin_y_in == pytest.approx(130.0)
    assert not scene.furniture[5:15, 5:15].any() and scene.furniture[:5].all()


def test_narrow_gaps_between_beams_are_bridged_but_never_near_a_hit() -> None:
    grid = OccupancyGrid(0.0, 0.0, 60.0, 60.0, 1.0)
    grid.log_odds[:, :] = -1.0
    grid.log_odds[:, 20] = 0.0  # a one-cell stripe no beam crossed: floor between two beams
    grid.log_odds[40:43, 40:43] = 0.0  # a 3-cell blob of unknown ...
    grid.log_odds[41, 41] = 2.0  # ... round a small object hit once
    out = bridged(grid)
    assert out.free[5:55, 20].all() and (out.log_odds[5:55, 20] == BRIDGED_LOG_ODDS).all()
    assert out.unknown[40, 40] and out.occupied[41, 41]  # the object's surroundings stay unknown
    assert grid.unknown[30, 20], "the grid itself is left as it was"


def test_a_candidate_seen_all_round_is_outlined_by_the_fit() -> None:
    walls = square(0.0, 0.0, 3.0)  # a 6 in square box at the origin
    views = [(scan_at(walls, x, y, 0.0), Pose(x, y, 0.0)) for x, y in ((24, 0), (0, 24), (-24, 0), (0, -24))]
    candidate = Candidate(1, 0.3, -0.2, ((3.0, 0.0), (0.0, 3.0), (-3.0, 0.0), (0.0, -3.0)), 6.0, 4, 0.0, 1.0)
    region = candidate_region(candidate, views, range_sigma_in=0.05)
    assert region.centroid == pytest.approx((0.0, 0.0), abs=0.05)
    assert region.length_in == pytest.approx(6.0, abs=0.2) and region.width_in == pytest.approx(6.0, abs=0.2)
    assert not region.round and region.pixel_count == pytest.approx(36.0 / PIXEL_IN2, rel=0.08)
    assert region.area_in2 is None and region.elongation is None  # a scan gives no appearance


def test_a_candidate_too_thin_to_fit_falls_back_to_its_own_returns() -> None:
    candidate = Candidate(7, 10.0, 5.0, ((8.0, 5.0), (10.0, 5.0), (12.0, 5.0)), 4.0, 2, 0.0, 1.0)
    region = candidate_region(candidate, [], range_sigma_in=0.5)
    assert region.centroid == pytest.approx((10.0, 5.0))
    assert region.length_in == pytest.approx(4.0) and region.width_in == pytest.approx(1.0)  # at least MIN_SIDE_IN
    assert region.orientation_deg in (pytest.approx(0.0, abs=1e-6), pytest.approx(180.0, abs=1e-6))


def test_a_place_is_seen_through_only_when_beams_cross_it_and_come_back_from_beyond() -> None:
    room = box(-60.0, -60.0, 60.0, 60.0)
    place = Region(((18.0, -2.0), (22.0, -2.0), (22.0, 2.0), (18.0, 2.0)), (20.0, 0.0), 25, 0.0, False, 4.0, 4.0)
    assert seen_through(place, scan_at(room, 0.0, 0.0), Pose(0.0, 0.0, 0.0))  # nothing there: the wall beyond
    assert not seen_through(place, scan_at(room + square(20.0, 0.0, 2.0), 0.0, 0.0), Pose(0.0, 0.0, 0.0))
    occluded = room + [(10.0, -6.0, 10.0, 6.0)]  # a screen between the robot and the place
    assert not seen_through(place, scan_at(occluded, 0.0, 0.0), Pose(0.0, 0.0, 0.0))
    blind = scan_at(room, 0.0, 0.0)
    dark = PlanarScan(blind.angles_rad, np.full_like(blind.ranges_in, math.inf), 0.0, 0.0, 0.0, 0.0, blind.max_range_in)
    assert not seen_through(place, dark, Pose(0.0, 0.0, 0.0))  # no echo at all is not a sighting
    assert not seen_through(place, blind, Pose(19.0, 0.0, 0.0))  # standing on the place: nothing to tell


def _on_square(cx: float, cy: float, half: float, n: int = 8) -> np.ndarray:
    """Returns on the two faces of a square facing -x and -y (what one scan sees)."""
    t = np.linspace(-half, half, n)
    return np.vstack([np.column_stack([np.full(n, cx - half), cy + t]), np.column_stack([cx + t, np.full(n, cy - half)])])


def test_a_region_is_moved_to_where_the_scan_sees_its_object_pushed() -> None:
    region = Region(((-3.0, -3.0), (3.0, -3.0), (3.0, 3.0), (-3.0, 3.0)), (0.0, 0.0), 56, 0.0, False, 6.0, 6.0)
    assert refit(region, _on_square(0.0, 0.0, 3.0)) is region  # seen where it is: kept as it was
    pushed = refit(region, _on_square(2.5, -1.0, 3.0))
    assert pushed.centroid == pytest.approx((2.5, -1.0), abs=0.05)
    assert pushed.pixel_count == region.pixel_count and pushed.length_in == region.length_in
    assert pushed.polygon[0] == pytest.approx((-0.5, -4.0), abs=0.05)
    assert refit(region, _on_square(0.3, 0.0, 3.0)) is region  # under half an inch: the outline's own noise
    wall = np.column_stack([np.full(12, -4.0), np.linspace(-8.0, 8.0, 12)])
    assert refit(region, wall) is region  # a line longer than the footprint: not this object
    assert refit(region, np.zeros((0, 2))) is region
