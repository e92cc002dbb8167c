"""``PlannerMoveCost`` works out each position's pose once per vision map (issue 32):
the exact rule prices every move between the positions it explores, and a pose costs
more to work out than the price itself. A new map (something moved near the object)
gets the poses worked out again, since a pose steps around the obstacles of its map.

Worked by hand on a drawn room (tests/planner/drawing.py; the HERO's base radius 9 in,
sonar 11 in ahead of the base, the map inflated 10.4 in): the object is a 1.75 in disc
at (100, 90); its position (6, 0) puts the sonar at x 107.75 and the base at 118.5 (to
the pixel), facing the object. A 2 x 20 in box at x 128.5 brings an obstacle to 9 in of
that base: on the map with the box the pose steps nearer the object, within the range
tolerance (planner.positions.free_pose_for_position).
"""

from __future__ import annotations

import math

import pytest

from behaviours.bridge import PlannerMoveCost
from learner.position import Position
from planner import Navigator, Region
from robot_profile import load_profile
from tests.planner.drawing import Canvas

AT = Position(6.0, 0.0)


def _room() -> Canvas:
    return Canvas().disc(100.0, 90.0, 1.75).robot(60.0, 90.0, 90.0)


def _object(nav: Navigator) -> Region:
    return min(nav.scene.regions, key=lambda r: math.hypot(r.centroid[0] - 100.0, r.centroid[1] - 90.0))


class _Counted(Navigator):
    """The real navigator, counting how often a pose is worked out."""

    poses_worked_out = 0

    def pose_for(self, region, distance_in, orientation_deg):  # type: ignore[no-untyped-def]
        self.poses_worked_out += 1
        return super().pose_for(region, distance_in, orientation_deg)


def test_a_pose_is_worked_out_once_per_map() -> None:
    nav = _Counted(load_profile().robot)
    nav.observe(_room().image())
    costs = PlannerMoveCost(nav, _object(nav))
    first = costs.pose(AT)
    assert first.x_in == pytest.approx(118.5) and first.y_in == pytest.approx(90.0)
    for goal in (Position(16.0, 90.0), Position(24.0, 180.0)):
        costs.move_cost(AT, goal)
        costs.move_cost(goal, AT)
    assert costs.pose(AT) == first
    assert nav.poses_worked_out == 3  # AT and the two goals, each once
    nav.observe(_room().image())  # the same obstacles: the same map, the poses kept
    costs.pose(AT)
    assert nav.poses_worked_out == 3


def test_a_new_map_gets_its_own_poses() -> None:
    nav = _Counted(load_profile().robot)
    nav.observe(_room().image())
    costs = PlannerMoveCost(nav, _object(nav))
    before = costs.pose(AT)
    nav.observe(_room().rect(128.5, 90.0, 2.0, 20.0, 0.0).image())
    after = costs.pose(AT)
    assert nav.poses_worked_out == 2
    assert after == nav.pose_for(_object(nav), 6.0, 0.0)  # the new map's pose
    assert not nav.vision_map.is_free(before.x_in, before.y_in) and nav.vision_map.is_free(after.x_in, after.y_in)
    assert 0.0 < before.x_in - after.x_in <= 1.5  # nearer the object, within the range tolerance
