"""The in-process learner service: learning, versions, id clashes, persistence and
concurrent robots, on a real SQLite file."""

from __future__ import annotations

import dataclasses
import sqlite3
import threading
from contextlib import closing
from pathlib import Path

import pytest

from learner.appearance import Appearance
from learner.library.store import LibraryStore, load_library
from learner.service import LearnerService, LibrarySnapshot, LocalLearner
from learner.service.local import VERSION_KEY
from tests.learner.fixtures import P, desc, four_objects, hero

# Fits the HERO 2000 profile the service checks against by default.
MUG = desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 10), ("Front-Hole?", P(6, None), 1))


def test_an_empty_store_without_seed_starts_at_version_zero(tmp_path: Path) -> None:
    with LocalLearner(tmp_path / "lib.sqlite") as learner:
        assert learner.library() == LibrarySnapshot(0, ())
        assert learner.version() == 0


def test_seed_is_imported_into_an_empty_store_only(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects()) as learner:
        assert learner.library() == LibrarySnapshot(1, tuple(four_objects()))
        learner.learn(MUG)
    with LocalLearner(path, seed_library=four_objects()) as reopened:  # not imported twice
        assert [d.object_id for d in reopened.library().descriptions] == ["cup", "box", "tumbler", "closed", "mug"]
        assert reopened.version() == 2


def test_learn_stores_the_description_and_bumps_the_version(tmp_path: Path) -> None:
    with LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects()) as learner:
        before = learner.library()
        assert learner.learn(MUG) == "mug"
        after = learner.library()
    assert after.version == before.version + 1
    assert after.descriptions == (*four_objects(), MUG)
    assert before.descriptions == tuple(four_objects())  # an old snapshot never changes


def test_an_id_clash_is_a_new_encounter_stored_under_the_next_free_id(tmp_path: Path) -> None:
    cup = four_objects()[0]
    with LocalLearner(tmp_path / "lib.sqlite", seed_library=four_objects()) as learner:
        assert learner.learn(cup) == "cup#2"
        assert learner.learn(cup) == "cup#3"
        ids = [d.object_id for d in learner.library().descriptions]
    assert ids[-2:] == ["cup#2", "cup#3"] and ids.count("cup") == 1


def test_version_and_descriptions_survive_reopening(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path) as learner:
        learner.learn(MUG)
        learner.learn(MUG)
        snapshot = learner.library()
    with LocalLearner(path) as reopened:
        assert reopened.library() == snapshot == LibrarySnapshot(2, (MUG, desc("mug#2", "Front-Wrap", *[
            (o.feature, o.position, o.value) for o in MUG.observations])))
    assert [d.object_id for d in load_library(path)] == ["mug", "mug#2"]  # the plain store agrees


@pytest.mark.parametrize(
    ("bad", "message"),
    [
        (desc("", "Front-Wrap"), "missing or empty string field 'id'"),
        (desc("nan", "Front-Wrap", ("Height", P(6, None), float("nan"))), "'value' must be a finite number"),
    ],
)
def test_a_description_that_cannot_be_stored_changes_nothing(tmp_path: Path, bad, message: str) -> None:  # noqa: ANN001
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects()) as learner:
        with pytest.raises(ValueError, match=message):
            learner.learn(bad)
        assert learner.library() == LibrarySnapshot(1, tuple(four_objects()))
    with LibraryStore(path) as store:
        assert store.descriptions() == four_objects()


def test_robots_learning_at_once_each_keep_their_description(tmp_path: Path) -> None:
    learner = LocalLearner(tmp_path / "lib.sqlite")
    ids: list[str] = []
    barrier = threading.Barrier(8)

    def robot() -> None:
        barrier.wait()
        ids.append(learner.learn(MUG))

    threads = [threading.Thread(target=robot) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(ids) == sorted(["mug", *(f"mug#{n}" for n in range(2, 9))])
    assert learner.version() == 8 and len(learner.library().descriptions) == 8
    learner.close()


def test_a_closed_learner_refuses_calls(tmp_path: Path) -> None:
    learner: LearnerService = LocalLearner(tmp_path / "lib.sqlite")
    learner.close()
    with pytest.raises(ValueError, match="closed"):
        learner.version()


# -- admission against the robot's knowledge -----------------------------
HERO_REFUSALS = [
    # Width-Degree-1° spans a few dozen degrees on the HERO 2000 profile: 1e308 is out.
    (desc("huge", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 1e308)),
     r"Width-Degree-1°\(24,0\) = 1e\+308 is outside"),
    (desc("nan", "Front-Wrap", ("Height", P(6, None), float("nan"))), "'value' must be a finite number"),
    (desc("inf", "Front-Wrap", ("Height", P(6, None), float("inf"))), "'value' must be a finite number"),
    (desc("colour", "Front-Wrap", ("Colour", P(6, None), 3)), "feature 'Colour' is not yielded"),
    (desc("magic", "Levitate", ("Height", P(6, None), 3)), "grasp 'Levitate' is not in the knowledge file"),
    (desc("hole", "Front-Wrap", ("Top-Hole?", P(6, None), 0.5)), "Top-Hole. is 0 or 1, got 0.5"),
    # D-Scan-0.3 measures Height only at 6 in; Front-Wrap grasps only at 6 in.
    (desc("far", "Front-Wrap", ("Height", P(60, None), 3)),
     r"Height\(60,\*\): distance 60 in is outside D-Scan-0.3's range \[6, 6\]"),
    (desc("reach", "Front-Wrap", at=P(24, None)),
     r"grasp_position \(24,\*\): distance 24 in is outside Front-Wrap's range"),
    (desc("x" * 201, "Front-Wrap"), "id is 201 characters, at most 200"),
    (desc("many", "Front-Wrap", *[("Height", P(6, o / 10), 3) for o in range(1001)]),
     "features: 1001 observations, at most 1000"),
]


@pytest.mark.parametrize(("bad", "message"), HERO_REFUSALS, ids=[d.object_id[:8] for d, _ in HERO_REFUSALS])
def test_a_description_the_robot_cannot_use_is_refused_and_nothing_is_stored(
        tmp_path: Path, bad, message: str) -> None:  # noqa: ANN001
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects(), knowledge=hero()) as learner:
        with pytest.raises(ValueError, match=message) as err:
            learner.learn(bad)
        assert "\n" not in str(err.value)
        assert learner.library() == LibrarySnapshot(1, tuple(four_objects()))
        assert learner.learn(MUG) == "mug"  # a good one after a bad one is stored
        assert learner.library() == LibrarySnapshot(2, (*four_objects(), MUG))
    with LibraryStore(path) as store:
        assert store.descriptions() == [*four_objects(), MUG]


def test_a_lesson_known_only_by_its_appearance_is_admitted_and_kept(tmp_path: Path) -> None:
    # what Learn saves when grasps failed cleanly and the one that held needed no sensing
    lesson = dataclasses.replace(desc("learned/Top-Vert-Grip", "Top-Vert-Grip", at=P(6, 0)),
                                 appearance=Appearance(True, 8.96, 1.239))
    path = tmp_path / "lib.sqlite"
    with LocalLearner(path, seed_library=four_objects(), knowledge=hero()) as learner:
        assert learner.learn(lesson) == "learned/Top-Vert-Grip"
    with LocalLearner(path, knowledge=hero()) as reopened:
        kept = reopened.library().descriptions[-1]
    assert kept == lesson and kept.observations == () and kept.appearance == Appearance(True, 8.96, 1.239)


def test_without_knowledge_only_the_format_is_checked(tmp_path: Path) -> None:
    with LocalLearner(tmp_path / "lib.sqlite") as learner:
        assert learner.learn(desc("colour", "Front-Wrap", ("Colour", P(6, None), 3))) == "colour"
        with pytest.raises(ValueError, match="'value' must be a finite number"):
            learner.learn(desc("inf", "Front-Wrap", ("Height", P(6, None), float("inf"))))


def test_a_seed_the_robot_cannot_use_is_refused_before_anything_is_written(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    with pytest.raises(ValueError, match="the seed library: description 'colour': feature 'Colour'"):
        LocalLearner(path, seed_library=[MUG, desc("colour", "Front-Wrap", ("Colour", P(6, None), 3))],
                     knowledge=hero())
    assert load_library(path) == []


POISON = [desc("huge", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 1e308)),
          desc("inf", "Front-Wrap", ("Height", P(6, None), float("inf"))),
          desc("colour", "Front-Wrap", ("Colour", P(6, None), 3))]


def poisoned_store(path: Path) -> None:
    """A store written before admission existed: good rows around bad ones, version 1."""
    with LibraryStore(path) as store:
        store.add([*four_objects()[:2], *POISON, *four_objects()[2:]])
    with closing(sqlite3.connect(path)) as db, db:  # as the old service did before writing
        db.execute("INSERT INTO meta VALUES (?, '1')", (VERSION_KEY,))


def test_a_poisoned_store_serves_its_good_descriptions_and_quarantines_the_rest(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    poisoned_store(path)
    with LocalLearner(path, seed_library=[MUG], knowledge=hero()) as learner:
        assert [(q.object_id, q.reason.split(": ", 2)[2]) for q in learner.quarantined] == [
            ("huge", "Width-Degree-1°(24,0) = 1e+308 is outside [0, 180]"),
            ("inf", "features[0]: 'value' must be a finite number, got inf"),
            ("colour", f"feature 'Colour' is not yielded by any sensing procedure in {hero().source}"),
        ]
        # served: the good ones; the version moved so no client keeps a cached bad row
        assert learner.library() == LibrarySnapshot(2, tuple(four_objects()))
        assert learner.learn(MUG) == "mug"
        assert learner.library() == LibrarySnapshot(3, (*four_objects(), MUG))
    with LibraryStore(path) as store:  # quarantined, not deleted
        assert [d.object_id for d in store.descriptions()] == ["cup", "box", "huge", "inf", "colour", "tumbler",
                                                               "closed", "mug"]


def test_without_knowledge_a_poisoned_store_quarantines_what_breaks_the_format(tmp_path: Path) -> None:
    path = tmp_path / "lib.sqlite"
    poisoned_store(path)
    with LocalLearner(path) as learner:
        assert [q.object_id for q in learner.quarantined] == ["inf"]
        assert [d.object_id for d in learner.library().descriptions] == ["cup", "box", "huge", "colour", "tumbler",
                                                                        "closed"]


def test_a_stored_row_no_description_may_hold_is_quarantined_and_the_rest_served(tmp_path: Path) -> None:
    """A row edited by hand to a negative footprint area (the appearance check refuses
    it when the row is built) is left out and named; the other two are served."""
    from executive.defaults import EXAMPLE_LIBRARY
    from learner.library.format import read_library_json

    store = tmp_path / "library.sqlite"
    three = read_library_json(EXAMPLE_LIBRARY)[:3]
    with LibraryStore(store) as opened:
        opened.add(three)
    with closing(sqlite3.connect(store)) as db, db:
        db.execute("UPDATE descriptions SET appearance_area_in2 = -1 WHERE id = ?", (three[1].object_id,))
    service = LocalLearner(store)
    try:
        assert [d.object_id for d in service.library().descriptions] == [three[0].object_id, three[2].object_id]
        (bad,) = service.quarantined
        assert bad.object_id == three[1].object_id
        assert bad.reason == "appearance area must be a positive number of square inches, got -1.0"
    finally:
        service.close()
