"""``csl camera calibrate``: from a saved realistic image to a calibration file and its
empty floor, the reprojection error printed; one-line errors for bad input."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np
import pytest

from csl_cli.main import main
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.node import DriverNode
from planner.segmentation import load_camera
from planner.vision import look
from tests.planner.vision_truth import lab_at, overhead
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session


@pytest.fixture(scope="module")
def lab_png(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("camera") / "lab.png"
    cv2.imwrite(str(path), overhead(lab_at(0), "realistic").pixels)
    return path


def test_calibrate_writes_the_file_and_prints_the_error(lab_png: Path, tmp_path: Path,
                                                        capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "cam" / "r1.json"
    assert main(["camera", "calibrate", "--image", str(lab_png), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert "calibrated from 9 of 9 markers: reprojection error 0." in printed
    assert f"wrote {out} and {out.with_suffix('.floor.png')}" in printed
    camera = load_camera(out)
    assert len(look(overhead(lab_at(1), "realistic"), camera).regions) == 7


def test_the_default_file_is_under_csl_home(lab_png: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("CSL_HOME", str(tmp_path / "home"))
    assert main(["camera", "calibrate", "--image", str(lab_png), "--robot", "r7"]) == 0
    assert (tmp_path / "home" / "camera" / "r7.json").is_file()
    assert (tmp_path / "home" / "camera" / "r7.floor.png").is_file()


@pytest.mark.parametrize("argv, message", [
    (["--image", "{tmp}/none.png"], "--image: {tmp}/none.png is not a readable image file"),
    (["--image", "{png}", "--board", "{tmp}/board.json"], "{tmp}/board.json: dictionary: expected"),
    (["--image", "{blank}"], "calibration: the image shows 0 of the board's markers"),
])
def test_bad_input_is_one_line(argv: list[str], message: str, lab_png: Path, tmp_path: Path,
                               capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "board.json").write_text('{"dictionary": "nope", "marker_in": 12, "markers": []}')
    cv2.imwrite(str(tmp_path / "blank.png"), np.full((300, 400), 90, np.uint8))
    fill = {"tmp": str(tmp_path), "png": str(lab_png), "blank": str(tmp_path / "blank.png")}
    argv = [a.format(**fill) for a in argv]
    assert main(["camera", "calibrate", *argv, "--out", str(tmp_path / "c.json")]) == 2
    err = capsys.readouterr().err.strip()
    assert message.format(**fill) in err and len(err.splitlines()) == 1


@pytest.mark.zenoh
def test_calibrate_takes_its_image_from_the_driver(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with open_session(listen=[endpoint]) as session, DriverNode(SimulatedHero("r3", camera="realistic"), session):
        assert main(["camera", "calibrate", "--robot", "r3", "--connect", endpoint,
                     "--out", str(tmp_path / "r3.json")]) == 0
    assert "calibrated from 9 of 9 markers" in capsys.readouterr().out
    assert load_camera(tmp_path / "r3.json").calibration.image_size == (504, 384)

