"""Calibration from the marker board: the lens and the floor mapping recovered from one
realistic image, to a fraction of an inch over the whole room; the file round trip;
one-line errors for bad files and for an image without the board."""

from __future__ import annotations

import json
import math
from pathlib import Path

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hero_driver.sim import render_realistic as rr
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.render_board import board_path
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import load_world
from camera_model.board import load_board
from planner.calibration import Calibration, calibrate, load_calibration, save_calibration

BOARD = load_board(board_path("lab"))


@pytest.fixture(scope="module")
def shot() -> tuple[SimWorld, np.ndarray]:
    sim = SimWorld(load_world("lab", profile_and_catalogue()[1]), 0, noise=NoiseConfig.off())
    return sim, sim.render("realistic").pixels


def true_raw_pixels(sim: SimWorld, points: np.ndarray) -> np.ndarray:
    """Where the simulated camera puts floor points (its mount, then its lens)."""
    geo = rr.Geometry.for_room(sim.spec)
    k, d = rr.lens_model(geo.width_px, geo.height_px)
    ideal = geo.project(points)
    rays = np.column_stack([ideal, np.ones(len(ideal))]) @ np.linalg.inv(k).T
    raw, _ = cv2.projectPoints(rays, np.zeros(3), np.zeros(3), k, d)
    return raw.reshape(-1, 2)


def test_the_room_is_mapped_to_a_fraction_of_an_inch(shot) -> None:
    sim, pixels = shot
    calibration = calibrate(pixels, BOARD)
    assert calibration.markers_seen == 9
    assert calibration.error_in < 0.35  # corners are found to ~1/3 pixel, a pixel is ~0.5 in
    floor = np.array([[x, y] for x in range(0, 241, 20) for y in range(0, 181, 20)], dtype=float)
    raw = true_raw_pixels(sim, floor)
    error = np.hypot(*(calibration.to_floor(raw[:, 0], raw[:, 1]) - floor).T)
    assert float(error.mean()) < 0.25 and float(error.max()) < 0.8  # the far corners lie outside the board
    # Without calibration the nominal mapping is inches off at the corners.
    nominal = np.column_stack([-6.0 + (raw[:, 0] + 0.5) * 0.5, 186.0 - (raw[:, 1] + 0.5) * 0.5])
    assert float(np.hypot(*(nominal - floor).T).max()) > 5.0


def test_the_lens_distortion_is_recovered(shot) -> None:
    """k1 is fitted at the fixed focal length f' = image width; the same pixel mapping
    at the true f = 0.9 width needs k1' = k1 (f'/f)^2 = -0.10 / 0.81 = -0.123."""
    _, pixels = shot
    calibration = calibrate(pixels, BOARD)
    assert calibration.distortion[0] == pytest.approx(-0.10 / 0.81, rel=0.15)


def test_rectified_floor_follows_the_documented_mapping(shot) -> None:
    """A marker in the rectified image sits where x = ox + (col + 0.5) ipp,
    y = oy - (row + 0.5) ipp puts it."""
    _, pixels = shot
    calibration = calibrate(pixels, BOARD)
    flat = calibration.rectify(pixels)
    big = cv2.resize(flat.pixels, None, fx=2, fy=2, interpolation=cv2.INTER_CUBIC)
    corners, ids, _ = cv2.aruco.ArucoDetector(
        cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_4X4_50), cv2.aruco.DetectorParameters()).detectMarkers(big)
    assert ids is not None and len(ids) >= 6
    for c, i in zip(corners, ids.ravel()):
        col, row = (c.reshape(4, 2).mean(axis=0) + 0.5) / 2 - 0.5
        x, y = flat.to_world(np.array([row]), np.array([col]))[0]
        marker = next(m for m in BOARD.markers if m.marker_id == int(i))
        assert math.hypot(x - marker.x_in, y - marker.y_in) < 0.6


def test_the_file_round_trips(shot, tmp_path: Path) -> None:
    _, pixels = shot
    calibration = calibrate(pixels, BOARD)
    save_calibration(calibration, tmp_path / "cam.json")
    again = load_calibration(tmp_path / "cam.json")
    np.testing.assert_allclose(again.homography, calibration.homography)
    np.testing.assert_allclose(again.distortion, calibration.distortion)
    assert again.floor_size == calibration.floor_size and again.error_in == calibration.error_in
    np.testing.assert_array_equal(again.rectify(pixels).pixels, calibration.rectify(pixels).pixels)


def test_an_image_without_the_board_is_one_clear_error() -> None:
    with pytest.raises(ValueError, match="shows 0 of the board's markers, at least 4"):
        calibrate(np.full((300, 400), 90, np.uint8), BOARD)


@pytest.mark.parametrize("change, message", [
    (lambda d: d.pop("homography"), "homography: expected 3x3 finite numbers"),
    (lambda d: d.update(distortion=[0.1, "x", 0, 0, 0]), "distortion: expected 5 finite numbers"),
    (lambda d: d["floor"].update(inches_per_pixel=0), "floor.inches_per_pixel: must be positive"),
    (lambda d: d.update(image_size=[504]), r"image_size: expected \[width, height\]"),
    (lambda d: d.update(format=9), "format: expected a calibration file of format 1"),
])
def test_a_bad_calibration_file_names_its_field(shot, tmp_path: Path, change, message) -> None:
    _, pixels = shot
    save_calibration(calibrate(pixels, BOARD), tmp_path / "cam.json")
    data = json.loads((tmp_path / "cam.json").read_text())
    change(data)
    (tmp_path / "cam.json").write_text(json.dumps(data))
    with pytest.raises(ValueError, match=f"cam.json: {message}"):
        load_calibration(tmp_path / "cam.json")


def test_unreadable_files_are_one_line_errors(tmp_path: Path) -> None:
    (tmp_path / "junk.json").write_text("{nope")
    with pytest.raises(ValueError, match="junk.json: cannot read the calibration"):
        load_calibration(tmp_path / "junk.json")
    (tmp_path / "board.json").write_text('{"dictionary": "DICT_4X4_50", "marker_in": 12, "markers": [{"id": 1.5}]}')
    with pytest.raises(ValueError, match=r"board.json: markers\[0\].id: expected an integer"):
        load_board(tmp_path / "board.json")



@pytest.fixture(scope="module")
def lab_calibration(shot) -> Calibration:
    return calibrate(shot[1], BOARD)


@settings(max_examples=40, deadline=None)
@given(col=st.integers(0, 300), row=st.integers(0, 230))
def test_rectifying_and_mapping_to_the_floor_agree(shot, lab_calibration: Calibration, col: int, row: int) -> None:
    """The raw pixel a rectified pixel is sampled from maps back to that pixel's
    centre on the floor: rectify and to_floor are one mapping."""
    map_x, map_y = lab_calibration._maps
    x, y = lab_calibration.rectify(shot[1]).to_world(np.array([row]), np.array([col]))[0]
    back = lab_calibration.to_floor(np.array([map_x[row, col]]), np.array([map_y[row, col]]))[0]
    assert math.hypot(back[0] - x, back[1] - y) < 0.01
