"""A scenario's keyword arguments become the world, noise, library and criterion of an
episode, and a mistake is one line naming the keyword."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from csl_testing.inputs import STEADY_NOISE, criterion_of, noise_config, placements, seed_library, world_spec
from executive.defaults import EXAMPLE_LIBRARY
from hero_driver.sim.noise import NOISE_PRESETS, NoiseConfig
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.worldfile import Placement
from learner.choosing.criteria import criterion
from learner.library.format import read_library_json, write_library_json

CATALOGUE = profile_and_catalogue()[1]


def test_no_world_is_the_bare_room_with_the_objects_given() -> None:
    spec = world_spec(None, [("cup-8oz/upright", 110, 80, 20), ("soda-can-12oz/lying", 60.0, 100.0)], CATALOGUE)
    assert (spec.room_width_in, spec.room_depth_in, spec.robot, spec.furniture) == (200.0, 140.0, (30.0, 30.0, 0.0), ())
    assert spec.objects == (Placement("cup-8oz/upright", 110.0, 80.0, 20.0),
                            Placement("soda-can-12oz/lying", 60.0, 100.0, 0.0))
    assert spec.noise is None and spec.source == "<scenario>"


def test_a_shipped_world_keeps_its_room_and_furniture_but_takes_the_objects_given() -> None:
    lab = json.loads(Path("hero_driver/worlds/lab.json").read_text(encoding="utf-8"))
    own = world_spec("lab", None, CATALOGUE)
    assert [p.entry_id for p in own.objects] == [o["id"] for o in lab["objects"]]
    placed = world_spec("lab", [("cup-8oz/upright", 120, 90)], CATALOGUE)
    assert placed.objects == (Placement("cup-8oz/upright", 120.0, 90.0, 0.0),)
    assert (placed.room_width_in, placed.furniture, placed.robot) == (240.0, own.furniture, own.robot)


def test_a_world_file_and_a_worldspec(tmp_path: Path) -> None:
    path = tmp_path / "corner.json"
    path.write_text(json.dumps({"room": {"width_in": 100, "depth_in": 100},
                                "robot": {"x_in": 20, "y_in": 20, "heading_deg": 90},
                                "objects": [{"id": "cup-8oz/upright", "x_in": 70, "y_in": 70}]}), encoding="utf-8")
    spec = world_spec(path, None, CATALOGUE)
    assert (spec.name, spec.robot, spec.objects) == ("corner", (20.0, 20.0, 90.0),
                                                      (Placement("cup-8oz/upright", 70.0, 70.0, 0.0),))
    moved = world_spec(spec, [Placement("cup-8oz/upright", 50.0, 60.0, 0.0)], CATALOGUE)
    assert moved.objects == (Placement("cup-8oz/upright", 50.0, 60.0, 0.0),) and moved.robot == spec.robot
    assert world_spec(spec, None, CATALOGUE) is spec


@pytest.mark.parametrize(("world", "objects", "message"), [
    ("labb", None, "world: 'labb' is neither a world file nor a shipped world (shipped: apartment, apartment-2, clutter, crossing, lab, reference, training, two-rooms)"),
    (None, [("no-such/thing", 50, 50)],
     "<scenario>: objects[0]: field 'id' names unknown catalogue entry 'no-such/thing'"),
    (None, [("cup-8oz/upright", 50, 50), "cup"], "objects[1]: expected a Placement or (entry, x_in, y_in[, yaw_deg])"),
    (None, [("cup-8oz/upright", 50, True)], "objects[0]: expected a Placement"),
    (None, [("cup-8oz/upright", 199, 70)],  # through the wall at x = 200
     "<scenario>: objects[0] 'cup-8oz/upright': lies outside the 200x140 in room"),
])
def test_a_bad_world_or_object_is_one_line_naming_it(world: str | None, objects: list | None, message: str) -> None:
    with pytest.raises(ValueError) as caught:
        world_spec(world, objects, CATALOGUE)
    text = str(caught.value)
    assert text.startswith(message) and "\n" not in text


def test_a_world_file_that_is_not_json(tmp_path: Path) -> None:
    path = tmp_path / "broken.json"
    path.write_text("{", encoding="utf-8")
    with pytest.raises(ValueError, match=r"^world: .*broken.json: cannot read world file"):
        world_spec(path, None, CATALOGUE)


@given(st.lists(st.tuples(st.sampled_from(sorted(CATALOGUE)), st.floats(0, 500), st.floats(0, 500),
                          st.floats(-360, 360)), max_size=5))
def test_placement_tuples_keep_their_values(entries: list[tuple[str, float, float, float]]) -> None:
    assert placements(entries) == tuple(Placement(*e) for e in entries)


def test_noise_by_preset_name_or_config() -> None:
    assert noise_config("paper") is NOISE_PRESETS["paper"]
    assert noise_config(STEADY_NOISE) is STEADY_NOISE and noise_config(None) is None
    assert (STEADY_NOISE.odometry_frac, STEADY_NOISE.pixel_sigma, STEADY_NOISE.outlier_p) == (
        0.0, 0.0, NoiseConfig().outlier_p)  # the mild sonar, exact odometry and camera
    with pytest.raises(ValueError, match=r"^noise: expected a NoiseConfig or one of clean, mild, paper, harsh"):
        noise_config("loud")


def test_library_shipped_from_a_file_or_given(tmp_path: Path) -> None:
    shipped = read_library_json(EXAMPLE_LIBRARY)
    assert seed_library(None) == shipped
    path = tmp_path / "two.json"
    write_library_json(path, shipped[:2])
    assert seed_library(path) == shipped[:2] == seed_library(str(path))
    assert seed_library(shipped[:1]) == shipped[:1] and seed_library([]) == []
    with pytest.raises(ValueError, match=r"^library: .*missing.json: library file not found$"):
        seed_library(tmp_path / "missing.json")
    with pytest.raises(ValueError, match=r"^library\[1\]: expected an ObjectDescription, got str$"):
        seed_library([shipped[0], "cup"])


def test_criterion_by_name() -> None:
    assert criterion_of("cs-id3").name == "cs-id3" and criterion_of(None) is None
    built = criterion("id3")
    assert criterion_of(built) is built
    with pytest.raises(ValueError, match=r"^criterion: unknown criterion 'cs-id4' \(choose from: "):
        criterion_of("cs-id4")
