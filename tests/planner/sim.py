"""Glue between the simulated HERO and the planner, as the executive will write it."""

from __future__ import annotations

from hero_driver.interface import Pose as DriverPose
from hero_driver.sim_driver import SimulatedHero
from planner import Navigator, PlanResult, Pose
from robot_profile import load_profile


def robot_pose(hero: SimulatedHero) -> Pose:
    pose = hero.state().pose
    return Pose(pose.x_in, pose.y_in, pose.heading_deg)


def drive(hero: SimulatedHero, plan: PlanResult, face: tuple[float, float]):
    """Follow a plan's waypoints, then face and centre on ``face``."""
    return hero.move([DriverPose(w.x_in, w.y_in, w.heading_deg) for w in plan.path], face=face).result()


def navigator() -> Navigator:
    return Navigator(load_profile().robot)
