"""Training probes: one object alone in a room, the robot placed at a learner position
``(distance, orientation)`` per docs/conventions.md, one procedure applied.

This is how training measurements are recorded from the simulator and how tests check
which grasp works from which approach, without the planner or a move in between.
"""

from __future__ import annotations

import math

from hero_driver.interface import Pose, SenseResult
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld, normalise_deg
from hero_driver.sim.worldfile import one_object_world
from robot_profile import RobotProfile


def approach_pose(sim: SimWorld, index: int, distance_in: float, orientation_deg: float) -> Pose:
    """The base pose that puts the sonar at ``(distance, orientation)`` from object
    ``index``, computed on the object's true footprint as the planner does on vision's
    polygon (docs/conventions.md).

    The reference axis is the footprint's major axis (the catalogue's local x, i.e. the
    object's yaw); a round footprint uses world +x, as vision does.
    """
    obj = sim.physics.objects[index]
    alpha = 0.0 if obj.entry.footprint.shape == "circle" else obj.yaw_deg
    a = math.radians(alpha + orientation_deg)
    ux, uy = math.cos(a), math.sin(a)
    far = 1000.0
    hit = obj.shape.segment_query((obj.x_in + far * ux, obj.y_in + far * uy), (obj.x_in, obj.y_in), 0.0)
    r_face = far * (1.0 - float(hit.alpha))
    reach = r_face + distance_in + sim.profile.robot.geometry.sensor_offset_in
    return Pose(obj.x_in + reach * ux, obj.y_in + reach * uy, normalise_deg(alpha + orientation_deg + 180.0))


def probe_world(entry_id: str, seed: int, noise: bool, profile: RobotProfile | None) -> SimWorld:
    """A world holding ``entry_id`` alone at the origin, yaw 0, with noise on or off."""
    loaded, catalogue = profile_and_catalogue(profile)
    return SimWorld(one_object_world(entry_id, catalogue), seed, profile=loaded,
                    noise=NoiseConfig() if noise else NoiseConfig.off())


def probe(entry_id: str, procedure: str, distance_in: float, orientation_deg: float,
          seed: int = 0, noise: bool = False, profile: RobotProfile | None = None) -> SenseResult:
    """Apply ``procedure`` to ``entry_id`` seen from ``(distance, orientation)``;
    raises DriverError as the driver would (out of range, unknown procedure)."""
    sim = probe_world(entry_id, seed, noise, profile)
    sim.pose = approach_pose(sim, 0, distance_in, orientation_deg)
    return sim.sense(procedure)


def grasp_probe(entry_id: str, grasp: str, orientation_deg: float, seed: int = 0,
                profile: RobotProfile | None = None) -> bool:
    """Whether ``grasp`` picks ``entry_id`` up when approached from ``orientation`` at
    the near end of the grasp's range (6 in for the HERO's grasps)."""
    sim = probe_world(entry_id, seed, False, profile)
    spec = sim.profile.grasping_procedure(grasp)
    distance = spec.range_in[0] if spec is not None else 0.0  # unknown: grasp() refuses it
    sim.pose = approach_pose(sim, 0, distance, orientation_deg)
    return sim.grasp(grasp).success
