"""The real OMPL planner on a scan-built map: it finds paths through what the scans saw
and never through what they did not."""

from __future__ import annotations

import math

import numpy as np
import pytest

from mapping import OccupancyGrid, PlanarScan, planning_map
from planner.geometry import Pose
from planner.paths import GOAL_BLOCKED, UNREACHABLE, PathPlanner
from tests.mapping.synthetic import Lidar, box

BASE_RADIUS_IN = 8.0
LIDAR = Lidar(sigma_in=0.5, dropout=0.05)


def two_rooms(door_open: bool = True) -> np.ndarray:
    """A 240 x 120 in flat split at x = 120 by a wall with a 40 in doorway (y 40-80)."""
    walls = box(0.0, 0.0, 240.0, 120.0) + [(120.0, 0.0, 120.0, 40.0), (120.0, 80.0, 120.0, 120.0)]
    if not door_open:
        walls.append((120.0, 40.0, 120.0, 80.0))
    return np.array(walls, dtype=float)


def scanned(poses: list[tuple[float, float]], door_open: bool = True) -> OccupancyGrid:
    """The flat mapped from scans at ``poses`` (true poses: the grid alone is under test)."""
    walls, rng = two_rooms(door_open), np.random.default_rng(1)
    grid = OccupancyGrid(-12.0, -12.0, 252.0, 132.0, 2.0)
    for x, y in poses:
        ranges = LIDAR.scan(walls, (x, y, 0.0), rng)
        grid.integrate(PlanarScan(LIDAR.angles_rad, ranges, x, y, 0.0, 0.0, LIDAR.max_range_in))
    return grid


BOTH_ROOMS = [(30.0 + 20.0 * i, 30.0 + 20.0 * j) for i in range(10) for j in range(4)]


def test_a_path_through_the_doorway_on_a_scan_built_map() -> None:
    vision_map = planning_map(scanned(BOTH_ROOMS), BASE_RADIUS_IN)
    planner = PathPlanner(vision_map)
    result = planner.plan(Pose(40.0, 100.0, 0.0), Pose(200.0, 20.0, 0.0))
    assert result.found, result.reason
    corners = [(40.0, 100.0), *result.corners]
    assert all(vision_map.segment_is_free(p, q) for p, q in zip(corners, corners[1:]))
    crossing = [p for p, q in zip(corners, corners[1:]) if (p[0] - 120.0) * (q[0] - 120.0) <= 0]
    assert crossing, "the path must cross the dividing wall"
    # where it crosses x = 120 it is in the doorway, at least the base's radius from its posts
    for p, q in zip(corners, corners[1:]):
        if (p[0] - 120.0) * (q[0] - 120.0) < 0:
            y = p[1] + (q[1] - p[1]) * (120.0 - p[0]) / (q[0] - p[0])
            assert 40.0 + BASE_RADIUS_IN <= y <= 80.0 - BASE_RADIUS_IN


def test_no_path_into_or_through_unknown_space() -> None:
    """Only the left room scanned, its door shut: the right room is unknown, so a goal
    there is blocked; and with a strip of the left room forgotten, its two ends are not
    connected."""
    grid = scanned([(30.0 + 20.0 * i, 30.0 + 20.0 * j) for i in range(4) for j in range(4)], door_open=False)
    assert grid.unknown[grid.cell_of(200.0, 60.0)]
    planner = PathPlanner(planning_map(grid, BASE_RADIUS_IN))
    assert planner.plan(Pose(40.0, 60.0, 0.0), Pose(200.0, 60.0, 0.0)).reason == GOAL_BLOCKED
    assert planner.plan(Pose(20.0, 60.0, 0.0), Pose(100.0, 60.0, 0.0)).found
    strip = grid.cell_of(60.0, 60.0)[1]
    grid.log_odds[:, strip - 1:strip + 2] = 0.0  # 6 in wide, wall to wall: unknown again
    planner = PathPlanner(planning_map(grid, BASE_RADIUS_IN))
    assert planner.plan(Pose(20.0, 60.0, 0.0), Pose(100.0, 60.0, 0.0)).reason == UNREACHABLE


def test_unknown_space_is_inflated_like_an_obstacle() -> None:
    """A lone unknown cell in known free space keeps the base centre at least its radius
    away: the cell itself and points within the radius are not free, points beyond the
    inflation are."""
    grid = OccupancyGrid(0.0, 0.0, 100.0, 100.0, 2.0)
    grid.log_odds[:] = -1.0
    row, col = grid.cell_of(50.0, 50.0)
    grid.log_odds[row, col] = 0.0
    vision_map = planning_map(grid, BASE_RADIUS_IN)
    assert not vision_map.is_free(51.0, 51.0)
    assert not vision_map.is_free(51.0 + BASE_RADIUS_IN, 51.0)
    assert vision_map.is_free(51.0 + vision_map.inflation_in + 2.0 * math.sqrt(2), 51.0)
    assert vision_map.inflation_in == pytest.approx(BASE_RADIUS_IN + (1 + math.sqrt(0.5)) * 2.0)


def test_a_negative_radius_is_refused() -> None:
    with pytest.raises(ValueError, match="base_radius_in"):
        planning_map(OccupancyGrid(0.0, 0.0, 10.0, 10.0, 1.0), -1.0)
