"""Idempotent learning: a retried learn with the same key stores nothing new and answers
the same id; old stores gain the key column and still open; ids stay cheap to find."""

from __future__ import annotations

import sqlite3
from contextlib import closing
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from learner.library.store import NEXT_SUFFIX, LibraryStore, load_library
from learner.service import LibrarySnapshot, LocalLearner
from learner.service.local import VERSION_KEY
from learner.service.protocol import ProtocolError, decode_learn_request, encode_learn_request
from tests.learner.fixtures import P, desc, four_objects

MUG = desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 10), ("Front-Hole?", P(6, None), 1))

# The schema of a version-2 store from before idempotent learning (no learn_key column).
OLD_SCHEMA = """
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE descriptions (seq INTEGER PRIMARY KEY AUTOINCREMENT, id TEXT NOT NULL UNIQUE, grasp TEXT NOT NULL,
    grasp_distance_in REAL, grasp_orientation_deg REAL, appearance_round INTEGER, appearance_area_in2 REAL,
    appearance_elongation REAL);
CREATE TABLE observations (description_seq INTEGER NOT NULL REFERENCES descriptions(seq) ON DELETE CASCADE,
    feature TEXT NOT NULL, distance_in REAL, orientation_deg REAL, value REAL NOT NULL);
INSERT INTO meta VALUES ('format', 'csl-library/2'), ('learner_version', '7');
INSERT INTO descriptions (id, grasp, grasp_distance_in) VALUES ('mug', 'Front-Wrap', 6);
INSERT INTO observations VALUES (1, 'Width-Degree-1°', 24, 0, 10), (1, 'Front-Hole?', 6, NULL, 1);
"""


def rows(path: Path) -> int:
    with closing(sqlite3.connect(path)) as db:
        return int(db.execute("SELECT count(*) FROM descriptions").fetchone()[0])


def test_a_retried_learn_stores_nothing_and_answers_the_same_id(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects()) as learner:
        assert learner.learn(MUG, "k1") == "mug"
        assert learner.version() == 2
        assert learner.learn(MUG, "k1") == "mug"  # the retry
        assert learner.version() == 2  # nothing changed, nothing for clients to refetch
        assert learner.learn(MUG, "k2") == "mug#2"  # another grasp of a mug is a new encounter
        assert [d.object_id for d in learner.library().descriptions][-2:] == ["mug", "mug#2"]
    assert rows(path) == 6
    with LocalLearner(path) as reopened:  # the key outlives the process that stored it
        assert reopened.learn(MUG, "k2") == "mug#2"
        assert reopened.learn(MUG, "k1") == "mug"
        assert reopened.version() == 3
    assert rows(path) == 6


def test_the_key_is_stored_with_its_row_and_the_version_in_one_transaction(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path) as learner:
        learner.learn(MUG, "k1")
    with closing(sqlite3.connect(path)) as db:
        assert db.execute("SELECT id, learn_key FROM descriptions").fetchall() == [("mug", "k1")]
        assert db.execute("SELECT value FROM meta WHERE key = ?", (VERSION_KEY,)).fetchone() == ("1",)


def test_a_key_already_used_by_a_stored_row_is_unique_in_the_file(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path) as learner:
        learner.learn(MUG, "k1")
    with closing(sqlite3.connect(path)) as db, pytest.raises(sqlite3.IntegrityError):
        db.execute("INSERT INTO descriptions (id, grasp, learn_key) VALUES ('other', 'Front-Wrap', 'k1')")


@pytest.mark.parametrize("key", ["", "x" * 101, "tab\there", 7])
def test_a_bad_key_is_refused_with_one_line_and_nothing_stored(tmp_path: Path, key: object) -> None:
    with LocalLearner(tmp_path / "lib.sqlite") as learner:
        with pytest.raises(ValueError, match="^key: an idempotency key is 1 to 100 printable characters"):
            learner.learn(MUG, key)  # type: ignore[arg-type]
        assert learner.library() == LibrarySnapshot(0, ())


def test_a_store_from_before_learn_keys_opens_upgraded_and_keeps_its_rows(tmp_path: Path) -> None:
    path = tmp_path / "old.sqlite"
    with closing(sqlite3.connect(path)) as db:
        db.executescript(OLD_SCHEMA)
    assert [d.object_id for d in load_library(path)] == ["mug"]
    with LocalLearner(path) as learner:
        assert learner.version() == 7
        assert learner.learn(MUG, "k1") == "mug#2"
        assert learner.learn(MUG, "k1") == "mug#2"
        assert learner.library().descriptions[0] == MUG
    with closing(sqlite3.connect(path)) as db:
        assert db.execute("SELECT id, learn_key FROM descriptions ORDER BY seq").fetchall() == [
            ("mug", None), ("mug#2", "k1")]


def test_ids_continue_from_the_last_one_found_and_skip_imported_ones(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with LibraryStore(path) as store:
        store.add([MUG, desc("mug#3", "Front-Wrap", ("Front-Hole?", P(6, None), 1))])
        assert store.append_learned(MUG, "a") == ("mug#2", True)
        assert store.append_learned(MUG, "b") == ("mug#4", True)  # mug#3 was imported: skipped
        assert store.meta_int(NEXT_SUFFIX + "mug") == 5
        assert store.append_learned(MUG, "a") == ("mug#2", False)
    assert [d.object_id for d in load_library(path)] == ["mug", "mug#3", "mug#2", "mug#4"]


@settings(max_examples=25, deadline=None)
@given(st.lists(st.sampled_from(["k1", "k2", "k3", "k4"]), min_size=1, max_size=12))
def test_any_sequence_of_retries_stores_each_key_once(tmp_path_factory: pytest.TempPathFactory,
                                                      keys: list[str]) -> None:
    path = tmp_path_factory.mktemp("lib") / "lib.sqlite"
    answered: dict[str, str] = {}
    with LocalLearner(path) as learner:
        for key in keys:
            object_id = learner.learn(MUG, key)
            assert answered.setdefault(key, object_id) == object_id
        assert learner.version() == len(set(keys))
    assert rows(path) == len(set(keys))
    assert sorted(answered.values()) == sorted(["mug", *[f"mug#{n}" for n in range(2, len(set(keys)) + 1)]])


def test_the_learn_request_carries_the_key_and_may_omit_it() -> None:
    assert decode_learn_request(encode_learn_request(MUG, "k1")) == (MUG, "k1")
    assert decode_learn_request(encode_learn_request(MUG)) == (MUG, None)
    bad = encode_learn_request(MUG).replace(b'{"v": 1', b'{"v": 1, "key": ""')
    with pytest.raises(ProtocolError, match="^key: an idempotency key"):
        decode_learn_request(bad)
