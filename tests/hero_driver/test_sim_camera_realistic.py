"""The realistic camera preset: no grey bands, the floor lit unevenly and textured the
same way every time, the lab's markers printed where its board file says, seen through
a lens whose distortion puts the nominal mapping inches off."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from camera_model.board import load_board
from hero_driver.interface import Pose
from hero_driver.sim import render_realistic as rr
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.render_board import aruco_dictionary, board_for
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import load_world


def lab(seed: int = 0) -> SimWorld:
    return SimWorld(load_world("lab", profile_and_catalogue()[1]), seed, noise=NoiseConfig.off())


def raw_pixel(spec_world: SimWorld, x: float, y: float) -> tuple[float, float]:
    """Where the simulated camera puts a floor point: mount homography, then the lens."""
    geo = rr.Geometry.for_room(spec_world.spec)
    k, d = rr.lens_model(geo.width_px, geo.height_px)
    ideal = geo.project([(x, y)])
    ray = np.array([[ideal[0, 0], ideal[0, 1], 1.0]]) @ np.linalg.inv(k).T
    raw, _ = cv2.projectPoints(ray, np.zeros(3), np.zeros(3), k, d)
    return float(raw[0, 0, 0]), float(raw[0, 0, 1])


def test_the_image_has_no_bands_and_says_nothing_of_its_lens() -> None:
    image = lab().render("realistic")
    assert image.pixels.dtype == np.uint8
    assert len(np.unique(image.pixels)) > 100
    assert image.camera_matrix is None and image.fisheye is None
    assert image.inches_per_pixel == rr.INCHES_PER_PIXEL and image.meta["camera"] == "realistic"


def test_every_marker_of_the_lab_board_is_printed_where_the_board_file_says() -> None:
    sim = lab()
    image = sim.render("realistic")
    board = board_for("lab")
    assert board is not None and len(board.markers) == 9
    detector = cv2.aruco.ArucoDetector(aruco_dictionary(board), cv2.aruco.DetectorParameters())
    corners, ids, _ = detector.detectMarkers(image.pixels)
    found = {int(i): c.reshape(4, 2).mean(axis=0) for c, i in zip(corners, ids.ravel())}
    assert sorted(found) == list(range(9))
    for marker in board.markers:
        col, row = raw_pixel(sim, marker.x_in, marker.y_in)
        # within half a pixel (0.25 in) of where the camera model puts the centre
        assert math.hypot(found[marker.marker_id][0] - col, found[marker.marker_id][1] - row) < 0.5


def test_the_nominal_mapping_is_inches_off_at_the_corners_so_calibration_is_needed() -> None:
    sim = lab()
    image = sim.render("realistic")
    col, row = raw_pixel(sim, 230.0, 10.0)
    x = image.origin_x_in + (col + 0.5) * image.inches_per_pixel
    y = image.origin_y_in - (row + 0.5) * image.inches_per_pixel
    assert math.hypot(x - 230.0, y - 10.0) > 3.0
    col, row = raw_pixel(sim, 120.0, 90.0)  # the middle barely moves
    x = image.origin_x_in + (col + 0.5) * image.inches_per_pixel
    y = image.origin_y_in - (row + 0.5) * image.inches_per_pixel
    assert math.hypot(x - 120.0, y - 90.0) < 1.5


def test_the_light_falls_off_across_the_room_and_objects_are_lighter_than_the_floor() -> None:
    sim = lab()
    sim.pose = Pose(200.0, 40.0, 0.0)
    image = sim.render("realistic").pixels.astype(float)

    def around(x: float, y: float) -> float:
        col, row = raw_pixel(sim, x, y)
        return float(np.median(image[round(row) - 3:round(row) + 4, round(col) - 3:round(col) + 4]))

    # light at (x, y) = LIGHT_MIN + LIGHT_SPAN (0.7 x/240 + 0.3 (1 - y/180)), times vignetting
    dim, bright = around(40.0, 140.0), around(180.0, 80.0)
    expected = (0.6 + 0.35 * (0.7 * 180 / 240 + 0.3 * (1 - 80 / 180))) / (0.6 + 0.35 * (0.7 * 40 / 240 + 0.3 * (1 - 140 / 180)))
    assert bright / dim == pytest.approx(expected, rel=0.15)
    box = around(185.0, 100.0)  # closed-box-10x10x10: albedo 0.80 against the floor's 0.42
    floor = around(160.0, 100.0)
    assert box / floor == pytest.approx(0.80 / 0.42, rel=0.12)
    assert around(200.0, 40.0) / around(200.0, 60.0) < 0.5  # the robot is painted dark


def test_the_floor_looks_the_same_every_time_but_the_noise_does_not() -> None:
    first = lab(seed=1).render("realistic").pixels.astype(float)
    second = lab(seed=2).render("realistic").pixels.astype(float)
    difference = first - second
    # two independent draws of sigma^2 = 2^2 + 0.04 * level (level ~ 60..110 on the floor)
    assert 2.5 < float(np.std(difference)) < 4.5
    texture = first - cv2.GaussianBlur(first, (0, 0), 8)
    texture_again = second - cv2.GaussianBlur(second, (0, 0), 8)
    assert float(np.corrcoef(texture.ravel(), texture_again.ravel())[0, 1]) > 0.7


def test_an_unknown_preset_is_one_clear_error() -> None:
    with pytest.raises(ValueError, match="camera preset 'fancy': expected one of simple, realistic"):
        lab().render("fancy")


def test_a_bad_board_file_names_the_file_and_field(tmp_path) -> None:
    bad = tmp_path / "b.json"
    bad.write_text('{"dictionary": "DICT_NOPE", "marker_in": 12, "markers": []}')
    with pytest.raises(ValueError, match=r"b\.json: dictionary"):
        load_board(bad)
