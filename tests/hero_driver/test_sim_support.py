"""Scene builders the simulator tests share (one object alone, the robot placed at a
learner position, no noise unless asked), and checks that the placement follows
docs/conventions.md, which every other test relies on."""

from __future__ import annotations

import math

import pytest

from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import approach_pose
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import one_object_world


def lone(entry_id: str, distance_in: float = 6.0, orientation_deg: float = 0.0, *, seed: int = 0,
         noise: NoiseConfig | None = None, yaw_deg: float = 0.0) -> SimWorld:
    sim = SimWorld(one_object_world(entry_id, profile_and_catalogue()[1], yaw_deg=yaw_deg), seed,
                   noise=noise if noise is not None else NoiseConfig.off())
    sim.pose = approach_pose(sim, 0, distance_in, orientation_deg)
    return sim


def object_pixels(sim: SimWorld) -> int:
    return int((sim.camera().pixels == 220).sum())


def test_approach_pose_follows_the_conventions() -> None:
    """sonar = c + (r_face + d) u, base = sonar + offset u, heading = alpha + theta + 180."""
    sim = lone("magazine-box-9x4x7/upright", 16.0, 90.0, yaw_deg=30.0)
    obj = sim.physics.objects[0]
    offset = sim.profile.robot.geometry.sensor_offset_in
    # theta = 90 from a 9x4 box's major axis: the face is the 9 in side, 2 in from c.
    u = (math.cos(math.radians(120.0)), math.sin(math.radians(120.0)))
    assert sim.pose.x_in == pytest.approx(obj.x_in + (2.0 + 16.0 + offset) * u[0])
    assert sim.pose.y_in == pytest.approx(obj.y_in + (2.0 + 16.0 + offset) * u[1])
    assert sim.pose.heading_deg == pytest.approx(300.0)
    sx, sy = sim.sonar_point()
    assert math.hypot(sx - obj.x_in, sy - obj.y_in) == pytest.approx(18.0)


def test_round_footprint_uses_world_x_as_reference() -> None:
    sim = lone("cup-8oz/upright", 24.0, 0.0, yaw_deg=50.0)
    obj = sim.physics.objects[0]
    assert sim.pose.y_in == pytest.approx(obj.y_in)
    assert sim.pose.x_in > obj.x_in and sim.pose.heading_deg == pytest.approx(180.0)
