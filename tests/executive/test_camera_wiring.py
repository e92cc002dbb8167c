"""The realistic camera end to end through ``csl`` (docs/camera.md): ``csl demo
--camera realistic`` calibrates from the first image of the lab's board; ``csl run
--camera-calibration FILE`` reads images through a calibration file; bad input is one
line. The real-process version (driver, calibrate, run as separate processes) is in
test_camera_processes.py."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from csl_cli.main import main
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.worldfile import load_world

LAB_OBJECTS = 7


def lab_placements() -> list[tuple[str, float, float]]:
    return [(p.entry_id, p.x_in, p.y_in) for p in load_world("lab", profile_and_catalogue()[1]).objects]


def located(out: Path) -> list[tuple[float, float]]:
    """The object regions of the episode's first image, from its log."""
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    regions = next(e for e in events if e["event"] == "located")["regions"]
    return [(r["centroid"][0], r["centroid"][1]) for r in regions]


def assert_every_object_located(out: Path) -> None:
    seen = located(out)
    assert len(seen) == LAB_OBJECTS  # no region that is not an object
    for _, x, y in lab_placements():  # each where the lab file puts it, to half an inch
        assert min(math.hypot(sx - x, sy - y) for sx, sy in seen) < 0.5


def report_rows(out: str) -> list[list[str]]:
    """The report table's object rows (index, object, grasp, outcome, ok, ...)."""
    return [line.split() for line in out.splitlines() if line[:1].isdigit() and "/" in line.split()[1]]


@pytest.mark.slow
def test_demo_on_the_realistic_camera_locates_and_handles_every_object(tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--camera", "realistic", "--no-plots", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    rows = report_rows(out)
    # the report names each lab object once, judged right (seed 0: all handled, as with bands)
    # (a trailing * marks one knocked over during the episode)
    assert sorted(r[1].rstrip("*") for r in rows) == sorted(entry for entry, _, _ in lab_placements())
    assert all(({"grasped", "left"} & set(r)) and "yes" in r for r in rows)
    assert f"{LAB_OBJECTS} objects: {LAB_OBJECTS}/{LAB_OBJECTS} handled correctly" in out
    assert_every_object_located(tmp_path)


def calibration_file(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> Path:
    """``csl camera calibrate`` on an image of the lab saved by the realistic simulator."""
    import cv2

    from hero_driver.sim_driver import SimulatedHero

    image = tmp_path / "lab.png"
    cv2.imwrite(str(image), SimulatedHero(camera="realistic", seed=7).camera().result().pixels)
    out = tmp_path / "camera" / "r1.json"
    assert main(["camera", "calibrate", "--image", str(image), "--out", str(out)]) == 0
    capsys.readouterr()
    return out


@pytest.mark.slow
def test_run_reads_the_realistic_simulator_through_a_calibration_file(tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    calibration = calibration_file(tmp_path, capsys)
    out = tmp_path / "out"
    assert main(["run", "--camera", "realistic", "--camera-calibration", str(calibration), "--no-plots",
                 "--library", str(tmp_path / "library.sqlite"), "--out", str(out)]) in (0, 1)
    assert len(report_rows(capsys.readouterr().out)) == LAB_OBJECTS
    assert_every_object_located(out)


def one_line_error(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("csl: error: ")
    return err[0]


def test_a_calibration_of_another_camera_is_refused_before_the_robot_moves(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    calibration = calibration_file(tmp_path, capsys)
    out = tmp_path / "out"
    # the simulator's band camera (315x240 pixels) is not the calibrated one (504x384)
    assert main(["run", "--camera-calibration", str(calibration), "--no-plots",
                 "--library", str(tmp_path / "library.sqlite"), "--out", str(out)]) == 2
    line = one_line_error(capsys)
    assert f"--camera-calibration: {calibration} is for 504x384 images, the driver's camera gives 315x240" in line
    # refused while the run set up, before its episode began (so before any move): a
    # failed start takes back the --out folder it made, log included
    assert not out.exists()


def test_a_bad_calibration_file_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    bad = tmp_path / "cal.json"
    bad.write_text(json.dumps({"format": 1, "floor": "wide"}))
    assert main(["run", "--camera-calibration", str(bad), "--out", str(tmp_path / "out")]) == 2
    assert f"--camera-calibration: {bad}: floor: expected an object" in one_line_error(capsys)
    assert main(["run", "--camera-calibration", str(tmp_path / "none.json"), "--out", str(tmp_path / "out")]) == 2
    assert "--camera-calibration: " in one_line_error(capsys)


def test_a_calibration_without_its_empty_floor_is_one_line(tmp_path: Path,
                                                           capsys: pytest.CaptureFixture[str]) -> None:
    calibration = calibration_file(tmp_path, capsys)
    calibration.with_suffix(".floor.png").unlink()
    assert main(["run", "--camera-calibration", str(calibration), "--out", str(tmp_path / "out")]) == 2
    assert "r1.floor.png: missing or not an image" in one_line_error(capsys)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["run", "--driver", "zenoh", "--camera", "realistic"], "--camera goes with --driver sim"),
        (["demo", "--camera", "fisheye"], "argument --camera: invalid choice: 'fisheye'"),
    ],
)
def test_bad_camera_arguments_are_one_line(argv: list[str], message: str, tmp_path: Path,
                                           capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*argv, "--out", str(tmp_path)]) == 2
    line = capsys.readouterr().err.strip()
    assert "\n" not in line and message in line


def test_a_world_without_a_board_says_so(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["demo", "--camera", "realistic", "--world", "training", "--out", str(tmp_path)]) == 2
    line = one_line_error(capsys)
    assert "training.json: names no marker board (field 'board'" in line
    assert line.endswith("or give --camera-calibration FILE")


def test_the_map_is_drawn_on_the_rectified_image(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from csl_cli.commands.episode import _as_mapped
    from hero_driver.sim_driver import SimulatedHero
    from planner.segmentation import load_camera

    camera = load_camera(calibration_file(tmp_path, capsys))
    raw = SimulatedHero(camera="realistic").camera().result()
    mapped = _as_mapped(raw, camera)
    c = camera.calibration
    assert mapped.pixels.shape == (c.floor_size[1], c.floor_size[0]) != raw.pixels.shape
    assert (mapped.inches_per_pixel, mapped.origin_x_in, mapped.origin_y_in) == (
        c.inches_per_pixel, c.origin_x_in, c.origin_y_in)
    assert _as_mapped(raw, None) is raw  # band images are drawn as they come
