"""No grasp is lost: a robot's learned descriptions wait in its own SQLite outbox until
the learner service has them.

A robot that grasped an object has paid minutes of robot time for its description; a
learner service that is restarting, or a network that drops for a second, must not
throw that away. So the robot's client writes each learned description to a local
outbox first (one committed transaction, with the learn's idempotency key) and then
delivers the outbox, oldest first, to the service. What cannot be delivered now stays
and is delivered on the next learn, library or version call, or at close, or by the
next run. A delivery whose reply was lost is simply sent again: the service finds the
key and stores nothing new (``LearnerService.learn``), so each grasp is stored once.

While the service is unreachable the robot goes on deciding with the last library it
received: the library only grows, so the old snapshot is a smaller but valid library.
A description the service refuses (``bad_request``: resending will not help) is kept
in the outbox, marked refused with the reason, for a person to look at; it never
blocks the ones behind it.
"""

from __future__ import annotations

import json
import sqlite3
import threading
import time
import uuid
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from learner.costs import GraspCostRecord
from learner.description import ObjectDescription
from learner.library.format import descriptions_from_json, descriptions_to_json
from learner.library.store import durable_and_quick
from learner.service.interface import KeepsGraspCosts, LearnerService, LearnerUnavailable, LibrarySnapshot

_SCHEMA = """
CREATE TABLE IF NOT EXISTS outbox (
    seq INTEGER PRIMARY KEY AUTOINCREMENT,
    learner TEXT NOT NULL,
    learn_key TEXT NOT NULL UNIQUE,
    description TEXT NOT NULL,
    queued_at REAL NOT NULL,
    refused TEXT
);
"""

QUEUED_PREFIX = "queued:"
"""What ``learn`` answers for a description not yet delivered: ``queued:<key>``; the
service names it when it is delivered."""


@dataclass(frozen=True)
class Waiting:
    """A learned description in the outbox and the key it will be delivered under."""

    key: str
    description: ObjectDescription


class Outbox:
    """The outbox file: learned descriptions per learner service name, oldest first.

    Several executives may share one file (one ``CSL_HOME``): each may deliver another's
    row, which is harmless, because a row is delivered under its own key.
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._db = sqlite3.connect(self.path, check_same_thread=False, timeout=10.0)
            durable_and_quick(self._db)
            with self._db:
                self._db.executescript(_SCHEMA)
        except (sqlite3.DatabaseError, OSError) as exc:
            raise ValueError(f"{self.path}: not a usable outbox: {exc}") from None

    def put(self, learner: str, description: ObjectDescription, key: str) -> None:
        """Queue ``description`` for ``learner`` under ``key``, committed before return."""
        text = json.dumps(descriptions_to_json([description]), ensure_ascii=False, allow_nan=False)
        with self._db:
            self._db.execute("INSERT INTO outbox (learner, learn_key, description, queued_at) VALUES (?,?,?,?)",
                             (learner, key, text, time.time()))

    def waiting(self, learner: str) -> list[Waiting]:
        """What waits for ``learner``, oldest first (refused rows excluded)."""
        rows = self._db.execute("SELECT learn_key, description FROM outbox WHERE learner = ? AND refused IS NULL "
                                "ORDER BY seq", (learner,)).fetchall()
        return [Waiting(key, _loads(text, f"{self.path}: outbox row {key}")) for key, text in rows]

    def count(self, learner: str, *, refused: bool = False) -> int:
        """How many wait for ``learner`` (or, with ``refused``, were refused by it)."""
        condition = "refused IS NOT NULL" if refused else "refused IS NULL"
        return int(self._db.execute(f"SELECT count(*) FROM outbox WHERE learner = ? AND {condition}",
                                    (learner,)).fetchone()[0])

    def delivered(self, key: str) -> None:
        with self._db:
            self._db.execute("DELETE FROM outbox WHERE learn_key = ?", (key,))

    def refuse(self, key: str, reason: str) -> None:
        with self._db:
            self._db.execute("UPDATE outbox SET refused = ? WHERE learn_key = ?", (reason, key))

    def close(self) -> None:
        self._db.close()


class OutboxLearner:
    """A :class:`LearnerService` that queues learns in an :class:`Outbox` and delivers
    them to ``service`` (named ``learner``), oldest first, whenever it can.

    ``learn`` answers the service's id when the description was delivered at once, and
    ``queued:<key>`` when it waits. ``library`` and ``version`` answer the service's,
    or while it is unreachable the last library received (LearnerUnavailable only when
    nothing was ever received).
    """

    def __init__(self, service: LearnerService, outbox: Outbox, learner: str) -> None:
        self.service, self.outbox, self.learner = service, outbox, learner
        self._lock = threading.RLock()
        self._last: LibrarySnapshot | None = None
        self._closed = False
        self.delivered = 0
        """Descriptions this client delivered, its own and earlier runs' alike."""
        self.waiting_at_close: int | None = None
        """How many waited in the outbox when :meth:`close` gave up delivering."""
        self._grasp_costs: list[GraspCostRecord] = []
        self.grasp_records_lost = 0
        """Grasp-cost records dropped because the service could not take them."""

    def learn(self, description: ObjectDescription, key: str | None = None) -> str:
        key = key if key is not None else str(uuid.uuid4())
        with self._lock:
            self._check_open()
            self.outbox.put(self.learner, description, key)  # first: the grasp is safe on disk
            answered = self.deliver()
        if key in answered:
            outcome = answered[key]
            if isinstance(outcome, ValueError):
                raise outcome
            return outcome
        return QUEUED_PREFIX + key

    def library(self) -> LibrarySnapshot:
        with self._lock:
            self._check_open()
            self.deliver()
            try:
                self._last = self.service.library()
            except LearnerUnavailable:
                if self._last is None:
                    raise
            return self._last

    def version(self) -> int:
        with self._lock:
            self._check_open()
            self.deliver()
            try:
                return self.service.version()
            except LearnerUnavailable:
                if self._last is None:
                    raise
                return self._last.version

    def record_grasp_attempts(self, attempts: Sequence[tuple[str, float, bool]], key: str | None = None,
                              robot: str | None = None) -> None:
        """Passed to the service when it keeps grasp costs (docs/method.md §5.7). Not
        queued: a record the service cannot take (it is unreachable, or refuses it, as a
        service from before grasp costs refuses the verb) is dropped and counted in
        :attr:`grasp_records_lost`, a few attempts of one object whose loss only slows
        the prices' learning and must not stop the robot."""
        with self._lock:
            self._check_open()
            if not isinstance(self.service, KeepsGraspCosts):
                return
            try:
                self.service.record_grasp_attempts(attempts, key, robot)
            except (LearnerUnavailable, ValueError):
                self.grasp_records_lost += 1

    def grasp_costs(self) -> list[GraspCostRecord]:
        """The service's grasp costs, or when it cannot say (unreachable, or from
        before grasp costs) the last received (none before any: the file's prices)."""
        with self._lock:
            self._check_open()
            if isinstance(self.service, KeepsGraspCosts):
                try:
                    self._grasp_costs = self.service.grasp_costs()
                except (LearnerUnavailable, ValueError):
                    pass
            return self._grasp_costs

    def deliver(self) -> dict[str, str | ValueError]:
        """Send what waits, oldest first, until the service is unreachable.

        Returns each attempted key's id, or the ValueError the service refused it with
        (the row is then kept, marked refused). Stops at the first unreachable call, so
        an outage costs one failed call, not one per waiting description.
        """
        answered: dict[str, str | ValueError] = {}
        with self._lock:
            for item in self.outbox.waiting(self.learner):
                try:
                    answered[item.key] = self.service.learn(item.description, item.key)
                except LearnerUnavailable:
                    break
                except ValueError as exc:
                    answered[item.key] = exc
                    self.outbox.refuse(item.key, " ".join(str(exc).split()))
                else:
                    self.outbox.delivered(item.key)
                    self.delivered += 1
        return answered

    def close(self) -> None:
        """Deliver what can be delivered, then close the service and the outbox; how
        many still wait is :attr:`waiting_at_close`."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            try:
                self.deliver()
                self.waiting_at_close = self.outbox.count(self.learner)
            finally:
                self.outbox.close()
                self.service.close()

    def __enter__(self) -> OutboxLearner:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def _check_open(self) -> None:
        if self._closed:
            raise LearnerUnavailable(f"learner {self.learner!r}: the client is closed")


def _loads(text: str, where: str) -> ObjectDescription:
    return descriptions_from_json(json.loads(text), where)[0]
