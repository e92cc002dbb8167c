"""Runs through a realistic camera whose room changed after calibration
(docs/camera.md, "When the room changes"): a change the vision cannot divide out stops
the run with one line and exit 2 before the robot moves; one it can (a lamp) runs as
the plain room does."""

from __future__ import annotations

import dataclasses
import math
import re
from concurrent.futures import Future
from pathlib import Path

import numpy as np
import pytest

from camera_model.board import load_board
from camera_model.image import CameraImage
from csl_cli.main import main
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.render_board import board_path
from hero_driver.sim.worldfile import load_world
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from planner.scene_check import SceneChanged
from planner.segmentation import Camera, calibrated_camera
from tests.executive.test_camera_processes import csl
from tests.hero_driver.test_zenoh_support import DriverProcess
from tests.zenoh_rpc.support import free_endpoint

LINE = re.compile(r"^csl: error: the floor no longer matches the calibration: foreground share \d+% of the floor "
                  r"\(at most 8%\)(, \d+ regions \(a floor of \d+ sq ft holds at most \d+\))?; "
                  r"recalibrate \(csl camera calibrate\)$")


def lab_camera() -> Camera:
    """Calibrated on the plain realistic lab, as 'csl camera calibrate' would be."""
    hero = SimulatedHero("cal", world="lab", seed=0, camera="realistic")
    try:
        return calibrated_camera(hero.camera().result().pixels, load_board(board_path("lab")))
    finally:
        hero.close()


class RugLaidMidRun(SimulatedHero):
    """The plain realistic lab until a rug is laid over the whole floor after the
    first RUG_AFTER images: a checkerboard of 8-pixel squares a quarter lighter and
    a quarter darker (a floor unlike its calibration everywhere)."""

    RUG_AFTER = 3

    def __init__(self) -> None:
        super().__init__("r1", world="lab", seed=0, camera="realistic")
        self.images = 0
        self.clock_at_rug: float | None = None

    def camera(self) -> Future[CameraImage]:
        image = super().camera().result()
        self.images += 1
        if self.images > self.RUG_AFTER:
            if self.clock_at_rug is None:
                self.clock_at_rug = self.state().clock_s
            rows, cols = np.indices(image.pixels.shape)
            rug = np.where((rows // 8 + cols // 8) % 2 == 0, 1.25, 0.75)
            image = dataclasses.replace(image, pixels=np.clip(image.pixels * rug, 0, 255).astype(np.uint8))
        done: Future[CameraImage] = Future()
        done.set_result(image)
        return done


def episode(preset: str, tmp_path: Path, hero: SimulatedHero | None = None) -> tuple[SimulatedHero, Executive]:
    hero = hero or SimulatedHero("r1", world="lab", seed=0, camera=preset)
    learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    return hero, Executive(hero, learner, camera=lab_camera())


def test_the_executive_stops_at_its_first_look_on_a_relaid_floor_before_any_robot_time(tmp_path: Path) -> None:
    hero, executive = episode("realistic-floor", tmp_path)
    with pytest.raises(SceneChanged, match=r"^the floor no longer matches the calibration: "):
        executive.run()
    executive.shutdown()
    assert hero.state().clock_s == 0.0  # no move, sense or grasp was sent
    assert [e["event"] for e in executive.log.events] == []  # not even a region located


def test_a_rug_laid_mid_run_stops_it_at_the_first_look_after(tmp_path: Path) -> None:
    """Robot time before the change was spent on real objects; none after it."""
    rugged = RugLaidMidRun()
    hero, executive = episode("realistic", tmp_path, rugged)
    with pytest.raises(SceneChanged, match=r"^the floor no longer matches the calibration: foreground share"):
        executive.run()
    executive.shutdown()
    assert rugged.images == RugLaidMidRun.RUG_AFTER + 1  # the first image with the rug was the last looked at
    assert rugged.clock_at_rug is not None and rugged.clock_at_rug > 0  # it worked before the rug
    assert hero.state().clock_s == rugged.clock_at_rug  # and not a second after


@pytest.mark.parametrize("command", ["run", "demo"])
def test_csl_on_a_relaid_floor_says_one_line_and_exits_2(command: str, tmp_path: Path,
                                                          capsys: pytest.CaptureFixture[str]) -> None:
    argv = [command, "--camera", "realistic-floor", "--no-plots", "--out", str(tmp_path / "out")]
    assert main(argv if command == "demo" else [*argv, "--driver", "sim"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""  # no report, no training (the demo checks before it trains)
    assert len(captured.err.splitlines()) == 1 and LINE.match(captured.err.strip()), captured.err


@pytest.mark.slow
def test_an_episode_under_a_lamp_switched_on_after_calibration_handles_every_object(tmp_path: Path) -> None:
    hero, executive = episode("realistic-lamp", tmp_path)
    result = executive.run()
    executive.shutdown()
    assert result.status == "SUCCESS"
    located = next(e for e in executive.log.events if e["event"] == "located")["regions"]
    placed = [(p.x_in, p.y_in) for p in load_world("lab", profile_and_catalogue()[1]).objects]
    assert len(located) == len(placed) == 7  # no phantom in the lamp's pool
    for x, y in placed:  # each within the scene changes' stated error (docs/camera.md)
        assert min(math.hypot(r["centroid"][0] - x, r["centroid"][1] - y) for r in located) < 1.0
    # seed 0: 5 grasped, the 10 in box left, and the lying bottle, pushed by a failed grasp
    # onto the board's print beside the marker at (90, 170), lost to the camera there
    # (docs/camera.md: an object on a marker cannot be told from the print)
    outcomes = [o.outcome for o in result.objects]
    assert outcomes.count("grasped") >= 5 and "failed" not in outcomes


@pytest.mark.zenoh
@pytest.mark.slow
def test_a_driver_restarted_on_a_relaid_floor_stops_the_run_through_the_old_calibration(tmp_path: Path) -> None:
    """As on a real robot: calibrated against the plain room's driver process, then the
    floor re-laid (the driver restarted with the change): the run says one line, exit 2."""
    calibration = tmp_path / "camera" / "r1.json"
    endpoint = free_endpoint()
    with DriverProcess(["-m", "csl_cli", "driver", "sim", "--camera", "realistic", "--listen", endpoint]) as driver:
        driver.ready()
        calibrated = csl("camera", "calibrate", "--connect", endpoint, "--out", str(calibration), home=tmp_path)
        assert calibrated.returncode == 0, calibrated.stderr
    endpoint = free_endpoint()
    with DriverProcess(["-m", "csl_cli", "driver", "sim", "--camera", "realistic-floor", "--listen", endpoint]) as driver:
        driver.ready()
        run = csl("run", "--driver", "zenoh", "--connect", endpoint, "--camera-calibration", str(calibration),
                  "--no-plots", "--library", str(tmp_path / "library.sqlite"), "--out", str(tmp_path / "out"),
                  home=tmp_path)
    assert run.returncode == 2 and run.stdout == ""
    assert len(run.stderr.splitlines()) == 1 and LINE.match(run.stderr.strip()), run.stderr
