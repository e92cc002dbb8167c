"""The overhead camera draws the movers ("the planner's map updated
from a new camera image"): a person or cart on the floor is a blob in the walls' band where
it stands, which vision maps as an obstacle and never takes for an object to grasp,
and a plan on a new image goes round it with no disc reported for it."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camera_model.bands import FLOOR, OBJECT, WALL
from camera_model.board import load_board
from hero_driver.sim.movers import MoverPreset, MoverTruth
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.render_board import board_path
from hero_driver.sim.world import SimWorld
from planner import Navigator, Pose
from planner.segmentation import calibrated_camera
from planner.vision import Scene, look
from tests.planner.test_navigator_avoid import _clearance

MOVERS = 2  # a person and a cart (the preset's shapes in turn)


def _lab(movers: int, camera: str = "simple", seed: int = 0) -> SimWorld:
    return SimWorld("lab", seed, noise=NoiseConfig.off(), camera=camera, movers=MoverPreset(movers))


def _clear_of_objects(sim: SimWorld) -> float:
    """The least distance from any object's centre to any mover's outline."""
    return min(math.hypot(o.x_in - m.x_in, o.y_in - m.y_in) - m.reach_in
               for m in sim.movers() for o in sim.physics.objects)


def _area_in2(sim: SimWorld, mover: MoverTruth) -> float:
    spec = sim.physics.movers.all[mover.index].spec
    return math.pi * spec.radius_in ** 2 if spec.shape == "disc" else spec.length_in * spec.width_in


def test_a_mover_is_a_wall_band_blob_where_it_stands() -> None:
    """Movers come from a random stream of their own, so the image with them differs
    from the image without only where they stand: one blob per mover, in the walls'
    band, centred on it and as large as its outline."""
    plain, busy = _lab(0), _lab(MOVERS)
    before, after = plain.camera(), busy.camera()
    changed = before.pixels != after.pixels
    assert set(np.unique(before.pixels[changed])) == {FLOOR} and set(np.unique(after.pixels[changed])) == {WALL}
    count, labels, stats, centroids = cv2.connectedComponentsWithStats(changed.astype(np.uint8), connectivity=8)
    assert count - 1 == MOVERS
    image, ipp = after, after.inches_per_pixel
    for mover in busy.movers():
        row, col = (round(v) for v in image.to_pixel(mover.x_in, mover.y_in))
        blob = labels[row, col]
        assert blob > 0, f"no blob under mover {mover.index}"
        (x, y), = image.to_world(np.array([centroids[blob][1]]), np.array([centroids[blob][0]]))
        assert math.hypot(x - mover.x_in, y - mover.y_in) < 0.5
        assert stats[blob, cv2.CC_STAT_AREA] * ipp ** 2 == pytest.approx(_area_in2(busy, mover), rel=0.05)


@settings(max_examples=12, deadline=None)
@given(count=st.integers(1, 4), seed=st.integers(0, 2 ** 16))
def test_movers_only_ever_add_wall_pixels_and_each_shows_at_its_centre(count: int, seed: int) -> None:
    """Whatever the floor: the movers change no pixel but to the walls' band (never an
    object's or the robot's), and the pixel under each mover's centre is a wall's, or
    an object's where one lies beneath it."""
    before, busy = _lab(0, seed=seed).camera(), _lab(count, seed=seed)
    after = busy.camera()
    assert set(np.unique(after.pixels[before.pixels != after.pixels])) <= {WALL}
    image = after
    for mover in busy.movers():
        row, col = (round(v) for v in image.to_pixel(mover.x_in, mover.y_in))
        assert after.pixels[row, col] in (WALL, OBJECT)


def test_vision_maps_a_mover_as_an_obstacle_and_finds_the_same_objects() -> None:
    plain, busy = look(_lab(0).camera()), look(_lab(MOVERS).camera())
    assert [r.centroid for r in busy.regions] == [r.centroid for r in plain.regions]
    for mover in _lab(MOVERS).movers():
        row, col = (round(v) for v in busy.image.to_pixel(mover.x_in, mover.y_in))
        assert busy.furniture[row, col] and not plain.furniture[row, col]
        assert not busy.objects[row, col]


def _realistic_scenes(seed: int) -> tuple[SimWorld, Scene, Scene]:
    """The lab with movers, and vision's scenes of it without and with them, read
    through a camera calibrated on the lab without movers (its empty floor)."""
    plain, busy = _lab(0, "realistic", seed), _lab(MOVERS, "realistic", seed)
    camera = calibrated_camera(plain.camera().pixels, load_board(board_path("lab")))
    return busy, look(plain.camera(), camera), look(busy.camera(), camera)


def _robot_gap(a: Scene, b: Scene) -> float:
    """How far apart the two scenes put the robot's centre (the sensor's noise
    differs between them by a fraction of an inch)."""
    assert a.robot is not None and b.robot is not None
    return math.hypot(a.robot.x_in - b.robot.x_in, a.robot.y_in - b.robot.y_in)


def test_the_realistic_camera_shows_movers_as_obstacles_not_objects() -> None:
    """Movers clear of the objects and furniture (seed 7) are new dark obstacles; no object region
    appears or goes, and the robot is still found where it stands."""
    busy, without, with_movers = _realistic_scenes(7)
    assert _clear_of_objects(busy) > 10.0
    assert len(with_movers.regions) == len(without.regions) and _robot_gap(with_movers, without) < 0.5
    for mover in busy.movers():
        row, col = (round(v) for v in with_movers.image.to_pixel(mover.x_in, mover.y_in))
        assert with_movers.furniture[row, col] and not without.furniture[row, col]
        assert all(math.dist(r.centroid, (mover.x_in, mover.y_in)) > mover.reach_in for r in with_movers.regions)


@pytest.mark.parametrize(("seed", "over_an_object"), [(0, True), (4, False), (5, False)])
def test_a_mover_over_something_light_is_not_taken_for_the_robot(seed: int, over_an_object: bool) -> None:
    """A mover is dark; over something light it is a dark region with a bright spot,
    as the robot is. Seed 0: the cart stands over the lying soda bottle (a box, not a
    disc); seed 4: the person half over a board marker's white paper (a disc, the spot
    too small and too far out for the robot's white disc); seed 5: the cart over
    another marker, larger than the robot. The robot is still found where it stands."""
    busy, without, with_movers = _realistic_scenes(seed)
    assert (_clear_of_objects(busy) < 0.0) == over_an_object
    assert _robot_gap(with_movers, without) < 0.5


def test_a_plan_on_a_new_image_goes_round_the_mover_with_no_disc_reported() -> None:
    """The crossing world's person walks the line x = 100 across the robot's way; once
    it stands on the robot's straight line, the map of a new image alone (no
    ``avoid`` disc, as after WaitForMover) keeps the base clear of it."""
    sim = SimWorld("crossing", 0, noise=NoiseConfig.off())
    sim.wait(78.0 / 12.0)  # from (100, 12) up to the robot's line y = 90 at 12 in/s
    person, = sim.movers()
    assert abs(person.y_in - 90.0) < 3.0
    nav = Navigator(sim.profile.robot)
    nav.observe(sim.camera())
    assert nav.avoided == () and not nav.vision_map.is_free(person.x_in, person.y_in)
    start, goal = Pose(30.0, 90.0, 0.0), Pose(170.0, 90.0, 0.0)
    around = nav.plan(start, goal)
    base = sim.profile.robot.geometry.base_radius_in
    assert around.found and _clearance(around.path, start, (person.x_in, person.y_in)) >= person.reach_in + base
