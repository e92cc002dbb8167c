"""A saved calibration is picked up by itself (docs/camera.md, "Running it"): ``csl
camera calibrate`` writes $CSL_HOME/camera/ROBOT.json, and ``csl run``/``csl demo``
on a camera with no grey bands read through it, saying so in one line; a driver
whose images have no bands and no saved calibration is one line naming the command
that makes one, before the robot moves."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from csl_cli.main import main
from csl_cli.commands.camera import default_calibration
from tests.executive.test_camera_processes import csl
from tests.executive.test_camera_wiring import LAB_OBJECTS, assert_every_object_located, calibration_file, report_rows
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint


def test_the_saved_calibration_is_where_calibrate_writes_by_default() -> None:
    assert default_calibration("r7") == Path(os.environ["CSL_HOME"]) / "camera" / "r7.json"


@pytest.mark.slow
def test_run_on_the_realistic_simulator_reads_through_the_saved_calibration(
        tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch) -> None:
    saved = calibration_file(tmp_path, capsys)  # written to tmp_path/camera/r1.json
    monkeypatch.setenv("CSL_HOME", str(tmp_path))
    assert default_calibration("r1") == saved
    out = tmp_path / "out"
    assert main(["run", "--camera", "realistic", "--no-plots", "--library", str(tmp_path / "library.sqlite"),
                 "--out", str(out)]) in (0, 1)
    captured = capsys.readouterr()
    assert (f"camera: reading images through the saved calibration {saved} (or give --camera-calibration FILE)"
            in captured.err.splitlines())
    assert len(report_rows(captured.out)) == LAB_OBJECTS
    assert_every_object_located(out)


@pytest.mark.zenoh
@pytest.mark.slow
def test_a_real_camera_over_zenoh_needs_a_calibration_then_uses_the_saved_one(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    out = tmp_path / "out"
    run = ("run", "--driver", "zenoh", "--connect", endpoint, "--no-plots", "--library",
           str(tmp_path / "library.sqlite"), "--out", str(out))
    argv = ["-m", "csl_cli", "driver", "sim", "--camera", "realistic", "--listen", endpoint]
    with DriverProcess(argv) as driver:
        driver.ready()
        refused = csl(*run, home=tmp_path)
        assert refused.returncode == 2
        assert refused.stderr.splitlines() == [
            f"csl: error: driver r1's camera gives real images (no grey bands) and no calibration is saved at "
            f"{tmp_path / 'camera' / 'r1.json'}: run 'csl camera calibrate --robot r1' first, or give "
            f"--camera-calibration FILE (docs/camera.md)"]
        assert not (out / "episode.jsonl").exists()  # refused before the robot moved
        assert csl("camera", "calibrate", "--connect", endpoint, home=tmp_path).returncode == 0
        ran = csl(*run, home=tmp_path)
    assert ran.returncode in (0, 1), ran.stderr
    assert (f"camera: reading images through the saved calibration {tmp_path / 'camera' / 'r1.json'} (or give "
            "--camera-calibration FILE)") in ran.stderr.splitlines()
    assert_every_object_located(out)
