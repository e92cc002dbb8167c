"""The in-process learner service: the library in a SQLite ``LibraryStore``.

Every call opens its own short-lived connection under one lock instead of sharing a
long-lived one: the zenoh node calls in from zenoh's threads, a SQLite connection
belongs to the thread that made it, and a learn happens once per grasp (seconds to
minutes apart), so the millisecond an open costs is nothing. Reads are served from an
immutable in-memory snapshot, rebuilt after each learn, so ``library()`` and
``version()`` never touch the disk.

The version lives in the store's ``meta`` table, so it survives restarts and a robot
that cached a snapshot before a restart still sees the next change. It is bumped in
its own transaction *before* the description is added: a crash between the two then
costs clients one needless refetch, where the other order could hide a committed
description behind an unchanged version. While a ``LocalLearner`` is open it is the
store's only expected writer; descriptions imported behind its back are seen after a
restart.

Given the robot's ``knowledge``, the learner admits only descriptions that robot can use
(:mod:`learner.service.admission`) and quarantines stored ones that fail: they stay in
the file, listed in :attr:`LocalLearner.quarantined`, and are never served, so one bad
row cannot stop every robot that reads the library.
"""

from __future__ import annotations

import sqlite3
import threading
from collections.abc import Sequence
from contextlib import closing
from dataclasses import replace
from pathlib import Path

from learner.description import ObjectDescription
from learner.knowledge import Knowledge
from learner.library import LibraryStore, check_library
from learner.service.admission import Quarantined, admitted, partition
from learner.service.interface import LibrarySnapshot

VERSION_KEY = "learner_version"
"""The ``meta`` row holding the library's version (absent means 0)."""


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
        with LibraryStore(self.path) as store:
            stored = store.descriptions()
            if seed_library and not stored:
                if knowledge is not None:
                    check_library(seed_library, knowledge, "the seed library")
                self._bump_version()
                store.add(list(seed_library))
                stored = store.descriptions()
        served, self.quarantined = partition(stored, knowledge, str(self.path))
        if self.quarantined:  # what clients cached may hold a quarantined row: make them refetch
            self._bump_version()
        self._snapshot = LibrarySnapshot(self._stored_version(), served)

    def library(self) -> LibrarySnapshot:
        with self._lock:
            self._check_open()
            return self._snapshot

    def version(self) -> int:
        with self._lock:
            self._check_open()
            return self._snapshot.version

    def learn(self, description: ObjectDescription) -> str:
        checked = admitted(description, self.knowledge, "not learned")  # before anything is written
        with self._lock:
            self._check_open()
            with LibraryStore(self.path) as store:
                stored = replace(checked, object_id=store.unique_id(checked.object_id))
                version = self._bump_version()
                store.add([stored])
            # Appended, not reloaded: a reload would serve the quarantined rows again.
            self._snapshot = LibrarySnapshot(version, (*self._snapshot.descriptions, stored))
        return stored.object_id

    def close(self) -> None:
        with self._lock:
            self._closed = True

    def __enter__(self) -> LocalLearner:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _check_open(self) -> None:
        if self._closed:
            raise ValueError(f"{self.path}: the learner is closed")

    def _stored_version(self) -> int:
        with closing(sqlite3.connect(self.path)) as db:
            row = db.execute("SELECT value FROM meta WHERE key = ?", (VERSION_KEY,)).fetchone()
        return 0 if row is None else int(row[0])

    def _bump_version(self) -> int:
        """Add one to the stored version in its own committed transaction."""
        with closing(sqlite3.connect(self.path)) as db, db:
            row = db.execute("SELECT value FROM meta WHERE key = ?", (VERSION_KEY,)).fetchone()
            version = 1 if row is None else int(row[0]) + 1
            db.execute("INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)", (VERSION_KEY, str(version)))
        return version

