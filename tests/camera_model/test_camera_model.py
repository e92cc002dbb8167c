"""The camera's published model (camera_model): the bands, the floor grid and the
board file, held by one leaf that both ends of the protocol read."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from camera_model import bands
from camera_model.board import DICTIONARY_BITS, load_board
from camera_model.floor_grid import FloorGrid

REPO = Path(__file__).resolve().parents[2]
LEVELS = (bands.FLOOR, bands.WALL, bands.BASE, bands.OBJECT, bands.MARKER)


def test_the_leaf_imports_nothing_of_ours_nor_opencv() -> None:
    code = ("import sys, camera_model.bands, camera_model.board, camera_model.fisheye, camera_model.floor_grid, "
            "camera_model.image\n"
            "print(sorted({m.split('.')[0] for m in sys.modules}))")
    loaded = subprocess.run([sys.executable, "-c", code], cwd=REPO, capture_output=True, text=True, check=True)
    names = set(json.loads(loaded.stdout.replace("'", '"')))
    assert not names & {"cv2", "planner", "hero_driver", "executive", "behaviours", "learner", "zenoh"}


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), noise=st.integers(0, bands.PIXEL_NOISE_MAX),
       shares=st.lists(st.floats(0.0, 1.0), min_size=5, max_size=5).filter(lambda s: sum(s) > 0))
def test_any_band_image_within_the_protocols_noise_looks_like_bands(seed: int, noise: int,
                                                                   shares: list[float]) -> None:
    rng = np.random.default_rng(seed)
    p = np.asarray(shares) / sum(shares)
    pixels = rng.choice(LEVELS, size=(60, 80), p=p) + rng.integers(-noise, noise + 1, size=(60, 80))
    assert bands.band_share(np.clip(pixels, 0, 255).astype(np.uint8)) == 1.0


def test_a_continuous_tone_image_does_not_look_like_bands() -> None:
    # a ramp over every grey level: within 12 of 0, 30, 110, 170, 220, 250 lie 13 + 4 x 25 + 18 = 131
    ramp = np.tile(np.arange(256, dtype=np.uint8), (10, 1))
    assert bands.band_share(ramp) == pytest.approx(131 / 256)
    assert not bands.looks_like_bands(ramp)


def test_the_realistic_preset_does_not_look_like_bands_and_the_simple_one_does() -> None:
    from hero_driver.sim_driver import SimulatedHero
    from hero_driver.sim.noise import NoiseConfig

    for camera, noise, expected in [("simple", "mild", True), ("simple", "harsh", True),
                                    ("realistic", "mild", False)]:
        driver = SimulatedHero(camera=camera, noise=NoiseConfig.preset(noise))
        assert bands.looks_like_bands(driver.camera().result().pixels) is expected, (camera, noise)
        driver.close()


def test_a_pixel_centre_is_where_the_protocol_page_says() -> None:
    grid = FloorGrid(0.8, -6.0, 186.0)  # the simulated lab's band image
    # pixel (0, 0)'s centre is half a pixel in from the top-left corner, rows counting down
    assert grid.to_world(0, 0).tolist() == [[-5.6, 185.6]]
    assert grid.to_world(np.array([10]), np.array([20])).tolist() == [[pytest.approx(10.4), pytest.approx(177.6)]]
    assert grid.to_pixel(10.4, 177.6) == (pytest.approx(10.0), pytest.approx(20.0))


@given(ipp=st.floats(0.05, 5.0), ox=st.floats(-500, 500), oy=st.floats(-500, 500),
       row=st.floats(-100, 1000), col=st.floats(-100, 1000))
def test_to_world_to_pixel_and_the_homography_agree(ipp: float, ox: float, oy: float, row: float,
                                                      col: float) -> None:
    grid = FloorGrid(ipp, ox, oy)
    (x, y), = grid.to_world(row, col)
    assert grid.to_pixel(x, y) == (pytest.approx(row, abs=1e-6), pytest.approx(col, abs=1e-6))
    c, r, w = grid.world_to_pixel() @ np.array([x, y, 1.0])
    assert (r / w, c / w) == (pytest.approx(row, abs=1e-6), pytest.approx(col, abs=1e-6))
    assert grid.finer(5).to_pixel(x, y) == (pytest.approx(5 * row + 2, abs=1e-5), pytest.approx(5 * col + 2, abs=1e-5))


def test_a_point_lies_in_the_pixel_the_protocol_page_says() -> None:
    """``col = floor((x - origin_x) / s)``, ``row = floor((origin_y - y) / s)``; the
    image's extent is its corners'."""
    grid = FloorGrid(0.8, -6.0, 186.0)
    # either side of the edge between columns 19 and 20 (x = 10) and rows 9 and 10 (y = 178)
    row, col = grid.to_cell(np.array([-6.0, 9.99, 10.01]), np.array([186.0, 178.01, 177.99]))
    assert np.floor(row).tolist() == [0, 9, 10] and np.floor(col).tolist() == [0, 19, 20]
    assert grid.to_cell(10.41, 177.59) == (pytest.approx(10.5125), pytest.approx(20.5125))
    assert grid.extent(240, 315) == (-6.0, pytest.approx(246.0), pytest.approx(-6.0), 186.0)


@pytest.mark.parametrize("ipp, ox", [(0.0, 0.0), (-1.0, 0.0), (math.nan, 0.0), (1.0, math.inf)])
def test_a_bad_mapping_is_refused(ipp: float, ox: float) -> None:
    with pytest.raises(ValueError):
        FloorGrid(ipp, ox, 0.0)


def test_the_dictionaries_are_opencvs_with_their_sizes() -> None:
    opencv = {name for name in dir(cv2.aruco) if name.startswith("DICT_")}
    assert set(DICTIONARY_BITS) == opencv
    for name, bits in DICTIONARY_BITS.items():
        assert cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, name)).markerSize == bits, name


def test_the_lab_board_reads_and_places_corners_top_edge_to_plus_y() -> None:
    board = load_board(REPO / "hero_driver" / "worlds" / "lab-board.json")
    assert (board.dictionary, board.marker_in, len(board.markers)) == ("DICT_4X4_50", 12.0, 9)
    first = board.markers[0]
    h = board.marker_in / 2
    assert board.corners(first.marker_id) == [(first.x_in - h, first.y_in + h), (first.x_in + h, first.y_in + h),
                                              (first.x_in + h, first.y_in - h), (first.x_in - h, first.y_in - h)]
    assert board.modules() == 6 and board.paper_in() == pytest.approx(12.0 * 8 / 6)


@pytest.mark.parametrize("text, message", [
    ("{nope", "cannot read the marker board"),
    ("[]", "a marker board is a JSON object"),
    ('{"dictionary": "DICT_NOPE", "marker_in": 12, "markers": [{"id": 0, "x_in": 0, "y_in": 0}]}', "dictionary: "),
    ('{"dictionary": "DICT_4X4_50", "marker_in": 0, "markers": [{"id": 0, "x_in": 0, "y_in": 0}]}',
     "marker_in: must be positive"),
    ('{"dictionary": "DICT_4X4_50", "marker_in": 12, "markers": []}', "markers: expected a non-empty list"),
    ('{"dictionary": "DICT_4X4_50", "marker_in": 12, "markers": [{"id": true, "x_in": 0, "y_in": 0}]}',
     r"markers\[0\].id: expected an integer"),
    ('{"dictionary": "DICT_4X4_50", "marker_in": 12, "markers": [{"id": 0, "x_in": "a", "y_in": 0}]}',
     r"markers\[0\].x_in: expected a finite number"),
    ('{"dictionary": "DICT_4X4_50", "marker_in": 12, "markers": [{"id": 0, "x_in": 0, "y_in": 0}, '
     '{"id": 0, "x_in": 5, "y_in": 0}]}', "markers: ids must be distinct"),
])
def test_a_bad_board_file_is_one_line_naming_the_file_and_field(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "board.json"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"board.json: {message}") as raised:
        load_board(path)
    assert "\n" not in str(raised.value)


@pytest.mark.parametrize("matrix, coefficients, size", [
    ([[252.0, 0, 157.0], [0, 252.0, 119.5], [0, 0, 1]], (0.05, 0.01, 0.0, 0.0), (315, 240)),  # the simulator's
    ([[300.0, 0, 200], [0, 310, 150], [0, 0, 1]], (0.1, -0.05, 0.01, -0.002), (400, 300)),
    ([[300.0, 2.5, 200], [0, 310, 150], [0, 0, 1]], (0.1, -0.05, 0.01, -0.002), (400, 300)),  # with skew
])
def test_the_fisheye_maps_are_opencvs(matrix: list[list[float]], coefficients: tuple[float, ...],
                                      size: tuple[int, int]) -> None:
    from camera_model.fisheye import undistortion_maps

    k = np.asarray(matrix)
    width, height = size
    expected = cv2.fisheye.initUndistortRectifyMap(k, np.asarray(coefficients).reshape(4, 1), np.eye(3), k,
                                                   (width, height), cv2.CV_32FC1)
    got = undistortion_maps(k, coefficients, height, width)
    # the same float32 maps, so nearest-neighbour sampling picks the same pixels
    assert np.array_equal(got[0], expected[0]) and np.array_equal(got[1], expected[1])
