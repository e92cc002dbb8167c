"""The move-cost heuristic: formula, estimate mode, exact mode."""

from __future__ import annotations

from dataclasses import replace

import math

import pytest

from planner import CostEstimator, Navigator, Pose, build_vision_map, look
from planner import move_seconds
from planner import paths as reasons
from robot_profile import Robot, load_profile
from tests.planner.drawing import WALL, Canvas

# the constants worked with by hand; any other the profile gains comes from the shipped one
MODEL = replace(load_profile().robot.motion, speed_in_per_s=0.5, turn_deg_per_s=5.0, vision_s=5.0, centring_s=15.0)
HERO = load_profile().robot.geometry  # the shipped profile's: base radius 9 in, sonar 11 in ahead of the centre


def test_formula_by_hand():
    # 40 in at 0.5 in/s, 90° at 5°/s, plus 5 s of vision and 15 s of centring.
    assert move_seconds(MODEL, 40.0, 90.0) == pytest.approx(80 + 18 + 5 + 15)
    assert move_seconds(MODEL, math.inf, 0.0) == math.inf


@pytest.fixture(scope="module")
def estimator() -> CostEstimator:
    room = Canvas().rect(120.0, 65.0, 6.0, 130.0, 0.0, WALL).robot(40.0, 40.0, 0.0)
    return CostEstimator(build_vision_map(look(room.image()), HERO), MODEL)


def test_estimate_of_a_clear_straight_move(estimator):
    cost = estimator.estimate(Pose(40.0, 40.0, 0.0), Pose(80.0, 40.0, 90.0))
    assert cost.possible and not cost.exact
    assert cost.length_in == pytest.approx(40.0, rel=0.05)
    assert cost.turning_deg == pytest.approx(90.0)
    assert cost.seconds == pytest.approx(move_seconds(MODEL, cost.length_in, 90.0))


def test_estimate_counts_the_detour(estimator):
    # Round the wall's top end at y = 130: up ~100 in, across, down ~100 in.
    cost = estimator.estimate(Pose(40.0, 40.0, 0.0), Pose(200.0, 40.0, 0.0))
    assert cost.length_in > 2 * 90.0 + 80.0
    # Left to climb, right over the top, right to descend, left to the goal heading:
    # the straight line's turns (none) would miss all of it.
    assert 180.0 < cost.turning_deg < 400.0


def test_already_there_costs_nothing(estimator):
    here = Pose(40.0, 40.0, 10.0)
    assert estimator.estimate(here, Pose(40.2, 40.1, 11.0)).seconds == 0.0


@pytest.mark.parametrize("goal, reason", [(Pose(120.0, 40.0, 0.0), reasons.GOAL_BLOCKED),
                                          (Pose(500.0, 40.0, 0.0), reasons.GOAL_OUTSIDE)])
def test_impossible_moves_cost_infinity(estimator, goal, reason):
    cost = estimator.estimate(Pose(40.0, 40.0, 0.0), goal)
    assert cost.seconds == math.inf and not cost.possible and cost.reason == reason


def test_exact_and_estimate_agree_on_a_detour():
    room = Canvas().rect(120.0, 65.0, 6.0, 130.0, 0.0, WALL).robot(40.0, 40.0, 0.0)
    navigator = Navigator(Robot(HERO, MODEL))
    navigator.observe(room.image())
    start, goal = Pose(40.0, 40.0, 0.0), Pose(200.0, 40.0, 270.0)
    exact = navigator.move_cost(start, goal, exact=True)
    estimate = navigator.move_cost(start, goal)
    assert exact.exact and exact.possible
    assert estimate.seconds == pytest.approx(exact.seconds, rel=0.15)


def test_pricing_many_candidates_reuses_one_distance_field():
    room = Canvas().rect(120.0, 65.0, 6.0, 130.0, 0.0, WALL).robot(40.0, 40.0, 0.0)
    estimator = CostEstimator(build_vision_map(look(room.image()), HERO), MODEL)
    start = Pose(40.0, 40.0, 0.0)
    costs = [estimator.estimate(start, Pose(float(x), 90.0, 0.0)) for x in range(60, 110, 5)]
    assert all(c.possible for c in costs)
    assert estimator.fields_computed == 1


def test_estimate_from_just_inside_the_margin_is_finite(estimator):
    cost = estimator.estimate(Pose(107.5, 60.0, 0.0), Pose(40.0, 100.0, 90.0))
    assert cost.possible
    deep = estimator.estimate(Pose(118.0, 60.0, 0.0), Pose(40.0, 100.0, 90.0))
    assert deep.reason == reasons.START_BLOCKED and not deep.possible
