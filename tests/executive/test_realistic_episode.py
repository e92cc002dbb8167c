"""An episode on realistic camera images: the simulated HERO shows what a real ceiling
camera would, the executive's vision reads it through a calibration made from the
episode's first image, and the lab's objects are located, recognised and grasped as
with band images."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from camera_model.board import load_board
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from hero_driver.sim.render_board import board_path
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.worldfile import load_world
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner


@pytest.mark.slow
def test_an_episode_on_realistic_images(tmp_path: Path) -> None:
    hero = SimulatedHero("r1", world="lab", seed=0, camera="realistic")
    learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    executive = Executive(hero, learner, board=load_board(board_path("lab")))
    result = executive.run()
    executive.shutdown()
    assert result.status == "SUCCESS"
    camera = executive.services.navigator.camera  # calibrated on the first image
    assert camera is not None and camera.calibration.markers_seen == 9
    located = next(e for e in executive.log.events if e["event"] == "located")["regions"]
    placed = [(p.x_in, p.y_in) for p in load_world("lab", profile_and_catalogue()[1]).objects]
    assert len(located) == len(placed) == 7
    for x, y in placed:  # each object where the lab file puts it, to half an inch
        assert min(math.hypot(r["centroid"][0] - x, r["centroid"][1] - y) for r in located) < 0.5
    # as with band images (seed 0: 5 grasped, the 10 in box and one bottle left)
    assert [o.outcome for o in result.objects].count("grasped") >= 5
    assert all(o.outcome in ("grasped", "left") for o in result.objects)
