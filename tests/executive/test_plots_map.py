"""The map shows objects where they ended and is drawn on an undistorted image: the
data it draws from worked by hand, the fish-eye undistortion checked against the
simulator's truth, and the PNG read back for what changes with a moved object."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import matplotlib.image
import numpy as np
import pytest

from behaviours.records import ObjectRecord
from camera_model.image import CameraImage
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from reporting.plots import Ending, endings, map_image, plot_map
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from planner import Region

OBJECT_BAND = 220  # docs/conventions.md, the overhead image's intensities
ROBOT_BAND = 170


def _square(x: float, y: float, half: float = 2.0) -> Region:
    polygon = ((x - half, y - half), (x + half, y - half), (x + half, y + half), (x - half, y + half))
    return Region(polygon, (x, y), 25, None, True, 2 * half, 2 * half)


def _record(index: int, first: Region, last: Region, outcome: str = "grasped") -> ObjectRecord:
    """Only what the map reads: the index, both regions and the outcome (no session or
    cost estimator: the map draws no decision)."""
    record = ObjectRecord(index, last, 25, None, None, first)  # type: ignore[arg-type]
    record.finish(outcome, "Top-Pinch")
    return record


def _side_effect(index: int, effect: str, **more: object) -> dict[str, object]:
    return {"event": "side_effect", "object": index, "effect": effect, **more}


def test_each_object_ends_where_the_side_effect_check_last_saw_it() -> None:
    records = [_record(0, _square(10, 10), _square(13, 14)),  # pushed, then knocked over: 3-4-5
               _record(1, _square(50, 50), _square(50, 50)),  # a clean failed grasp only
               _record(2, _square(80, 20), _square(80, 20)),  # rolled out of sight
               _record(3, _square(30, 60), _square(36, 68))]  # pushed: 6-8-10
    events = [_side_effect(0, "pushed", shift_in=2.0), _side_effect(1, "none", shift_in=0.0),
              _side_effect(0, "changed", shift_in=3.0), _side_effect(2, "changed", reason="region lost"),
              _side_effect(3, "pushed", shift_in=10.0), {"event": "grasp", "object": 3, "success": False}]
    assert endings(records, events) == [
        Ending(0, _square(10, 10).polygon, _square(13, 14).polygon, 5.0, "knocked over"),
        Ending(1, _square(50, 50).polygon, _square(50, 50).polygon, 0.0, None),
        Ending(2, _square(80, 20).polygon, _square(80, 20).polygon, 0.0, "lost from sight"),
        Ending(3, _square(30, 60).polygon, _square(36, 68).polygon, 10.0, "pushed"),
    ]


def _map(path: Path, records: list[ObjectRecord], events: list[dict[str, object]]) -> np.ndarray:
    image = CameraImage(np.full((100, 120), 30, np.uint8), 0.8, 0.0, 80.0)
    plot_map(path, image, records, events, [f"object {r.index}" for r in records], (20.0, 20.0),
             base_radius_in=8.0)
    return matplotlib.image.imread(path)


def test_a_pushed_object_is_drawn_where_it_ended(tmp_path: Path) -> None:
    still = _map(tmp_path / "still.png", [_record(0, _square(40, 40), _square(40, 40))], [])
    pushed = _map(tmp_path / "pushed.png", [_record(0, _square(40, 40), _square(60, 40))],
                  [_side_effect(0, "pushed", shift_in=20.0)])
    assert still.shape == pushed.shape and still.shape[1] > still.shape[0] > 400
    assert not np.array_equal(still, pushed)


def test_a_fish_eye_image_is_undistorted_before_anything_is_drawn_on_it() -> None:
    """The simulated lens moves the objects towards the image centre: at the world
    position of each object (and of the robot) the raw image may show the floor, the
    undistorted one shows the object."""
    lens = dataclasses.replace(NoiseConfig.off(), fisheye=True)
    driver = SimulatedHero("r1", world="lab", seed=0, noise=lens)
    try:
        raw = driver.camera().result()
        truths, pose = driver.truth(), driver.state().pose
    finally:
        driver.close()
    assert raw.fisheye is not None
    flat = map_image(raw)
    assert flat.fisheye is None and flat.pixels.shape == raw.pixels.shape
    grid = CameraImage(raw.pixels, raw.inches_per_pixel, raw.origin_x_in, raw.origin_y_in)

    def at(pixels: np.ndarray, x: float, y: float) -> int:
        row, col = grid.to_pixel(x, y)
        return int(pixels[round(row), round(col)])

    places = [(t.x_in, t.y_in, OBJECT_BAND) for t in truths] + [(pose.x_in, pose.y_in, ROBOT_BAND)]
    assert all(at(flat.pixels, x, y) == band for x, y, band in places)
    assert sum(at(raw.pixels, x, y) != band for x, y, band in places) >= 2  # what drawing on the raw image got wrong


def test_an_image_without_a_lens_is_drawn_as_it_is() -> None:
    image = CameraImage(np.full((10, 12), 30, np.uint8), 0.8, 0.0, 8.0)
    assert map_image(image) is image


@pytest.mark.slow
def test_a_lab_episode_with_side_effects_draws_objects_where_they_ended(tmp_path: Path) -> None:
    learner = LocalLearner(tmp_path / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    executive = Executive(SimulatedHero("r1", world="lab", seed=0, noise=NoiseConfig.preset("paper")), learner)
    try:
        result = executive.run()
        image = executive.services.driver.camera().result()
    finally:
        executive.shutdown()
        learner.close()
    events = executive.log.events
    ended = endings(result.objects, events)
    for record, ending in zip(result.objects, ended):
        effects = {e["effect"] for e in events if e["event"] == "side_effect" and e["object"] == record.index}
        assert ending.shift_in == math.dist(record.first_region.centroid, record.region.centroid)
        if effects <= {"none"}:  # nothing moved it: it ends where it was first seen
            assert (ending.change, ending.shift_in) == (None, 0.0)
        else:
            assert ending.change == ("knocked over" if "changed" in effects else "pushed") and ending.shift_in > 0
    assert {e.change for e in ended} >= {"pushed", "knocked over"}  # the seed shows both

    labels = [f"object {r.index}" for r in result.objects]
    plot_map(tmp_path / "ended.png", image, result.objects, events, labels, base_radius_in=8.0)
    as_first_seen = [dataclasses.replace(r, region=r.first_region) for r in result.objects]
    untouched = [e for e in events if e["event"] != "side_effect"]  # the same moves, nothing pushed
    plot_map(tmp_path / "first.png", image, as_first_seen, untouched, labels, base_radius_in=8.0)
    assert not np.array_equal(matplotlib.image.imread(tmp_path / "ended.png"),
                              matplotlib.image.imread(tmp_path / "first.png"))
