"""The simulator's camera preset chosen once, at the world (docs/simulator.md, "The
overhead camera"), and a world's marker board named in its world file."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from hero_driver.cli import CAMERA_PRESETS
from hero_driver.sim.camera import PRESETS
from hero_driver.sim.render_board import board_for, board_path
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import WORLDS_DIR, load_world
from hero_driver.sim_driver import SimulatedHero


@pytest.mark.parametrize("preset", PRESETS)
def test_the_world_camera_draws_its_preset(preset: str) -> None:
    sim, twin = SimWorld("lab", 3, camera=preset), SimWorld("lab", 3)
    image = sim.camera()
    assert np.array_equal(image.pixels, twin.render(preset).pixels)  # the same draws, the same image
    assert image.meta.get("camera", "simple") == preset


def test_the_default_is_the_band_image() -> None:
    assert SimWorld("lab").camera().pixels.shape == (240, 315)  # 0.8 in pixels over the lab and its walls


def test_the_driver_passes_the_preset_through_and_keeps_it_over_reset() -> None:
    hero = SimulatedHero("r1", world="lab", camera="realistic")
    assert hero.camera().result().pixels.shape == (384, 504)
    hero.reset(seed=5).result()
    assert hero.camera().result().meta["camera"] == "realistic"


def test_an_unknown_preset_is_one_line() -> None:
    with pytest.raises(ValueError, match=r"^camera preset 'fisheye': expected one of simple, realistic, realistic-lamp, "
                                         r"realistic-shadow, realistic-floor, realistic-exposure$"):
        SimWorld("lab", camera="fisheye")


def test_the_driver_command_offers_the_simulator_presets() -> None:
    assert CAMERA_PRESETS == PRESETS


def test_the_lab_names_its_board_beside_it() -> None:
    spec = load_world("lab", profile_and_catalogue()[1])
    assert spec.board == WORLDS_DIR / "lab-board.json" == board_path("lab")
    board = board_for(spec)
    assert board is not None and len(board.markers) == 9


def write_world(folder: Path, **extra: object) -> Path:
    data = {"room": {"width_in": 60, "depth_in": 60}, "robot": {"x_in": 30, "y_in": 30, "heading_deg": 0}, **extra}
    path = folder / "room.json"
    path.write_text(json.dumps(data))
    return path


def test_a_board_is_found_relative_to_its_world_file(tmp_path: Path) -> None:
    (tmp_path / "boards").mkdir()
    board = tmp_path / "boards" / "mine.json"
    board.write_text(json.dumps({"dictionary": "DICT_4X4_50", "marker_in": 6,
                                 "markers": [{"id": 3, "x_in": 10, "y_in": 10}]}))
    spec = load_world(write_world(tmp_path, board="boards/mine.json"), profile_and_catalogue()[1])
    assert spec.board == tmp_path / "boards" / "mine.json"
    printed = board_for(spec)
    assert printed is not None and [(m.marker_id, m.x_in, m.y_in) for m in printed.markers] == [(3, 10.0, 10.0)]
    # the realistic camera prints it: the same scene without the board differs only on
    # the marker's paper (8 in square: 256 pixels of 0.5 in), around (10, 10) in
    bare, printed = (SimWorld(s, 0, camera="realistic").camera() for s in (dataclasses.replace(spec, board=None), spec))
    rows, cols = np.nonzero(np.abs(printed.pixels.astype(int) - bare.pixels.astype(int)) > 20)
    assert 150 < len(rows) <= 256
    x = printed.origin_x_in + (cols.mean() + 0.5) * printed.inches_per_pixel
    y = printed.origin_y_in - (rows.mean() + 0.5) * printed.inches_per_pixel
    assert abs(x - 10) < 2 and abs(y - 10) < 2  # nominal mapping: the lens moves it a little


def test_a_world_without_a_board_has_none(tmp_path: Path) -> None:
    spec = load_world(write_world(tmp_path), profile_and_catalogue()[1])
    assert spec.board is None and board_for(spec) is None
    with pytest.raises(ValueError, match=r"room\.json: names no marker board \(field 'board'"):
        board_path(spec.source)


@pytest.mark.parametrize(("board", "problem"), [("missing.json", "names .*missing.json, which is not a file \\(nor a shipped board\\)"),
                                                 (7, "must be the name of a marker board file"),
                                                 ("", "must be the name of a marker board file")])
def test_a_bad_board_field_is_one_line(tmp_path: Path, board: object, problem: str) -> None:
    with pytest.raises(ValueError, match=rf"room\.json: world: field 'board' {problem}$"):
        load_world(write_world(tmp_path, board=board), profile_and_catalogue()[1])
