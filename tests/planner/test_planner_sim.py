"""The planner against the simulated HERO's default lab: vision, positions, move costs."""

from __future__ import annotations

import math
import statistics

import pytest

from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from learner.training.stage import training_orientations
from planner import look
from planner.geometry import angle_between
from planner.move_cost import arrived
from tests.planner.sim import drive, navigator, robot_pose
from tests.planner.test_vision_orientations import as_training_object


def truth_by_position(hero: SimulatedHero, region):
    return min(hero.truth(), key=lambda t: math.dist((t.x_in, t.y_in), region.centroid))


@pytest.mark.parametrize("fisheye", [False, True])
def test_lab_regions_match_the_ground_truth(fisheye):
    hero = SimulatedHero(seed=1, noise=NoiseConfig(fisheye=fisheye))
    scene = look(hero.camera().result())
    truth = hero.truth()
    assert len(scene.regions) == len(truth)
    tolerance = 1.0 if fisheye else 0.5
    for region in scene.regions:
        real = truth_by_position(hero, region)
        assert math.dist(region.centroid, (real.x_in, real.y_in)) < tolerance
    pose = hero.state().pose
    assert math.dist((scene.robot.x_in, scene.robot.y_in), (pose.x_in, pose.y_in)) < tolerance
    assert angle_between(scene.robot.heading_deg, pose.heading_deg) < 3.0


def test_lab_orientations_follow_the_objects_yaw():
    hero = SimulatedHero(seed=1, noise=NoiseConfig.off())
    scene = look(hero.camera().result())
    elongated = [r for r in scene.regions if r.length_in > 1.5 * r.width_in and r.pixel_count >= 20]
    assert len(elongated) >= 2  # the magazine box and the lying bottle
    for region in elongated:
        real = truth_by_position(hero, region)
        # Symmetric footprints: either end of the axis may hold more pixels.
        assert angle_between(region.orientation_deg % 180, real.yaw_deg % 180) < 5 or \
            angle_between(region.orientation_deg % 180, real.yaw_deg % 180) > 175
    found = training_orientations([as_training_object(r) for r in scene.regions])
    assert len(found) == 4
    for want in (0.0, 90.0, 180.0, 270.0):
        assert min(angle_between(f, want) for f in found) < 8.0


def test_planned_positions_put_the_sonar_at_the_asked_distance():
    hero = SimulatedHero(seed=2, noise=NoiseConfig.off())
    nav = navigator()
    regions = nav.observe(hero.camera().result()).regions
    checked = 0
    for region, distance, orientation in [(regions[2], 6.0, 90.0), (regions[4], 16.0, 0.0),
                                          (regions[6], 6.0, 180.0), (regions[0], 24.0, 270.0)]:
        plan = nav.plan_to(robot_pose(hero), region, distance, orientation)
        if not plan.found:
            continue
        moved = drive(hero, plan, region.centroid)
        assert not moved.collided and moved.centred
        sensed = hero.sense("H-Sweep-5°").result()
        assert sensed.distance_in == pytest.approx(distance, abs=1.0)
        nav.observe(hero.camera().result())
        checked += 1
    assert checked >= 3


def test_move_costs_track_the_simulated_move_times():
    hero = SimulatedHero(seed=3)
    nav = navigator()
    regions = nav.observe(hero.camera().result()).regions
    estimate_errors, exact_errors = [], []
    for k in range(12):
        region = regions[(5 * k) % len(regions)]
        start = robot_pose(hero)
        goal = nav.pose_for(region, (6.0, 16.0, 24.0)[k % 3], (0.0, 90.0, 180.0, 270.0)[k % 4])
        plan = nav.plan(start, goal)
        if not plan.found or arrived(start, goal):
            continue
        estimate = nav.move_cost(start, goal)
        exact = nav.move_cost(start, goal, exact=True)
        actual = drive(hero, plan, region.centroid).duration_s
        estimate_errors.append(abs(estimate.seconds - actual) / actual)
        exact_errors.append(abs(exact.seconds - actual) / actual)
        nav.observe(hero.camera().result())
    assert len(exact_errors) >= 8
    assert statistics.median(exact_errors) < 0.05
    assert statistics.median(estimate_errors) < 0.15
