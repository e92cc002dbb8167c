"""The empty floor made from one image (planner/segmentation.py) must not invent
objects: what it paints out (objects, and never a mere speck of noise) is filled from
the floor around it, not from a wall beside it. Looking at the very image a camera was
calibrated on then finds exactly the objects on it."""

from __future__ import annotations

import numpy as np
import pytest

from camera_model.board import load_board
from camera_model.image import CameraImage
from hero_driver.sim.render_board import board_path
from hero_driver.sim_driver import SimulatedHero
from planner.segmentation import calibrated_camera, empty_floor, segment
from planner.vision import look

FLOOR, WALL, OBJECT = 100, 30, 160


def floor_with_wall() -> np.ndarray:
    """60x60 pixels of floor with a wall along the top, a little sensor noise."""
    pixels = np.full((60, 60), FLOOR, np.float64)
    pixels[:10] = WALL
    pixels += np.random.default_rng(0).normal(0.0, 2.0, pixels.shape)
    return np.clip(np.round(pixels), 0, 255).astype(np.uint8)


def components(mask: np.ndarray) -> int:
    import cv2

    return cv2.connectedComponents(mask.astype(np.uint8))[0] - 1


def test_an_object_against_a_wall_is_filled_with_floor_not_wall() -> None:
    pixels = floor_with_wall()
    pixels[10:14, 30:34] = OBJECT  # touching the wall
    floor = empty_floor(CameraImage(pixels, 0.8, 0.0, 48.0))
    under = floor.level[10:14, 30:34]
    assert np.all(np.abs(under - FLOOR) < 0.1 * FLOOR)  # filled from the wall it would read ~50


def test_a_speck_beside_a_wall_is_not_painted_out_so_no_object_appears() -> None:
    pixels = floor_with_wall()
    pixels[10, 20] = 125  # one pixel 25 % over the floor: noise or texture, not an object
    pixels[30:34, 40:44] = OBJECT
    image = CameraImage(pixels, 0.8, 0.0, 48.0)
    masks = segment(image, empty_floor(image))
    assert components(masks.objects) == 1 and masks.objects[30:34, 40:44].all()


# Lab images on which, calibrated on themselves, vision found 8 to 10 regions before
# the fix (specks by the walls painted out and filled from the wall); 7 objects stand there.
@pytest.mark.parametrize(("seed", "frame"), [(0, 1), (1, 0), (3, 1), (5, 1)])
def test_the_calibration_image_itself_shows_just_the_lab_objects(seed: int, frame: int) -> None:
    hero = SimulatedHero("r1", world="lab", seed=seed, camera="realistic")
    image = [hero.camera().result() for _ in range(frame + 1)][-1]
    camera = calibrated_camera(image.pixels, load_board(board_path("lab")))
    scene = look(image, camera)
    assert len(scene.regions) == 7
