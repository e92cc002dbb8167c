"""An object's grasp attempts and their idempotency key reach the library store in one
transaction (executive/grasp_attempts.py, ``LocalLearner.record_grasp_attempts``): a
crash between writing the key and writing the attempts neither loses the batch (the
key stored alone would make every retry add nothing) nor counts it twice."""

from __future__ import annotations

import sqlite3
from pathlib import Path
from types import SimpleNamespace
from typing import cast

import pytest

from behaviours.records import ObjectRecord
from behaviours.services import LibraryMatrix
from executive import defaults
from executive.grasp_attempts import LearnedGraspCosts
from learner.costs import GraspCostRecord
from learner.service.local import LocalLearner
from robot_profile import load_profile

EVENTS = [
    {"event": "sense", "object": 0, "seconds": 40.0},
    {"event": "grasp", "object": 0, "grasp": "Front-Pinch", "success": False, "seconds": 30.0},
    {"event": "grasp", "object": 0, "grasp": "Front-Wrap", "success": True, "seconds": 50.0},
]
RECORDED = [GraspCostRecord("Front-Pinch", 0, 0.0, 1, 30.0), GraspCostRecord("Front-Wrap", 1, 50.0, 0, 0.0)]
OBJECT = cast(ObjectRecord, SimpleNamespace(index=0))  # finished() reads the object's index only


class _DiesBeforeTheAttempts:
    """The store's SQLite connection, which fails (a crash: the disk went away) at the
    statement that adds the attempts to the totals, once; everything else passes."""

    def __init__(self, db: sqlite3.Connection) -> None:
        self._db, self.failed = db, False

    def __getattr__(self, name: str) -> object:
        return getattr(self._db, name)

    def __enter__(self) -> sqlite3.Connection:
        return self._db.__enter__()

    def __exit__(self, *exc: object) -> bool | None:
        return self._db.__exit__(*exc)

    def execute(self, sql: str, *args: object) -> sqlite3.Cursor:
        if sql.startswith("INSERT OR REPLACE INTO grasp_costs_by_robot") and not self.failed:
            self.failed = True
            raise sqlite3.OperationalError("disk I/O error (injected)")
        return self._db.execute(sql, *args)  # type: ignore[arg-type]


def _costs(store: Path) -> tuple[LocalLearner, LearnedGraspCosts]:
    knowledge = load_profile(defaults.KNOWLEDGE).knowledge()
    learner = LocalLearner(store, knowledge=knowledge)
    return learner, LearnedGraspCosts(learner, knowledge, LibraryMatrix(learner, knowledge), EVENTS)


def test_a_failure_between_the_key_and_the_attempts_leaves_neither(tmp_path: Path) -> None:
    learner, costs = _costs(tmp_path / "library.sqlite")
    fault = _DiesBeforeTheAttempts(learner._store._db)
    learner._store._db = fault  # type: ignore[assignment]
    with pytest.raises(sqlite3.OperationalError, match="injected"):
        costs.finished(OBJECT)
    assert fault.failed and learner.grasp_costs() == []
    assert [a.as_record() for a in costs.finished(OBJECT)] == [("Front-Pinch", 30.0, False),
                                                               ("Front-Wrap", 50.0, True)]  # the retry
    assert learner.grasp_costs() == RECORDED  # recorded: not lost
    costs.finished(OBJECT)  # retried once more (its reply was lost, say): the key holds
    assert learner.grasp_costs() == RECORDED  # counted once
    learner.close()


def test_after_the_crash_a_reopened_store_takes_the_retry(tmp_path: Path) -> None:
    store = tmp_path / "library.sqlite"
    learner, costs = _costs(store)
    learner._store._db = _DiesBeforeTheAttempts(learner._store._db)  # type: ignore[assignment]
    attempts = [("Front-Wrap", 50.0, True)]
    with pytest.raises(sqlite3.OperationalError):
        learner.record_grasp_attempts(attempts, key="episode/0")
    learner.close()
    again = LocalLearner(store)  # the service restarted on the same file
    again.record_grasp_attempts(attempts, key="episode/0")
    again.record_grasp_attempts(attempts, key="episode/0")
    assert again.grasp_costs() == [GraspCostRecord("Front-Wrap", 1, 50.0, 0, 0.0)]
    again.close()
