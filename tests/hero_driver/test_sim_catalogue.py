"""The catalogue and world files: Table 3 is complete, and bad files fail with one
line naming the file, the entry and the problem."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from hero_driver.sim.catalogue import load_catalogue
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import load_world, parse_world

TABLE_3 = {
    "cup-8oz/upright": {"Front-Wrap"},
    "soda-can-12oz/upright": {"Front-Wrap"},
    "soda-can-12oz/lying": {"Top-Vert-Grip", "Top-Hor-Grip"},
    "tumbler-16oz/upright": {"Top-Pinch"},
    "tumbler-16oz/lying": {"Front-Pinch"},
    "tumbler-32oz/upright": {"Top-Pinch"},
    "tumbler-32oz/lying": {"Front-Pinch"},
    "tennis-can/upright": {"Front-Wrap"},
    "tennis-can/lying": {"Top-Vert-Grip", "Top-Hor-Grip"},
    "open-box-9x4x5/upright-facing-sideways": {"Front-Pinch"},
    "open-box-9x4x5/lying-facing-up": {"Top-Pinch"},
    "open-box-9x4x5/lying-facing-sideways": {"Front-Pinch"},
    "open-box-9x4x5/lying-facing-down": {"No-Grab"},
    "closed-box-11x9x12/upright": {"No-Grab"},
}
TEST_OBJECTS = ["closed-box-2x2x2/upright", "soda-bottle-16oz/upright", "tumbler-20oz/upright",
                "tumbler-20oz/upside-down", "magazine-box-9x4x7/upright", "closed-box-10x10x10/upright"]


def test_table_3_training_objects_have_the_papers_grasps() -> None:
    catalogue = profile_and_catalogue()[1]
    for entry_id, grasps in TABLE_3.items():
        assert catalogue[entry_id].set == "training"
        assert {g.procedure for g in catalogue[entry_id].grasps} == grasps
    assert {e.id for e in catalogue.values() if e.set == "training"} == set(TABLE_3)


def test_test_objects_present_and_knock_over_targets_lie() -> None:
    catalogue = profile_and_catalogue()[1]
    for entry_id in TEST_OBJECTS:
        assert catalogue[entry_id].set == "test"
    for entry in catalogue.values():
        target = entry.side_effects.knocks_to
        if target is not None:
            assert catalogue[target].footprint.shape == "rect" and catalogue[target].rolls


def test_shipped_worlds_load() -> None:
    lab = SimWorld("lab")
    assert {t.entry_id for t in lab.truth()} >= set(TEST_OBJECTS)
    training = SimWorld("training")
    assert {t.entry_id for t in training.truth()} == set(TABLE_3)


def _write(tmp_path: Path, data: dict, name: str = "w.json") -> Path:
    path = tmp_path / name
    path.write_text(json.dumps(data))
    return path


GOOD = {"room": {"width_in": 100, "depth_in": 100}, "robot": {"x_in": 20, "y_in": 20},
        "objects": [{"id": "cup-8oz/upright", "x_in": 60, "y_in": 60}]}


@pytest.mark.parametrize("change, words", [
    ({"objects": [{"id": "mug/upright", "x_in": 60, "y_in": 60}]}, ["objects[0]", "unknown catalogue entry"]),
    ({"objects": [{"id": "cup-8oz/upright", "x_in": 99.5, "y_in": 60}]}, ["objects[0]", "outside"]),
    ({"objects": [{"id": "cup-8oz/upright", "x_in": 60, "y_in": 60},
                  {"id": "soda-can-12oz/upright", "x_in": 62, "y_in": 60}]}, ["objects[1]", "overlaps"]),
    ({"room": {"width_in": "wide", "depth_in": 100}}, ["room", "width_in"]),
    ({"furniture": [{"name": "desk", "x_in": 60, "y_in": 60, "width_in": 20, "depth_in": 20}]}, ["overlaps"]),
    ({"noise": {"sonar": True, "loud": 3}}, ["noise", "loud"]),
])
def test_bad_world_file_names_file_entry_and_problem(tmp_path: Path, change: dict, words: list[str]) -> None:
    path = _write(tmp_path, {**GOOD, **change})
    with pytest.raises(ValueError) as info:
        load_world(path, profile_and_catalogue()[1])
    message = str(info.value)
    assert "\n" not in message and str(path) in message
    for word in words:
        assert word in message


def test_robot_overlapping_an_object_is_rejected(tmp_path: Path) -> None:
    path = _write(tmp_path, {**GOOD, "robot": {"x_in": 55, "y_in": 60}})
    with pytest.raises(ValueError, match="robot"):
        SimWorld(path)


def test_unreadable_world_file(tmp_path: Path) -> None:
    path = tmp_path / "broken.json"
    path.write_text("{not json")
    with pytest.raises(ValueError, match="broken.json"):
        load_world(path, profile_and_catalogue()[1])


def test_bad_catalogue_entry_is_named(tmp_path: Path) -> None:
    data = json.loads((Path(__file__).resolve().parents[2] / "hero_driver/worlds/catalogue.json").read_text())
    data["entries"][3]["grasps"] = [{"procedure": "Front-Squeeze", "approach": "any"}]
    path = _write(tmp_path, data, "cat.json")
    with pytest.raises(ValueError) as info:
        load_catalogue(profile_and_catalogue()[0].grasp_names, path)
    assert "cat.json" in str(info.value) and data["entries"][3]["id"] in str(info.value)
    assert "procedure" in str(info.value)


def test_parse_world_defaults_yaw_and_noise() -> None:
    spec = parse_world(GOOD, "<inline>", profile_and_catalogue()[1])
    assert spec.objects[0].yaw_deg == 0.0 and spec.noise is None


def test_misspelt_fields_are_rejected(tmp_path: Path) -> None:
    path = _write(tmp_path, {**GOOD, "objetcs": []})
    with pytest.raises(ValueError, match="objetcs"):
        load_world(path, profile_and_catalogue()[1])
