"""The in-process learner service: learning, versions, id clashes, persistence and
concurrent robots, on a real SQLite file."""

from __future__ import annotations

import threading
from pathlib import Path

import pytest

from learner.library import LibraryStore, load_library
from learner.service import LearnerService, LibrarySnapshot, LocalLearner
from tests.learner.fixtures import P, desc, four_objects

MUG = desc("mug", "Front-Wrap", ("Width-Degree-1°", P(24, 0), 10), ("Handle?", P(6, None), 1))


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
