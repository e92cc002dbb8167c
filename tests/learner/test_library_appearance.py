"""Library format version 2: descriptions carry the camera's appearance; version 1 still loads."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

from learner.appearance import Appearance
from learner.description import ObjectDescription, Observation
from learner.library.format import descriptions_from_json, descriptions_to_json, read_library_json
from learner.library.store import LibraryStore, load_library
from tests.learner.fixtures import P

LYING = ObjectDescription("can/lying", "Top-Vert-Grip", P(6, 0), (Observation("Width", P(6, 0), 2.5),),
                          Appearance(False, 13.44, 2.333))
OLD = ObjectDescription("cup", "Front-Wrap", P(6, None), (Observation("Height", P(6, None), 3.5),))


def test_json_round_trip_keeps_the_appearance_and_writes_version_2() -> None:
    doc = descriptions_to_json([LYING, OLD])
    assert doc["version"] == 2
    entries = doc["descriptions"]
    assert entries[0]["appearance"] == {"round": False, "area_in2": 13.44, "elongation": 2.333}
    assert "appearance" not in entries[1]
    assert descriptions_from_json(json.loads(json.dumps(doc))) == [LYING, OLD]


def test_a_version_1_library_loads_without_appearances(tmp_path: Path) -> None:
    path = tmp_path / "old.json"
    path.write_text(json.dumps({"format": "csl-library", "version": 1, "descriptions": [
        {"id": "cup", "grasp": "Front-Wrap", "grasp_position": [6, "*"],
         "features": [{"feature": "Height", "position": [6, "*"], "value": 3.5}]}]}), encoding="utf-8")
    assert read_library_json(path) == [OLD]


def test_version_1_has_no_appearance_key() -> None:
    doc = {"format": "csl-library", "version": 1, "descriptions": [
        {"id": "a", "grasp": "G", "grasp_position": [6, "*"], "appearance": {"round": True}}]}
    with pytest.raises(ValueError, match=r"descriptions\[0\]: unknown key 'appearance'"):
        descriptions_from_json(doc, "lib")


def test_a_bad_appearance_names_the_entry() -> None:
    doc = descriptions_to_json([LYING])
    doc["descriptions"][0]["appearance"]["elongation"] = 0.5  # type: ignore[index]
    with pytest.raises(ValueError, match=r"lib: descriptions\[0\] \(can/lying\): appearance: .*elongation"):
        descriptions_from_json(doc, "lib")


def test_sqlite_store_keeps_the_appearance(tmp_path: Path) -> None:
    with LibraryStore(tmp_path / "lib.sqlite") as store:
        store.add([LYING, OLD])
    assert load_library(tmp_path / "lib.sqlite") == [LYING, OLD]


def test_a_version_1_store_is_upgraded_on_opening(tmp_path: Path) -> None:
    path = tmp_path / "old.sqlite"
    with sqlite3.connect(path) as db:  # the version-1 schema, one description in it
        db.executescript("""
            CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
            INSERT INTO meta VALUES ('format', 'csl-library/1');
            CREATE TABLE descriptions (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE,
                grasp TEXT NOT NULL, grasp_distance_in REAL, grasp_orientation_deg REAL);
            CREATE TABLE observations (description_seq INTEGER NOT NULL REFERENCES descriptions(seq)
                ON DELETE CASCADE, feature TEXT NOT NULL, distance_in REAL, orientation_deg REAL, value REAL NOT NULL);
            INSERT INTO descriptions (id, grasp, grasp_distance_in, grasp_orientation_deg)
                VALUES ('cup', 'Front-Wrap', 6, NULL);
            INSERT INTO observations VALUES (1, 'Height', 6, NULL, 3.5);
        """)
    db.close()
    with LibraryStore(path) as store:
        assert store.descriptions() == [OLD]
        store.add([LYING])  # a description learned after the upgrade keeps its appearance
    assert load_library(path) == [OLD, LYING]
    with sqlite3.connect(path) as db:
        assert db.execute("SELECT value FROM meta WHERE key='format'").fetchone() == ("csl-library/2",)
    db.close()
