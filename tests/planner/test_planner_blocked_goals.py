"""A test position whose base pose falls in an (inflated) obstacle moves within the range
tolerance, or is priced as unreachable; it never becomes a failed plan."""

from __future__ import annotations

import math

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from planner import Navigator, Pose, pose_for_position
from planner import paths as reasons
from planner.positions import RANGE_TOLERANCE_IN, TOLERANCE_STEP_IN
from robot_profile import load_profile
from tests.planner.drawing import WALL, Canvas
from tests.planner.sim import drive, robot_pose

ROBOT = load_profile().robot
BOX_X, BOX_Y, HALF = 100.0, 90.0, 3.0  # a 6 x 6 in box; its 0° face is at x = 103


def _beside_a_wall(wall_x: float) -> tuple[Navigator, object]:
    """The box with a wall whose near side is at ``wall_x``, behind its 0° test positions."""
    room = (Canvas().rect(BOX_X, BOX_Y, 2 * HALF, 2 * HALF, 0.0).rect(wall_x + 3.0, BOX_Y, 6.0, 60.0, 0.0, WALL)
            .robot(40.0, 40.0, 0.0))
    nav = Navigator(ROBOT)
    region = next(r for r in nav.observe(room.image()).regions if math.dist(r.centroid, (BOX_X, BOX_Y)) < 1.0)
    return nav, region


def _base_at(region, distance_in: float) -> tuple[float, float]:  # noqa: ANN001
    pose = pose_for_position(region, distance_in, 0.0, ROBOT.geometry)
    return pose.x_in, pose.y_in


def test_a_wall_behind_the_position_moves_it_nearer_by_the_least_that_frees_the_base() -> None:
    # base at x = 103 + 6 + 11 = 120; inflated by the 9 in base radius a wall at 129
    # leaves it blocked down to 5.1 in (found by the map, checked here step by step)
    nav, region = _beside_a_wall(129.0)
    free = nav.vision_map.is_free
    assert not free(*_base_at(region, 6.0))
    pose = nav.pose_for(region, 6.0, 0.0)
    distance, orientation = nav.position_of(region, pose)
    assert free(pose.x_in, pose.y_in) and orientation == pytest.approx(0.0, abs=1e-6)
    assert distance == pytest.approx(5.1, abs=1e-6)
    assert not free(*_base_at(region, distance + TOLERANCE_STEP_IN))
    assert pose.heading_deg == pytest.approx(180.0)  # still facing the object along the same ray
    start = Pose(40.0, 40.0, 0.0)
    assert nav.move_cost(start, pose).possible
    plan = nav.plan_to(start, region, 6.0, 0.0)
    assert plan.found and plan.path[-1] == pose


def test_a_position_blocked_beyond_the_tolerance_is_priced_unreachable() -> None:
    nav, region = _beside_a_wall(126.0)
    pose = nav.pose_for(region, 6.0, 0.0)
    assert pose == pose_for_position(region, 6.0, 0.0, ROBOT.geometry)  # the asked pose, unmoved
    cost = nav.move_cost(Pose(40.0, 40.0, 0.0), pose)
    assert not cost.possible and cost.reason == reasons.GOAL_BLOCKED
    # the other faces are clear and keep their exact poses
    for orientation in (90.0, 180.0, 270.0):
        assert nav.pose_for(region, 6.0, orientation) == pose_for_position(region, 6.0, orientation, ROBOT.geometry)


@settings(max_examples=15, deadline=None)
@given(wall_x=st.floats(124.0, 134.0), distance=st.sampled_from([6.0, 8.0]))
def test_a_moved_position_is_the_nearest_free_one_within_the_tolerance(wall_x: float, distance: float) -> None:
    nav, region = _beside_a_wall(wall_x)
    free = nav.vision_map.is_free
    pose = nav.pose_for(region, distance, 0.0)
    moved, _ = nav.position_of(region, pose)
    if free(*_base_at(region, distance)):
        assert moved == pytest.approx(distance, abs=1e-6)
        return
    if not free(pose.x_in, pose.y_in):  # nothing free within the tolerance: unmoved, priced unreachable
        assert moved == pytest.approx(distance, abs=1e-6)
        assert all(not free(*_base_at(region, distance + s * TOLERANCE_STEP_IN)) for s in range(-15, 16))
        return
    shift = abs(moved - distance)
    assert shift <= RANGE_TOLERANCE_IN + 1e-6
    nearer_shifts = [k * TOLERANCE_STEP_IN for k in range(1, round(shift / TOLERANCE_STEP_IN))]
    assert all(not free(*_base_at(region, distance + s)) and not free(*_base_at(region, distance - s))
               for s in nearer_shifts)


def test_the_demo_lab_position_near_the_wall_is_reached_and_sensed() -> None:
    """Seed 0's lab: 39 in from the object at (70, 60) at 2° the base would stand in the
    south wall's inflated margin (priced unreachable before); moved 0.2 in nearer it is
    planned, driven, and the 1° sweep accepts the distance."""
    hero = SimulatedHero("r1", world="lab", seed=0, noise=NoiseConfig.off())
    nav = Navigator(ROBOT)
    regions = nav.observe(hero.camera().result()).regions
    region = min(regions, key=lambda r: math.dist(r.centroid, (70.0, 60.0)))
    nominal = pose_for_position(region, 39.0, 2.0, ROBOT.geometry)
    assert not nav.vision_map.is_free(nominal.x_in, nominal.y_in)
    plan = nav.plan_to(robot_pose(hero), region, 39.0, 2.0)
    assert plan.found
    distance, _ = nav.position_of(region, plan.path[-1])
    assert 39.0 - RANGE_TOLERANCE_IN <= distance < 39.0
    moved = drive(hero, plan, region.centroid)
    assert not moved.collided
    sensed = hero.sense("H-Sweep-1°").result()
    assert sensed.distance_in == pytest.approx(distance, abs=1.0)
