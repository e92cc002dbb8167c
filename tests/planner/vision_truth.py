"""Vision against the simulator's truth, per camera preset (the test of
tests/planner/test_vision_realistic.py and bench/bench_vision.py both use it).

The lab's objects are moved to several poses (each shifted a few inches and turned),
the robot parked somewhere else each time (once right at an object, as after a failed
grasp); every pose is photographed with a preset and looked at. For each object:
how far the region's centroid is from the object's centre, how far its orientation is
from the object's major axis (modulo the footprint's symmetry: 180° for a rectangle,
90° for a square, none for a circle), and its pixel count (the side-effect check
compares counts of one object before and after a grasp).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from camera_model.board import load_board
from camera_model.image import CameraImage
from hero_driver.interface import Pose
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.probe import approach_pose
from hero_driver.sim.render_board import board_path
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import Placement, load_world
from planner.segmentation import Camera, calibrated_camera
from planner.vision import look

MATCH_IN = 6.0  # a region this close to an object is that object's
ROBOT_PARKED = (Pose(30.0, 30.0, 0.0), Pose(150.0, 75.0, 200.0), Pose(80.0, 150.0, 300.0))
# The simple preset's own pixel noise; no camera yaw error (vision's error alone).
NOISE = dataclasses.replace(NoiseConfig.off(), pixel_sigma=4.0)


@dataclass(frozen=True)
class Seen:
    """One object at one pose as vision saw it (``found`` False: no region matched)."""

    entry_id: str
    pose: int
    found: bool
    location_error_in: float = math.nan
    orientation_error_deg: float | None = None
    pixel_count: int = 0


def lab_at(pose: int, seed: int = 0, noise: NoiseConfig = NOISE) -> SimWorld:
    """The lab with every object shifted and turned for pose number ``pose`` (pose 0
    is the lab as shipped, the robot at its start); ``noise`` the simulator's (its
    fish-eye switch gives band images through a lens)."""
    spec = load_world("lab", profile_and_catalogue()[1])
    rng = np.random.default_rng(1000 + pose)
    placements = tuple(
        p if pose == 0 else Placement(p.entry_id, p.x_in + float(rng.uniform(-6, 6)),
                                      p.y_in + float(rng.uniform(-6, 6)), p.yaw_deg + 37.0 * pose)
        for p in spec.objects)
    sim = SimWorld(dataclasses.replace(spec, objects=placements), seed, noise=noise)
    if pose == len(ROBOT_PARKED):  # right at the magazine box, as after a failed grasp
        sim.pose = approach_pose(sim, 4, 2.0, 90.0)
    else:
        sim.pose = ROBOT_PARKED[pose % len(ROBOT_PARKED)]
    return sim


def overhead(sim: SimWorld, preset: str) -> CameraImage:
    return sim.render(preset)


def lab_camera() -> Camera:
    """Calibrated on the shipped lab (objects and robot on the floor, painted out of
    the empty floor): the harder case of no cleared floor."""
    return calibrated_camera(overhead(lab_at(0), "realistic").pixels, load_board(board_path("lab")))


def seen(sim: SimWorld, preset: str, pose: int, camera: Camera | None) -> list[Seen]:
    """Each object of ``sim`` as vision sees it through ``preset``."""
    scene = look(overhead(sim, preset), camera if preset == "realistic" else None)
    out = []
    for obj in sim.physics.objects:
        fp = obj.entry.footprint
        near = [r for r in scene.regions if math.hypot(r.centroid[0] - obj.x_in, r.centroid[1] - obj.y_in) < MATCH_IN]
        if not near:
            out.append(Seen(obj.entry.id, pose, False))
            continue
        region = min(near, key=lambda r: math.hypot(r.centroid[0] - obj.x_in, r.centroid[1] - obj.y_in))
        orientation = None
        if fp.shape == "rect" and region.orientation_deg is not None:
            period = 90.0 if math.isclose(fp.length_in, fp.width_in) else 180.0
            off = (region.orientation_deg - obj.yaw_deg) % period
            orientation = min(off, period - off)
        out.append(Seen(obj.entry.id, pose, True,
                        math.hypot(region.centroid[0] - obj.x_in, region.centroid[1] - obj.y_in),
                        orientation, region.pixel_count))
    return out


def measure(preset: str, poses: int, camera: Camera | None = None, noise: NoiseConfig = NOISE) -> list[Seen]:
    """Every lab object at poses 0..poses-1 through ``preset``."""
    if preset == "realistic" and camera is None:
        camera = lab_camera()
    return [s for pose in range(poses) for s in seen(lab_at(pose, noise=noise), preset, pose, camera)]


def pixel_spread(results: list[Seen]) -> dict[str, float]:
    """Per object, the largest relative change of its pixel count between two poses
    (what the side-effect check would read as "changed" above 0.25)."""
    counts: dict[str, list[int]] = {}
    for s in results:
        if s.found:
            counts.setdefault(s.entry_id, []).append(s.pixel_count)
    return {k: (max(v) - min(v)) / min(v) for k, v in counts.items()}

