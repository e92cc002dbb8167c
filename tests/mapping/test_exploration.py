"""Where to explore next, worked out on a hand-made grid of two rooms.

The grid: 2 in cells over x, y in [-10, 250] x [-10, 130]. Two 120 x 120 in rooms side by
side, split at x = 120 by a wall with a 40 in doorway (y 40-80). The left room is
explored (free), except its top-left corner (x < 30, y > 90), which is still unknown; the
right room is unknown. So there are two frontiers: the doorway (20 cells of x 118-120,
y 40-80: 40 in) and the corner's L (15 + 15 cells: the edges x = 30-32 and y = 88-90,
some 60 in), each larger than the 12 in (6 cell) threshold.
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
                                                        (Pose(20.0, 50.0, 90.0), False, (41.0, 97.0))])
def test_the_goal_is_the_nearer_frontier(robot: Pose, doorway: bool, spot: tuple[float, float]) -> None:
    """From (100, 60), beside the doorway, the doorway's viewing pose (109, 61) is 9 in
    away and the corner's (41, 97) 70 in: the doorway. From (20, 50) the corner's is 52 in
    away and the doorway's 90 in: the corner. The sizes (20 and 30 cells) weigh less than
    the distances: scores 5.2 s / √30 = 0.94 against 9.0 s / √20 = 2.0."""
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
    the home is mapped; with the threshold at 2 in it is not (if a pose can see it)."""
    grid = two_rooms(corner_known=True, right_known=True)
    fill(grid, 0.0, 60.0, 2.0, 64.0, 0.0)
    robot = Pose(60.0, 60.0, 0.0)
    assert is_mapped(grid, robot, (), straight_line(robot))
    assert not is_mapped(grid, robot, (), straight_line(robot), ExplorationSettings(min_frontier_in=2.0))


def test_the_choice_is_the_same_every_time() -> None:
    robot = Pose(70.0, 60.0, 0.0)
    goals = {next_goal(two_rooms(), robot, (), straight_line(robot)) for _ in range(3)}
    assert len(goals) == 1
