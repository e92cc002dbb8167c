"""The overhead camera: intensity bands, object pixels where the objects are, pixel
noise within ±12, and a fish-eye image that OpenCV undistorts back."""

from __future__ import annotations

import dataclasses
import math

import cv2
import numpy as np
import pytest

from camera_model.image import CameraImage
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.world import SimWorld
from tests.hero_driver.test_sim_support import lone


def world_of(image: CameraImage, row: float, col: float) -> tuple[float, float]:
    return (image.origin_x_in + (col + 0.5) * image.inches_per_pixel,
            image.origin_y_in - (row + 0.5) * image.inches_per_pixel)


def regions(pixels: np.ndarray, value: int) -> list[tuple[int, float, float]]:
    """(pixel count, row, col) of each connected region of one intensity."""
    n, _, stats, centroids = cv2.connectedComponentsWithStats((pixels == value).astype(np.uint8))
    return [(int(stats[i, 4]), float(centroids[i, 1]), float(centroids[i, 0])) for i in range(1, n)]


@pytest.mark.parametrize("entry, yaw, area, perimeter", [
    ("closed-box-10x10x10/upright", 0.0, 100.0, 40.0),
    ("closed-box-11x9x12/upright", 37.0, 99.0, 40.0),
    ("tumbler-32oz/upright", 0.0, math.pi * 4.0, math.pi * 4.0),
    ("tennis-can/lying", 120.0, 8.3 * 2.9, 22.4),
])
def test_an_object_appears_where_it_is_with_its_area(entry: str, yaw: float, area: float, perimeter: float) -> None:
    sim = lone(entry, 40.0, 90.0, yaw_deg=yaw)
    image = sim.camera()
    assert image.inches_per_pixel == 0.8 and image.pixels.dtype == np.uint8
    assert set(np.unique(image.pixels)) == {30, 110, 170, 220, 250}
    [(count, row, col)] = regions(image.pixels, 220)
    expected = area / 0.64
    assert abs(count - expected) <= 0.5 * perimeter / 0.8 + 2
    x, y = world_of(image, row, col)
    assert math.hypot(x - 200.0, y - 200.0) < 0.8


def test_robot_base_and_heading_marker() -> None:
    sim = SimWorld("lab", noise=NoiseConfig.off())
    image = sim.camera()
    [(marker, mr, mc)] = regions(image.pixels, 250)
    [(base, br, bc)] = regions(image.pixels, 170)
    assert abs(base + marker - math.pi * 81 / 0.64) < 15
    mx, my = world_of(image, mr, mc)
    assert mx == pytest.approx(30.0 + 6.0, abs=0.8) and my == pytest.approx(30.0, abs=0.8)
    assert image.pixels[0, 0] == 110 and image.pixels[image.pixels.shape[0] // 2, 20] == 30


def test_lab_objects_are_all_visible() -> None:
    sim = SimWorld("lab", noise=NoiseConfig.off())
    found = regions(sim.camera().pixels, 220)
    assert len(found) == len(sim.truth())


def test_pixel_noise_is_bounded_and_seeded() -> None:
    clean = SimWorld("lab", noise=NoiseConfig.off()).camera().pixels.astype(int)
    noisy_cfg = dataclasses.replace(NoiseConfig.off(), pixel_sigma=6.0)
    noisy = SimWorld("lab", 5, noise=noisy_cfg).camera().pixels.astype(int)
    assert np.abs(noisy - clean).max() <= 12 and np.abs(noisy - clean).mean() > 1
    assert np.array_equal(noisy, SimWorld("lab", 5, noise=noisy_cfg).camera().pixels)


def test_fisheye_image_undistorts_back() -> None:
    clean = SimWorld("lab", noise=NoiseConfig.off()).camera()
    bent = SimWorld("lab", noise=dataclasses.replace(NoiseConfig.off(), fisheye=True)).camera()
    assert bent.camera_matrix is not None and bent.fisheye is not None
    assert clean.camera_matrix is None and clean.fisheye is None
    assert not np.array_equal(bent.pixels, clean.pixels)
    back = cv2.fisheye.undistortImage(bent.pixels, bent.camera_matrix, np.asarray(bent.fisheye),
                                      Knew=bent.camera_matrix)
    assert np.mean(back == clean.pixels) > 0.95
    for _, row, col in regions(clean.pixels, 220):
        window = back[int(row) - 2:int(row) + 3, int(col) - 2:int(col) + 3]
        assert (np.abs(window.astype(int) - 220) < 40).any()
