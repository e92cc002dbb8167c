"""The library: JSON exchange, the SQLite store, and its transactions."""

from __future__ import annotations

import json
import sqlite3

import pytest

from learner.library.format import descriptions_from_json, descriptions_to_json, write_library_json
from learner.library.store import LibraryStore, load_library
from tests.learner.fixtures import P, desc, four_objects


def test_json_round_trip_keeps_dont_care_slots() -> None:
    lib = four_objects()
    doc = descriptions_to_json(lib)
    assert doc["descriptions"][3]["grasp_position"] == ["*", "*"]
    assert doc["descriptions"][0]["features"][0] == {"feature": "Height", "position": [6, "*"], "value": 3.5}
    assert descriptions_from_json(json.loads(json.dumps(doc))) == lib


@pytest.mark.parametrize(
    ("doc", "message"),
    [
        ({"format": "x"}, "'format' must be 'csl-library'"),
        ({"format": "csl-library", "version": 4, "descriptions": []}, "unsupported 'version' 4"),
        ({"format": "csl-library", "version": 1, "descriptions": [{"id": "a"}]},
         "descriptions[0]: missing or empty string field 'grasp'"),
        ({"format": "csl-library", "version": 1, "descriptions": [
            {"id": "a", "grasp": "G", "grasp_position": [6, "*"], "features": [
                {"feature": "Width", "position": [6, 0], "value": "wide"}]}]},
         "descriptions[0] (a): features[0]: 'value' must be a finite number"),
        ({"format": "csl-library", "version": 1, "descriptions": [
            {"id": "a", "grasp": "G", "grasp_position": [6, "near"]}]},
         "grasp_position[1]: expected a number or \"*\""),
    ],
)
def test_bad_library_json_names_entry_and_field(doc, message) -> None:  # noqa: ANN001
    with pytest.raises(ValueError) as err:
        descriptions_from_json(doc, "lib.json")
    assert str(err.value).startswith("lib.json: ") and message in str(err.value)


def test_store_round_trip_and_unique_ids(tmp_path) -> None:  # noqa: ANN001
    with LibraryStore(tmp_path / "lib.sqlite") as store:
        store.add(four_objects())
        assert store.descriptions() == four_objects()
        assert store.unique_id("cup") == "cup#2" and store.unique_id("mug") == "mug"
    assert load_library(tmp_path / "lib.sqlite") == four_objects()  # persisted


def test_a_failed_write_leaves_the_library_as_it_was(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "lib.sqlite"
    with LibraryStore(path) as store:
        store.add(four_objects()[:2])
    batch = [desc("new", "Front-Wrap", ("Width", P(6, 0), 3)), four_objects()[0]]  # the 2nd clashes
    with LibraryStore(path) as store, pytest.raises(ValueError, match="'cup' is already in the library"):
        store.add(batch)
    assert [d.object_id for d in load_library(path)] == ["cup", "box"]


def test_a_crash_mid_transaction_loses_nothing_committed(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "lib.sqlite"
    with LibraryStore(path) as store:
        store.add(four_objects())
    # a writer that dies mid-transaction: its rows never become visible
    raw = sqlite3.connect(path)
    raw.execute("BEGIN")
    raw.execute("INSERT INTO descriptions (id, grasp) VALUES ('half', 'Front-Wrap')")
    raw.close()  # closed without commit, as a killed process would leave it
    assert [d.object_id for d in load_library(path)] == ["cup", "box", "tumbler", "closed"]


def test_not_a_library(tmp_path) -> None:  # noqa: ANN001
    junk = tmp_path / "junk.sqlite"
    junk.write_bytes(b"this is not sqlite" * 100)
    with pytest.raises(ValueError, match="not a csl library database"):
        LibraryStore(junk)
    with pytest.raises(ValueError, match="library file not found"):
        load_library(tmp_path / "none.json")


def test_json_files_are_written_whole(tmp_path) -> None:  # noqa: ANN001
    path = tmp_path / "lib.json"
    write_library_json(path, four_objects())
    assert load_library(path) == four_objects()
    assert not list(tmp_path.glob("*.tmp"))


@pytest.mark.parametrize(("key", "text", "shown"), [
    ("id", "cup\nmug", "'cup\\nmug'"), ("id", "cup\x00", "'cup\\x00'"), ("grasp", "Front\u202eWrap", "'Front\\u202eWrap'"),
])
def test_ids_and_grasp_names_must_be_printable_and_the_refusal_escapes_them(key: str, text: str, shown: str) -> None:
    entry = {"id": "cup", "grasp": "Front-Wrap", "grasp_position": [6, "*"], "features": [], key: text}
    with pytest.raises(ValueError) as refused:
        descriptions_from_json({"format": "csl-library", "version": 1, "descriptions": [entry]}, "lib.json")
    line = str(refused.value)
    assert line == (f"lib.json: descriptions[0]: '{key}' must be printable text (no control or format characters: "
                    f"a newline, NUL, a right-to-left override), got {shown}")
    assert line.isprintable()
