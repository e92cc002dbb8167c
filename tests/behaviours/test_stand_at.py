"""``PlannerMoveCost.stand_at`` (behaviours.bridge): moves from where the robot really
stands are priced from its real pose, on the real planner.

A learner position names where the sonar is, not which way the robot faces. Worked by
hand on a drawn room (tests/planner/drawing.py; the HERO's base radius 9 in, sonar 11 in
ahead of the base): the object is a 1.75 in disc at (100, 90), the robot stands at
(60, 90) facing +y, so its sonar is at (60, 101): 41.5 in from the object's centre,
39.7 in beyond its face. The pose that position names faces the object with the base
11 in behind the sonar, at about (49.4, 103.9): 17.5 in from the real base, and 5.3 in
from the centre of a 6 x 6 in box at (46, 108), deep in its 12 in margin (the 4 in
escape the planner allows does not leave it). The real base is 22.8 in from the box:
clear. Before the fix every move from the start of such an object was priced ``inf``,
so the learner saw no test it could make and grasped blind at an ambiguous leaf.
"""

from __future__ import annotations

import math

import pytest

from behaviours.bridge import PlannerMoveCost, relative_position
from learner.position import Position
from planner import Navigator, Pose, Region
from robot_profile import load_profile
from tests.planner.drawing import Canvas

REAL = Pose(60.0, 90.0, 90.0)
TEST_AT = Position(6.0, 0.0)  # the sonar 6 in out on the object's +x side, clear of everything


def _room() -> tuple[Navigator, Region]:
    nav = Navigator(load_profile().robot)
    nav.observe(Canvas().disc(100.0, 90.0, 1.75).rect(46.0, 108.0, 6.0, 6.0, 0.0).robot(60.0, 90.0, 90.0).image())
    target = min(nav.scene.regions, key=lambda r: math.hypot(r.centroid[0] - 100.0, r.centroid[1] - 90.0))
    return nav, target


def test_the_position_of_a_robot_not_facing_the_object_names_a_pose_in_an_obstacle() -> None:
    nav, target = _room()
    here = relative_position(nav, target, REAL)
    assert here.distance_in == pytest.approx(39.7, abs=0.3)
    facing = PlannerMoveCost(nav, target).pose(here)
    assert math.hypot(facing.x_in - REAL.x_in, facing.y_in - REAL.y_in) == pytest.approx(17.5, abs=0.5)
    assert nav.vision_map.is_free(REAL.x_in, REAL.y_in) and not nav.vision_map.is_free(facing.x_in, facing.y_in)
    assert PlannerMoveCost(nav, target).move_cost(here, TEST_AT) == math.inf  # what the learner was told


def test_moves_from_where_the_robot_stands_are_priced_from_its_real_pose() -> None:
    nav, target = _room()
    estimator = PlannerMoveCost(nav, target)
    before = estimator.move_cost(relative_position(nav, target, REAL), TEST_AT)  # cached, then corrected
    here = estimator.stand_at(REAL)
    assert here == relative_position(nav, target, REAL)
    priced = estimator.move_cost(here, TEST_AT)
    assert before == math.inf and math.isfinite(priced)
    assert priced == pytest.approx(nav.move_cost(REAL, estimator.pose(TEST_AT)).seconds)
    # a move *to* the stood position still ends facing the object
    assert estimator.pose(here).heading_deg == pytest.approx(
        math.degrees(math.atan2(target.centroid[1] - 103.9, target.centroid[0] - 49.4)) % 360.0, abs=2.0)


def test_retarget_forgets_the_real_pose() -> None:
    nav, target = _room()
    estimator = PlannerMoveCost(nav, target)
    here = estimator.stand_at(REAL)
    estimator.retarget(target)  # the object moved: its positions mean other poses now
    assert estimator.move_cost(here, TEST_AT) == math.inf


def test_a_retarget_tells_the_learner_every_price_changed() -> None:
    nav, target = _room()
    costs = PlannerMoveCost(nav, target)
    before = costs.generation
    costs.retarget(target)
    assert costs.generation == before + 1  # learner.costs.estimator_generation reads it
