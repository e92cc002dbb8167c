"""The library's SQLite store: what a running robot appends to after every grasp.

Each write is one transaction, so a crash mid-write loses nothing that was committed and
leaves no half-written description behind. The store keeps the descriptions (with a
learn's idempotency key), a per-grasp record of what grasps have cost, and a ``meta``
table (the format and version, the service's version counter). Its format name and
versions are the JSON format's (``learner.library.format``); :func:`load_library` reads
either kind of file.
"""

from __future__ import annotations

import array
import dataclasses
import functools
import sqlite3
import sys
from collections.abc import Callable, Iterable, Sequence
from pathlib import Path
from typing import TypeVar

from learner.appearance import Appearance
from learner.costs import ROBOT_WEIGHT, GraspCostRecord
from learner.description import ObjectDescription, Observation, in_order
from learner.library.backup import damage_line, problems
from learner.library.format import FORMAT, READS, VERSION, read_library_json
from learner.position import Position

_SCHEMA = """
CREATE TABLE IF NOT EXISTS meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE IF NOT EXISTS descriptions (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    id TEXT NOT NULL UNIQUE,
    grasp TEXT NOT NULL,
    grasp_distance_in REAL,
    grasp_orientation_deg REAL,
    appearance_round INTEGER,
    appearance_area_in2 REAL,
    appearance_elongation REAL
);
CREATE TABLE IF NOT EXISTS observations (
    description_seq INTEGER NOT NULL REFERENCES descriptions(seq) ON DELETE CASCADE,
    feature TEXT NOT NULL,
    distance_in REAL,
    orientation_deg REAL,
    value REAL NOT NULL
);
CREATE INDEX IF NOT EXISTS observations_by_description ON observations(description_seq);
CREATE TABLE IF NOT EXISTS observation_codes (
    code INTEGER PRIMARY KEY,
    feature TEXT NOT NULL,
    distance_in REAL,
    orientation_deg REAL,
    value REAL NOT NULL
);
"""

_CODED = "observation_codes"
"""The ``descriptions`` column holding each description's observations as codes into
the ``observation_codes`` table (little-endian int32, in :func:`in_order` order).

A 100,000-description library has some 1.8 million observation rows but only about
12,000 distinct observations (values are kept to 0.1): reading the rows one by one
costs seconds, reading one blob per description and a small table of distinct
observations costs a fraction of one, and each distinct observation is one shared
object in memory. The ``observations`` table stays the record an older csl reads and
writes; a row it wrote has no codes, and gains them when this csl next opens the
store (:meth:`LibraryStore._code_uncoded`)."""

_LEARN_KEYS = "CREATE UNIQUE INDEX IF NOT EXISTS descriptions_by_learn_key ON descriptions(learn_key)"
"""Each learn's idempotency key is stored on its row (NULL for imported descriptions),
unique, so a retried learn finds what the first attempt stored."""

NEXT_SUFFIX = "next_suffix:"
"""``meta`` keys ``next_suffix:<stem>``: where :meth:`LibraryStore.unique_id` starts
looking for a free ``stem#n``, so naming the 100,000th encounter of an object costs
what naming the second did."""

T = TypeVar("T")

_SET_META = "INSERT OR REPLACE INTO meta (key, value) VALUES (?, ?)"

_GRASP_COSTS = """CREATE TABLE IF NOT EXISTS grasp_costs (grasp TEXT PRIMARY KEY, successes INTEGER NOT NULL,
    success_s REAL NOT NULL, failures INTEGER NOT NULL, failure_s REAL NOT NULL)"""
"""Per grasp, the attempts that held and failed and the robot seconds they cost
(learner.costs.GraspCostRecord), the fleet's: the sum over ``grasp_costs_by_robot``,
kept beside it so a reader needs no sum (and a csl from before robots reads it as
ever); made by the first record, absent before."""

_GRASP_COSTS_BY_ROBOT = """CREATE TABLE IF NOT EXISTS grasp_costs_by_robot (grasp TEXT NOT NULL,
    robot TEXT NOT NULL, successes INTEGER NOT NULL, success_s REAL NOT NULL, failures INTEGER NOT NULL,
    failure_s REAL NOT NULL, PRIMARY KEY (grasp, robot))"""
"""Per grasp and robot, what that robot's attempts weigh, at most ``ROBOT_WEIGHT``
attempts (learner.costs); robot ``''`` holds attempts recorded without a robot's
name, and a store's totals from before robots were named (one anonymous robot)."""


def durable_and_quick(db: sqlite3.Connection) -> None:
    """Write-ahead logging with a sync on every commit: a committed learn survives a
    crash or power loss as before, for one fsync instead of the rollback journal's
    several (a one-row commit on the development machine, idle: 1.2 ms against 5.9 ms),
    and readers never wait for the writer."""
    db.execute("PRAGMA journal_mode = WAL")
    db.execute("PRAGMA synchronous = FULL")


def _refusing_damage(read: Callable[[LibraryStore], T]) -> Callable[[LibraryStore], T]:
    """A read of the store whose failures on a damaged file become the store's
    one-line refusal instead of a traceback: SQLite's errors (a page damaged inside,
    text that is no longer UTF-8), and rows that no longer decode (a code with no
    observation, a column of another type, a blob cut short)."""

    @functools.wraps(read)
    def checked(self: LibraryStore) -> T:
        try:
            return read(self)
        except (sqlite3.DatabaseError, KeyError, TypeError, ValueError) as exc:
            raise self._damaged(exc) from None

    return checked


class LibraryStore:
    """A persistent library in one SQLite file (``NULL`` stands for ``*``)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        self._codes: dict[tuple[str, float | None, float | None, float], int] | None = None  # read when needed
        self.undecodable: list[tuple[str, str]] = []  # rows the last descriptions() left out: (id, why)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            # one connection used from whichever thread holds the owner's lock (the zenoh
            # node answers from zenoh's threads); LocalLearner serialises every call
            self._db = sqlite3.connect(self.path, check_same_thread=False, timeout=10.0)
            found = problems(self._db)  # a damaged store is refused, not served (learner.library.backup)
            if found:
                self._db.close()
                raise ValueError(damage_line(self.path, found))
            self._db.execute("PRAGMA foreign_keys = ON")
            durable_and_quick(self._db)
            with self._db:
                self._db.executescript(_SCHEMA)
                self._db.execute("INSERT OR IGNORE INTO meta VALUES ('format', ?)", (f"{FORMAT}/{VERSION}",))
                fmt = self._db.execute("SELECT value FROM meta WHERE key='format'").fetchone()[0]
                if fmt == f"{FORMAT}/1":
                    self._upgrade_from_1()
                    fmt = f"{FORMAT}/{VERSION}"
                if fmt == f"{FORMAT}/{VERSION}":
                    self._add_columns()
        except sqlite3.DatabaseError as exc:
            raise self._damaged(exc) from None
        if fmt != f"{FORMAT}/{VERSION}":
            raise ValueError(f"{self.path}: library format {fmt!r}, this csl reads "
                             f"{', '.join(f'{FORMAT}/{v}' for v in READS)}")

    def _upgrade_from_1(self) -> None:
        """A version-1 store gains the appearance columns (NULL: not recorded), in the
        opening transaction: its descriptions load as before, new ones keep theirs."""
        for column, kind in (("appearance_round", "INTEGER"), ("appearance_area_in2", "REAL"),
                             ("appearance_elongation", "REAL")):
            self._db.execute(f"ALTER TABLE descriptions ADD COLUMN {column} {kind}")
        self._db.execute("UPDATE meta SET value = ? WHERE key = 'format'", (f"{FORMAT}/{VERSION}",))

    def _add_columns(self) -> None:
        """A store from before idempotent learning gains the ``learn_key`` column (NULL:
        no key) and its unique index, one from before observation codes the
        :data:`_CODED` column, filled; all in the opening transaction. An older csl still
        reads and writes the upgraded file (it names its columns)."""
        columns = {row[1] for row in self._db.execute("PRAGMA table_info(descriptions)")}
        if "learn_key" not in columns:
            self._db.execute("ALTER TABLE descriptions ADD COLUMN learn_key TEXT")
        self._db.execute(_LEARN_KEYS)
        if _CODED not in columns:
            self._db.execute(f"ALTER TABLE descriptions ADD COLUMN {_CODED} BLOB")
        self._code_uncoded()

    def _code_uncoded(self) -> None:
        """Give every description without observation codes (a store from before them,
        or rows an older csl added) its codes, in the opening transaction: the cost of
        one full read, once."""
        seqs = [seq for (seq,) in self._db.execute(f"SELECT seq FROM descriptions WHERE {_CODED} IS NULL")]
        for seq in seqs:
            observations = in_order(self._observations_of(seq))
            self._db.execute(f"UPDATE descriptions SET {_CODED} = ? WHERE seq = ?",
                             (self._coded(observations), seq))

    def _observations_of(self, seq: int) -> list[Observation]:
        """One description's rows of the ``observations`` table."""
        return [Observation(sys.intern(f), Position(d, o), v) for f, d, o, v in self._db.execute(
            "SELECT feature, distance_in, orientation_deg, value FROM observations WHERE description_seq = ?",
            (seq,))]

    def _coded(self, observations: Sequence[Observation]) -> bytes:
        """The codes blob of ``observations`` (in the given order), adding any
        observation not yet coded to ``observation_codes`` in the caller's transaction."""
        if self._codes is None:
            self._codes = {(f, d, o, v): code for code, f, d, o, v in self._db.execute(
                "SELECT code, feature, distance_in, orientation_deg, value FROM observation_codes")}
        codes = array.array("i")
        for obs in observations:
            key = (obs.feature, obs.position.distance_in, obs.position.orientation_deg, obs.value)
            code = self._codes.get(key)
            if code is None:
                code = self._db.execute("INSERT INTO observation_codes (feature, distance_in, orientation_deg, value)"
                                        " VALUES (?,?,?,?)", key).lastrowid
                self._codes[key] = code
            codes.append(code)
        return _little_endian(codes).tobytes()

    def close(self) -> None:
        self._db.close()

    def __enter__(self) -> LibraryStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _damaged(self, exc: Exception) -> ValueError:
        """The one-line refusal of a file that cannot be read as a library: not a
        database, or one damaged inside. Only the message's first line: a damaged
        schema's message goes on with its SQL, newlines and all."""
        text = (str(exc).strip().splitlines() or [""])[0]
        reason = text if isinstance(exc, sqlite3.DatabaseError) else \
            f"a row does not decode ({type(exc).__name__}: {text})"
        return ValueError(f"{self.path}: not a csl library database: {reason}")

    @_refusing_damage
    def descriptions(self) -> list[ObjectDescription]:
        """Every description, in the order they were added; a row whose values no
        description may hold is left out and listed in :attr:`undecodable` (id, reason),
        so one bad row does not take the rest of the library with it.

        Each description's observations come from its codes (:data:`_CODED`), each
        distinct observation built once and shared; a row without codes (added by an
        older csl while this store was open) is read from ``observations``.
        """
        positions: dict[tuple[float | None, float | None], Position] = {}  # one object per position
        by_code: dict[int, Observation] = {}
        for code, feature, d, o, v in self._db.execute(
                "SELECT code, feature, distance_in, orientation_deg, value FROM observation_codes"):
            position = positions.get((d, o)) or positions.setdefault((d, o), Position(d, o))
            by_code[code] = Observation(sys.intern(feature), position, v)
        decode = by_code.__getitem__
        out = []
        self.undecodable = []
        for seq, i, g, d, o, r, a, e, coded in self._db.execute(
                "SELECT seq, id, grasp, grasp_distance_in, grasp_orientation_deg, appearance_round,"
                f" appearance_area_in2, appearance_elongation, {_CODED} FROM descriptions ORDER BY seq"):
            observations = (in_order(self._observations_of(seq)) if coded is None
                            else tuple(map(decode, _little_endian(array.array("i", coded)))))
            try:  # values no description may hold (written by hand, or by a csl without the check)
                position = positions.get((d, o)) or positions.setdefault((d, o), Position(d, o))
                out.append(ObjectDescription(i, sys.intern(g), position, observations,
                                             None if r is None else Appearance(bool(r), a, e)))
            except ValueError as exc:
                self.undecodable.append((str(i), str(exc).splitlines()[0] if str(exc) else type(exc).__name__))
        return out

    def meta_int(self, key: str) -> int:
        """An integer kept in ``meta`` (0 when absent)."""
        row = self._db.execute("SELECT value FROM meta WHERE key = ?", (key,)).fetchone()
        return 0 if row is None else int(row[0])

    def set_meta(self, key: str, value: str) -> None:
        """Write one ``meta`` row in its own committed transaction."""
        with self._db:
            self._db.execute(_SET_META, (key, value))

    def learned(self, key: str) -> str | None:
        """The id a learn with idempotency ``key`` was stored under, or None."""
        row = self._db.execute("SELECT id FROM descriptions WHERE learn_key = ?", (key,)).fetchone()
        return None if row is None else str(row[0])

    def append_learned(self, description: ObjectDescription, key: str | None,
                       meta: Iterable[tuple[str, str]] = ()) -> tuple[str, bool]:
        """Store one learned description under a free id (:meth:`unique_id`) and return
        ``(id, True)``; or, when a learn with ``key`` is already stored, store nothing
        and return ``(its id, False)``.

        The key, the row, its observations and the ``meta`` rows (the service's version)
        are one transaction: a crash leaves either all of them or none, so a retry after
        any failure either finds the key or stores the description for the first time.
        """
        with self._db:
            if key is not None:
                stored = self.learned(key)
                if stored is not None:
                    return stored, False
            object_id = self.unique_id(description.object_id)
            self._insert(dataclasses.replace(description, object_id=object_id), key)
            self._db.executemany(_SET_META, meta)
        return object_id, True

    def add(self, descriptions: Sequence[ObjectDescription], *, replace: bool = False) -> int:
        """Add descriptions in one transaction; an existing id is an error unless ``replace``.

        Returns how many were written. On any error nothing is written.
        """
        with self._db:
            for d in descriptions:
                exists = self._db.execute("SELECT seq FROM descriptions WHERE id = ?", (d.object_id,)).fetchone()
                if exists and not replace:
                    raise ValueError(f"{self.path}: description {d.object_id!r} is already in the library "
                                     "(use --replace to overwrite)")
                if exists:
                    self._db.execute("DELETE FROM descriptions WHERE seq = ?", exists)
                self._insert(d, None)
        return len(descriptions)

    def _insert(self, d: ObjectDescription, key: str | None) -> None:
        """One description's rows, inside the caller's transaction."""
        look = d.appearance
        observations = in_order(d.observations)
        seq = self._db.execute(
            "INSERT INTO descriptions (id, grasp, grasp_distance_in, grasp_orientation_deg, appearance_round,"
            f" appearance_area_in2, appearance_elongation, learn_key, {_CODED}) VALUES (?,?,?,?,?,?,?,?,?)",
            (d.object_id, d.grasp, d.grasp_position.distance_in, d.grasp_position.orientation_deg,
             None if look is None else int(look.round), None if look is None else look.area_in2,
             None if look is None else look.elongation, key, self._coded(observations)),
        ).lastrowid
        self._db.executemany(
            "INSERT INTO observations VALUES (?,?,?,?,?)",
            [(seq, o.feature, o.position.distance_in, o.position.orientation_deg, o.value) for o in observations],
        )

    def unique_id(self, stem: str) -> str:
        """``stem`` if free, else the first free ``stem#n`` from where the last one was
        found (``stem#2``, ``stem#3``...): new encounters of an object.

        Each probe is one look-up in the id index, and the place to start is kept in
        ``meta`` (written in the caller's transaction when there is one), so the cost
        does not grow with the number of encounters already stored.
        """
        if not self._taken(stem):
            return stem
        n = self.meta_int(NEXT_SUFFIX + stem) or 2  # a kept hint is at least 3
        while self._taken(f"{stem}#{n}"):
            n += 1
        self._db.execute(_SET_META, (NEXT_SUFFIX + stem, str(n + 1)))
        return f"{stem}#{n}"

    def _taken(self, object_id: str) -> bool:
        return self._db.execute("SELECT 1 FROM descriptions WHERE id = ?", (object_id,)).fetchone() is not None

    # -- what each grasp has cost (docs/library-format.md, "Grasp costs") ---------------
    def record_grasp_attempts(self, attempts: Iterable[tuple[str, float, bool]], key: str | None = None,
                              robot: str = "") -> bool:
        """Add ``(grasp, robot seconds, success)`` attempts by ``robot`` (``''``: unnamed)
        to its per-grasp running totals, each capped at ``ROBOT_WEIGHT`` attempts, and
        bring the fleet's totals (their sum) up to date; returns False, adding nothing,
        when the ``meta`` row ``key`` (an idempotency key: this batch was recorded) is
        already stored. The key and the totals are one transaction: a crash leaves both
        or neither, so a retry neither counts the batch twice nor finds it marked but
        missing. The tables are made by the first record, so a store that never records
        a grasp is left exactly as it was."""
        added: dict[str, GraspCostRecord] = {}  # the batch per grasp, checked before anything is written
        for grasp, seconds, success in attempts:
            added[grasp] = added.get(grasp, GraspCostRecord(grasp)).with_attempt(float(seconds), bool(success))
        with self._db:  # read and written in one transaction: two writers never lose each other's attempts
            if key is not None:
                if self.meta_int(key):
                    return False
                self._db.execute(_SET_META, (key, "1"))
            self._robots_named()
            for grasp, batch in added.items():
                row = self._db.execute("SELECT successes, success_s, failures, failure_s FROM grasp_costs_by_robot"
                                       " WHERE grasp = ? AND robot = ?", (grasp, robot)).fetchone()
                held = GraspCostRecord(grasp, *row) if row else GraspCostRecord(grasp)
                now = held.plus(batch).capped(ROBOT_WEIGHT)
                self._db.execute("INSERT OR REPLACE INTO grasp_costs_by_robot VALUES (?,?,?,?,?,?)",
                                 (grasp, robot, now.successes, now.success_s, now.failures, now.failure_s))
                self._db.execute(
                    "INSERT OR REPLACE INTO grasp_costs SELECT grasp, SUM(successes), SUM(success_s), SUM(failures),"
                    " SUM(failure_s) FROM grasp_costs_by_robot WHERE grasp = ? GROUP BY grasp", (grasp,))
        return True

    def _robots_named(self) -> None:
        """Make the grasp-cost tables; a store whose totals predate robots' names gets
        them as the unnamed robot's (inside the caller's transaction)."""
        self._db.execute(_GRASP_COSTS)
        if self._db.execute("SELECT 1 FROM sqlite_master WHERE type='table' AND name='grasp_costs_by_robot'"
                            ).fetchone() is None:
            self._db.execute(_GRASP_COSTS_BY_ROBOT)
            self._db.execute("INSERT INTO grasp_costs_by_robot SELECT grasp, '', successes, success_s, failures,"
                             " failure_s FROM grasp_costs")

    def grasp_cost_records(self) -> list[GraspCostRecord]:
        """Every grasp's running totals, by name (none in a store that never recorded one)."""
        if self._db.execute("SELECT 1 FROM sqlite_master WHERE type='table' AND name='grasp_costs'").fetchone() is None:
            return []
        return [GraspCostRecord(g, int(n), float(s), int(m), float(f)) for g, n, s, m, f in self._db.execute(
            "SELECT grasp, successes, success_s, failures, failure_s FROM grasp_costs ORDER BY grasp")]


def _little_endian(codes: array.array) -> array.array:
    """``codes`` in the blob's byte order (little-endian), swapped in place if need be."""
    if sys.byteorder == "big":
        codes.byteswap()
    return codes


def load_library(path: str | Path) -> list[ObjectDescription]:
    """Descriptions from a ``.json`` file or a SQLite store (by extension)."""
    path = Path(path)
    if path.suffix.lower() == ".json":
        return read_library_json(path)
    if not path.exists():
        raise ValueError(f"{path}: library not found")
    with LibraryStore(path) as store:
        return store.descriptions()
