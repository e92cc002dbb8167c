"""Where to explore next, worked out on a hand-made grid of two rooms.

The grid: 2 in cells over x, y in [-10, 250] x [-10, 130]. Two 120 x 120 in rooms side by
side, split at x = 120 by a wall with a 40 in doorway (y 40-80). The left room is
explored (free), except its top-left corner (x < 30, y > 90), which is still unknown; the
right room is unknown. So there are two frontiers: the doorway and the corner's L. Only
unknown cells more than 6 in (``surface_in``) from the centre of every occupied cell
count, so the cells beside the doorway's posts and beside the corner's walls do not:
the doorway's frontier is 14 cells (x 118-120, centres y = 47-73: an unknown cell at
y 45 is 6 in from the post's cell at y 39), the corner's L 12 + 12 cells (the edge
x = 30-32 up to the cell centred y = 113, 8 in below the top wall's cells centred
y = 121; the edge y = 88-90 from the cell centred x = 7, 8 in right of the left wall's
cells centred x = -1), each larger than the 12 in (6 cell) threshold.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from mapping import OccupancyGrid
from mapping.candidates import Candidate
from mapping.exploration import ExplorationSettings, is_mapped, next_goal, standing_room
from mapping.occupancy import HIT, MISS
from planner.geometry import Pose

SPEED_IN_S = 10.0


def fill(grid: OccupancyGrid, x0: float, y0: float, x1: float, y1: float, value: float) -> None:
    """Set the cells whose centres lie in [x0, x1) x [y0, y1)."""
    rows, cols = grid.shape
    centres = grid.grid.to_world(*np.indices((rows, cols)).reshape(2, -1)).reshape(rows, cols, 2)
    inside = (centres[..., 0] >= x0) & (centres[..., 0] < x1) & (centres[..., 1] >= y0) & (centres[..., 1] < y1)
    grid.log_odds[inside] = value


def two_rooms(corner_known: bool = False, right_known: bool = False) -> OccupancyGrid:
    grid = OccupancyGrid(-10.0, -10.0, 250.0, 130.0, 2.0)
    fill(grid, 0.0, 0.0, 120.0, 120.0, MISS)
    if not corner_known:
        fill(grid, 0.0, 90.0, 30.0, 120.0, 0.0)
    if right_known:
        fill(grid, 120.0, 0.0, 240.0, 120.0, MISS)
    for x0, y0, x1, y1 in ((-4, -4, 244, 0), (-4, 120, 244, 124), (-4, -4, 0, 124), (240, -4, 244, 124),
                           (120, 0, 122, 40), (120, 80, 122, 120)):
        fill(grid, x0, y0, x1, y1, HIT)
    if not right_known:
        fill(grid, 122.0, 0.0, 240.0, 120.0, 0.0)
        fill(grid, 120.0, 40.0, 122.0, 80.0, 0.0)
    return grid


def straight_line(robot: Pose):
    return lambda pose: math.dist((robot.x_in, robot.y_in), (pose.x_in, pose.y_in)) / SPEED_IN_S


@pytest.mark.parametrize(("robot", "doorway", "spot"), [(Pose(100.0, 60.0, 0.0), True, (109.0, 61.0)),
                                                        (Pose(20.0, 50.0, 90.0), False, (41.0, 95.0))])
def test_the_goal_is_the_nearer_frontier(robot: Pose, doorway: bool, spot: tuple[float, float]) -> None:
    """The corner's middle is its cell nearest the centroid (24.5, 95.5), (31, 95); the
    nearest cell 12 in from every unknown cell is (41, 95). From (100, 60), beside the
    doorway, the doorway's viewing pose (109, 61) is 9 in away and the corner's 69 in:
    the doorway. From (20, 50) the corner's is 50 in away and the doorway's 90 in: the
    corner. The sizes (14 and 24 cells) weigh less than the distances: scores
    5.0 s / √24 = 1.0 against 9.0 s / √14 = 2.4."""
    grid = two_rooms()
    goal = next_goal(grid, robot, (), straight_line(robot))
    assert goal is not None
    assert (goal.target_x_in > 100.0) is doorway
    assert (goal.pose.x_in, goal.pose.y_in) == spot
    # the viewing pose is in explored space, clear of the walls and the unknown, facing the target
    row, col = grid.cell_of(goal.pose.x_in, goal.pose.y_in)
    assert grid.free[row, col]
    assert standing_room(grid)[row, col]
    assert math.dist((goal.pose.x_in, goal.pose.y_in), (goal.target_x_in, goal.target_y_in)) <= 60.0
    facing = math.degrees(math.atan2(goal.target_y_in - goal.pose.y_in, goal.target_x_in - goal.pose.x_in))
    assert goal.pose.heading_deg == pytest.approx(facing)
    travel_in = math.dist((robot.x_in, robot.y_in), (goal.pose.x_in, goal.pose.y_in))
    assert goal.cost_s == pytest.approx(travel_in / SPEED_IN_S)


def test_the_doorway_viewing_pose_stands_back_from_the_posts() -> None:
    """The doorway's middle is at (119, 59) or (119, 61); the nearest cell whose centre is
    12 in from the centre of every wall and unknown cell is 12 in in front of the
    doorway's unknown cells (centred on x = 121): x = 109, level with it."""
    robot = Pose(60.0, 20.0, 0.0)
    goal = next_goal(two_rooms(corner_known=True), robot, (), straight_line(robot))
    assert goal is not None and goal.target_x_in == 119.0 and 59.0 <= goal.target_y_in <= 61.0
    assert goal.pose.x_in == 109.0 and goal.pose.y_in == goal.target_y_in


def test_an_unreachable_frontier_is_passed_over() -> None:
    """The planner says the doorway cannot be reached (cost inf): the corner is next."""
    robot = Pose(100.0, 60.0, 0.0)
    cost = straight_line(robot)
    goal = next_goal(two_rooms(), robot, (), lambda p: math.inf if p.x_in > 60.0 else cost(p))
    assert goal is not None and goal.target_x_in < 40.0


def test_a_candidate_keeps_the_viewing_pose_off_it() -> None:
    """A candidate at the doorway's viewing pose: the pose moves 12 in or more from its outline."""
    robot = Pose(60.0, 20.0, 0.0)
    grid = two_rooms(corner_known=True)
    first = next_goal(grid, robot, (), straight_line(robot))
    assert first is not None
    spot = (first.pose.x_in, first.pose.y_in)
    candidate = Candidate(1, *spot, (spot,), 0.0, 3, 0.0, 1.0)
    moved = next_goal(grid, robot, (candidate,), straight_line(robot))
    assert moved is not None and math.dist((moved.pose.x_in, moved.pose.y_in), spot) >= 12.0


def test_mapped_when_no_frontier_is_left() -> None:
    grid = two_rooms(corner_known=True, right_known=True)
    robot = Pose(60.0, 60.0, 0.0)
    assert next_goal(grid, robot, (), straight_line(robot)) is None
    assert is_mapped(grid, robot, (), straight_line(robot))
    assert not is_mapped(two_rooms(), robot, (), straight_line(robot))


def test_small_frontiers_do_not_count() -> None:
    """Only a 4 in (2 cell) unknown notch is left on the left wall's inside: below 12 in,
    the home is mapped; with the threshold at 2 in it is not (if a pose can see it),
    unknown space beside a wall counted (``surface_in`` 0). As it is (6 in), the notch
    is the wall's own: its cells are 2 in from the wall's."""
    grid = two_rooms(corner_known=True, right_known=True)
    fill(grid, 0.0, 60.0, 2.0, 64.0, 0.0)
    robot = Pose(60.0, 60.0, 0.0)
    assert is_mapped(grid, robot, (), straight_line(robot))
    counted = ExplorationSettings(min_frontier_in=2.0, surface_in=0.0)
    assert not is_mapped(grid, robot, (), straight_line(robot), counted)
    assert is_mapped(grid, robot, (), straight_line(robot), ExplorationSettings(min_frontier_in=2.0))


def test_a_frontier_whose_middle_no_pose_sees_is_looked_at_from_its_end() -> None:
    """The corner known, and of the right room only a 16 in strip seen straight through
    the doorway (y 52-68, up to the far wall): two frontiers along the strip's edges, the
    top one 57 cells (centres x = 121-233, y = 67: the cells beyond lie within 6 in of
    the far wall) and 3 in the doorway beside it (x = 119, y = 69-73), 60 cells centred
    on (174.1, 67.2). Its middle (175, 67) lies in the strip, where no cell is 12 in from
    the unknown, and the left room's cells are more than 60 in from it. Its cell nearest
    the robot at (60, 64) is (119, 69), 59.2 in away: seen from (109, 69), 49.2 in from the
    robot (4.9 s). The bottom edge's, mirrored, is (119, 51), seen from (109, 51), 50.7 in
    from the robot (5.1 s): the top one is chosen."""
    grid = two_rooms(corner_known=True)
    fill(grid, 120.0, 52.0, 240.0, 68.0, MISS)
    robot = Pose(60.0, 64.0, 0.0)
    goal = next_goal(grid, robot, (), straight_line(robot))
    assert goal is not None and goal.frontier.size == 60
    assert (goal.target_x_in, goal.target_y_in) == (119.0, 69.0)
    assert (goal.pose.x_in, goal.pose.y_in, goal.pose.heading_deg) == (109.0, 69.0, 0.0)
    assert goal.cost_s == pytest.approx(math.hypot(49.0, 5.0) / SPEED_IN_S)


def speckled_wall() -> OccupancyGrid:
    """60 x 40 in of 1 in cells, cell (row, col) centred on x = col + 0.5, y = 39.5 - row:
    a room (rows 9-39 free) whose top wall a noisy range finder left speckled. Its face,
    row 8, is occupied in every third column (0, 3, ...) and free in the others (returns
    measured long cleared them); behind it row 7 is free in those same every-third
    columns and unknown in the others; rows 0-6 are unknown (the wall's inside)."""
    grid = OccupancyGrid(0.0, 0.0, 60.0, 40.0, 1.0)
    grid.log_odds[9:, :] = MISS
    grid.log_odds[8, :] = MISS
    grid.log_odds[8, ::3] = HIT
    grid.log_odds[7, ::3] = MISS
    return grid


def test_a_speckled_wall_is_not_chased() -> None:
    """Every unknown cell counted, the speckle is one frontier of 60 cells: row 8's 40
    free cells and row 7's 20, which touch at their corners. Its centroid is (30.0,
    31.83) and its middle the cell (8, 29) at (29.5, 31.5); the nearest cell 12 in from
    the face's occupied cells, (29.5, 19.5), sees it straight up column 29: the robot is
    sent there. Yet every unknown cell beside a free one is at most 1.4 in from an
    occupied face cell, within 6 in (``surface_in``): nothing to explore."""
    grid = speckled_wall()
    robot = Pose(30.0, 10.0, 0.0)
    chased = next_goal(grid, robot, (), straight_line(robot), ExplorationSettings(surface_in=0.0))
    assert chased is not None and chased.frontier.size == 60
    assert (chased.target_x_in, chased.target_y_in) == (29.5, 31.5)
    assert (chased.pose.x_in, chased.pose.y_in, chased.pose.heading_deg) == (29.5, 19.5, 90.0)
    assert next_goal(grid, robot, (), straight_line(robot)) is None
    assert is_mapped(grid, robot, (), straight_line(robot))


def test_the_choice_is_the_same_every_time() -> None:
    robot = Pose(70.0, 60.0, 0.0)
    goals = {next_goal(two_rooms(), robot, (), straight_line(robot)) for _ in range(3)}
    assert len(goals) == 1
