"""Test and grasp positions among objects close together (docs/planner.md "Clutter"):
a position whose base would stand on a neighbour is priced ``inf`` (moved within the
range tolerance first), and driving to any position priced finite never touches an
object in the simulator (pymunk's contact count stays 0)."""

from __future__ import annotations

import math

import pytest

from hero_driver.interface import Pose as DriverPose
from hero_driver.sim.world import SimWorld
from planner import Navigator, Pose, Region
from robot_profile import load_profile

CLOSE = [(70.0, 60.0), (75.2, 60.0), (130.0, 110.0), (130.0, 115.0), (137.5, 110.0)]  # clutter.json's pair and trio


def region_at(nav: Navigator, x: float, y: float) -> Region:
    return min(nav.scene.regions, key=lambda r: math.hypot(r.centroid[0] - x, r.centroid[1] - y))


def here(sim: SimWorld) -> Pose:
    return Pose(sim.pose.x_in, sim.pose.y_in, sim.pose.heading_deg)


def test_the_position_between_a_close_pair_is_unreachable() -> None:
    sim = SimWorld("clutter", 0)
    nav = Navigator(load_profile().robot)
    nav.observe(sim.camera())
    tumbler = region_at(nav, 70.0, 60.0)
    # (0, 0) of the tumbler: sonar at its +x face, the base 11 in further, centred 1.85 +
    # 11 = 12.85 in from the tumbler, 7.65 in from the bottle's centre: within the 9 in
    # base radius of the bottle (1.35 in) and no 1.5 in shift escapes it
    cost = nav.position_cost(here(sim), tumbler, 0.0, 0.0)
    assert not cost.possible and cost.reason == "goal in an obstacle"


@pytest.mark.slow
def test_no_position_priced_finite_among_close_objects_is_a_collision() -> None:
    sim = SimWorld("clutter", 0)
    nav = Navigator(load_profile().robot)
    nav.observe(sim.camera())
    radius = load_profile().robot.geometry.base_radius_in
    driven = blocked = 0
    for x, y in CLOSE:
        target = region_at(nav, x, y)
        for orientation in range(0, 360, 30):
            for distance in (0.0, 6.0):
                goal = nav.pose_for(target, distance, float(orientation))
                cost = nav.move_cost(here(sim), goal)
                if sim.physics.overlaps_disc((goal.x_in, goal.y_in), radius):
                    assert not cost.possible  # a base on an object is never priced
                if not cost.possible:
                    blocked += 1
                    continue
                plan = nav.plan(here(sim), goal)
                assert plan.found, (x, y, orientation, distance)
                moved = sim.move([DriverPose(w.x_in, w.y_in, w.heading_deg) for w in plan.path], face=target.centroid)
                assert not moved.collided, (x, y, orientation, distance)
                driven += 1
    assert sim.contacts == 0
    assert driven >= 30 and blocked >= 10  # both kinds really met
