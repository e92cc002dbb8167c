"""Training objects carry their camera appearance (objects file version 2; 1 still loads)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from learner.appearance import Appearance
from learner.position import Position
from learner.training.inputs import TrainingObject, objects_document, read_objects

CAN = TrainingObject("can/lying", "Top-Vert-Grip", Position(6, 0), ((-2.5, -1.0), (2.5, -1.0), (2.5, 1.0)), False,
                     Appearance(False, 13.44, 2.333))


def test_objects_file_round_trip_keeps_the_appearance(tmp_path: Path) -> None:
    path = tmp_path / "objects.json"
    doc = objects_document([CAN])
    assert doc["version"] == 2 and doc["objects"][0]["appearance"] == {  # type: ignore[index]
        "round": False, "area_in2": 13.44, "elongation": 2.333}
    path.write_text(json.dumps(doc), encoding="utf-8")
    assert read_objects(path) == [CAN]


def test_a_version_1_objects_file_loads_without_appearance(tmp_path: Path) -> None:
    path = tmp_path / "objects.json"
    path.write_text(json.dumps({"format": "csl-training-objects", "version": 1, "objects": [
        {"id": "cup", "grasp": "Front-Wrap", "round": True}]}), encoding="utf-8")
    (cup,) = read_objects(path)
    assert cup.appearance is None and cup.round


def test_a_bad_appearance_names_the_object(tmp_path: Path) -> None:
    path = tmp_path / "objects.json"
    path.write_text(json.dumps({"format": "csl-training-objects", "version": 2, "objects": [
        {"id": "cup", "grasp": "Front-Wrap", "round": True,
         "appearance": {"round": True, "area_in2": -1, "elongation": 1}}]}), encoding="utf-8")
    with pytest.raises(ValueError, match=r"objects\[0\] \(cup\): appearance: appearance area must be a positive"):
        read_objects(path)
