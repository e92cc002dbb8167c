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
"""

from __future__ import annotations

import sqlite3
import threading
from collections.abc import Sequence
from contextlib import closing
from dataclasses import replace
from pathlib import Path

from learner.description import ObjectDescription
from learner.library import LibraryStore, descriptions_from_json, descriptions_to_json
from learner.service.interface import LibrarySnapshot

VERSION_KEY = "learner_version"
"""The ``meta`` row holding the library's version (absent means 0)."""


class LocalLearner:
    """A :class:`~learner.service.interface.LearnerService` on one SQLite file.

    ``seed_library`` is imported when the store holds no description yet, so a fresh
    robot starts from the shipped example library while a used store is never
    overwritten.
    """

    def __init__(self, store_path: str | Path,
                 seed_library: Sequence[ObjectDescription] | None = None) -> None:
        self.path = Path(store_path)
        self._lock = threading.Lock()
        self._closed = False
        with LibraryStore(self.path) as store:
            if seed_library and not store.descriptions():
                self._bump_version()
                store.add(list(seed_library))
            self._snapshot = LibrarySnapshot(self._stored_version(), tuple(store.descriptions()))

    def library(self) -> LibrarySnapshot:
        with self._lock:
            self._check_open()
            return self._snapshot

    def version(self) -> int:
        with self._lock:
            self._check_open()
            return self._snapshot.version

    def learn(self, description: ObjectDescription) -> str:
        checked = _storable(description)
        with self._lock:
            self._check_open()
            with LibraryStore(self.path) as store:
                stored = replace(checked, object_id=store.unique_id(checked.object_id))
                version = self._bump_version()
                store.add([stored])
                self._snapshot = LibrarySnapshot(version, tuple(store.descriptions()))
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


def _storable(description: ObjectDescription) -> ObjectDescription:
    """``description`` as the library JSON would give it back, or ValueError.

    Every stored description must survive ``csl library export`` and the zenoh
    protocol, so it goes through the same validation as a library file (an empty
    id, a NaN value), checked before anything is written.
    """
    return descriptions_from_json(descriptions_to_json([description]), "learn")[0]
