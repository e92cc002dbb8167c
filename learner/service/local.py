"""The in-process learner service: the library in a SQLite ``LibraryStore``.

One store connection is kept open and every call takes one lock: the zenoh node calls
in from zenoh's threads, and the lock serialises them on that connection. Reads are
served from an immutable in-memory snapshot, extended (never reloaded) after each
learn, so ``library()`` and ``version()`` never touch the disk and a learn costs the
same whatever the library's size.

The version lives in the store's ``meta`` table, so it survives restarts and a robot
that cached a snapshot before a restart still sees the next change. It is written in
the same transaction as the learned description (and its idempotency key): a crash
leaves both or neither. While a ``LocalLearner`` is open it is the store's only
expected writer; descriptions imported behind its back are seen after a restart.

Each learn may carry an idempotency key, made once per grasped object by the client:
a retried learn (the reply was lost, the service restarted) finds the key in the store
and answers the id the first attempt stored, storing nothing and leaving the version
alone, so a retry never duplicates a description.

Given the robot's ``knowledge``, the learner admits only descriptions that robot can use
(:mod:`learner.service.admission`) and quarantines stored ones that fail: they stay in
the file, listed in :attr:`LocalLearner.quarantined`, and are never served, so one bad
row cannot stop every robot that reads the library.
"""

from __future__ import annotations

import threading
from collections.abc import Sequence
from dataclasses import replace
from pathlib import Path

from learner.costs import GraspCostRecord, implausible_attempt
from learner.description import Descriptions, ObjectDescription
from learner.knowledge import Knowledge
from learner.library.checks import check_library
from learner.library.store import LibraryStore
from learner.service.admission import Quarantined, admitted, partition
from learner.service.interface import (LibraryChanges, LibrarySnapshot, check_grasp_attempts, check_learn_key,
                                       check_robot_name)

VERSION_KEY = "learner_version"
"""The ``meta`` row holding the library's version (absent means 0)."""
GRASP_RECORD_KEY = "grasp_record:"
"""``meta`` keys ``grasp_record:<key>``: the idempotency keys of grasp-cost records made."""


class LocalLearner:
    """A :class:`~learner.service.interface.LearnerService` on one SQLite file.

    ``seed_library`` is imported when the store holds no description yet, so a fresh
    robot starts from the shipped example library while a used store is never
    overwritten. ``knowledge`` is the robot the library serves: with it, ``learn``
    refuses what that robot cannot use and a stored description it cannot use is
    quarantined at opening (see :attr:`quarantined`); without it only the library
    format is checked.
    """

    quarantined: tuple[Quarantined, ...]
    """Stored descriptions not served, with why: reported when the service starts,
    kept in the file for a person to repair or delete."""

    def __init__(self, store_path: str | Path,
                 seed_library: Sequence[ObjectDescription] | None = None, *,
                 knowledge: Knowledge | None = None) -> None:
        self.path = Path(store_path)
        self.knowledge = knowledge
        self._lock = threading.Lock()
        self._closed = False
        self._store = LibraryStore(self.path)
        try:
            stored = self._store.descriptions()
            if seed_library and not stored:
                if knowledge is not None:
                    check_library(seed_library, knowledge, "the seed library")
                self._bump_version()
                self._store.add(list(seed_library))
                stored = self._store.descriptions()
            served, refused = partition(stored, knowledge, str(self.path))
            self.quarantined = (*(Quarantined(i, why) for i, why in self._store.undecodable), *refused)
            if self.quarantined:  # what clients cached may hold a quarantined row: make them refetch
                self._bump_version()
            self._snapshot = LibrarySnapshot(self._stored_version(), Descriptions(served))
            # since opening, each version is one learned description more than the last
            self._opened = (self._snapshot.version, len(served))
        except BaseException:
            self._store.close()
            raise

    def library(self) -> LibrarySnapshot:
        with self._lock:
            self._check_open()
            return self._snapshot

    def version(self) -> int:
        with self._lock:
            self._check_open()
            return self._snapshot.version

    def changes(self, since: int) -> LibraryChanges:
        """The descriptions learned after version ``since``: a slice of the snapshot,
        so the cost is that of the change. Only versions from this opening on are known
        change by change; for any other ``since`` the answer is the whole library."""
        with self._lock:
            self._check_open()
            snapshot = self._snapshot
        opened_version, opened_count = self._opened
        if not opened_version <= since <= snapshot.version:
            return LibraryChanges(snapshot.version, 0, snapshot.descriptions)
        start = opened_count + since - opened_version
        return LibraryChanges(snapshot.version, start, snapshot.descriptions[start:])

    def learn(self, description: ObjectDescription, key: str | None = None) -> str:
        checked = admitted(description, self.knowledge, "not learned")  # before anything is written
        if key is not None:
            check_learn_key(key)
        with self._lock:
            self._check_open()
            version = self._snapshot.version + 1
            object_id, stored = self._store.append_learned(checked, key, [(VERSION_KEY, str(version))])
            if stored:
                # Appended, not reloaded: a reload would serve the quarantined rows again.
                self._snapshot = LibrarySnapshot(
                    version, self._snapshot.descriptions.plus([replace(checked, object_id=object_id)]))
        return object_id

    def record_grasp_attempts(self, attempts: Sequence[tuple[str, float, bool]], key: str | None = None,
                              robot: str | None = None) -> None:
        """Add ``(grasp, robot seconds, success)`` attempts to the store's per-grasp cost
        totals (docs/library-format.md, "Grasp costs"); the library's version is not
        bumped: descriptions did not change. Checked whole before anything is written
        (:func:`~learner.service.interface.check_grasp_attempts`, and with ``knowledge``
        every grasp must be the robot's and every duration plausible for it,
        :func:`~learner.costs.implausible_attempt`). A ``key`` already recorded adds nothing; the
        key and the attempts are written in one transaction, so a crash neither loses
        the batch nor lets its retry count it twice."""
        checked = check_grasp_attempts(list(attempts))
        if self.knowledge is not None:
            for i, (grasp, seconds, success) in enumerate(checked):
                if not self.knowledge.has_grasp(grasp):
                    raise ValueError(f"grasp costs not recorded: grasp {grasp!r} is not in the knowledge file "
                                     f"{self.knowledge.source}")
                why = implausible_attempt(self.knowledge, grasp, seconds, success)
                if why is not None:
                    raise ValueError(f"grasp costs not recorded: attempts[{i}]: {why}")
        if key is not None:
            check_learn_key(key)
        if robot is not None:
            check_robot_name(robot)
        with self._lock:
            self._check_open()
            self._store.record_grasp_attempts(checked, None if key is None else GRASP_RECORD_KEY + key, robot or "")

    def grasp_costs(self) -> list[GraspCostRecord]:
        """What each grasp has cost so far, for :func:`learner.costs.with_learned_grasp_costs`."""
        with self._lock:
            self._check_open()
            return self._store.grasp_cost_records()

    def close(self) -> None:
        with self._lock:
            if not self._closed:
                self._closed = True
                self._store.close()

    def __enter__(self) -> LocalLearner:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _check_open(self) -> None:
        if self._closed:
            raise ValueError(f"{self.path}: the learner is closed")

    def _stored_version(self) -> int:
        return self._store.meta_int(VERSION_KEY)

    def _bump_version(self) -> int:
        """Add one to the stored version in its own committed transaction."""
        version = self._stored_version() + 1
        self._store.set_meta(VERSION_KEY, str(version))
        return version

