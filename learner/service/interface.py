"""What a robot asks of the learner service, wherever the service runs.

The executive holds a ``LearnerService`` and never knows whether the library lives in
its own process or behind zenoh; both implementations honour the same contract, so
the in-process one is the reference the zenoh pair is tested against.
"""

from __future__ import annotations

import math
import re
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol, runtime_checkable

from learner.costs import GraspCostRecord
from learner.description import ObjectDescription


class LearnerUnavailable(ConnectionError):
    """The learner service could not be reached, stopped answering, or answered with
    something that is not the protocol: the learner is lost, not the input wrong (the
    command line tells the two apart by exit status)."""


class LearnerTimedOut(LearnerUnavailable):
    """A service that is there did not answer one request in time (busy, or a large
    library on a slow link): the message names the request and the time it was given,
    which a client can raise (``csl run --learner-timeout``)."""


@dataclass(frozen=True)
class LibrarySnapshot:
    """The library as of one ``version``.

    Immutable so a robot can keep using a snapshot while another robot learns: the
    next snapshot is a new object, never a change under its feet.
    """

    version: int
    descriptions: Sequence[ObjectDescription]
    """A tuple, or an append-only :class:`~learner.description.Descriptions` (equal to
    the tuple of its entries) so that a learn need not copy the library."""


@dataclass(frozen=True)
class LibraryPage:
    """Descriptions ``start`` onwards of the library at ``version``, which held
    ``total`` then: one page of a library fetched in pieces."""

    version: int
    start: int
    total: int
    descriptions: Sequence[ObjectDescription]


@dataclass(frozen=True)
class LibraryChanges:
    """What changed since a version a client holds: the library at ``version`` is the
    client's first ``start`` descriptions followed by ``added``.

    ``start`` 0 is the whole library (the service could not tell what changed since the
    client's version: it restarted, quarantined, or never saw that version); a client
    that does not hold ``start`` descriptions at the version it asked about must fetch
    the whole library.
    """

    version: int
    start: int
    added: Sequence[ObjectDescription]


@runtime_checkable
class KeepsChanges(Protocol):
    """A service that can answer "what changed since version v" with only the change,
    so a client holding v pays for the change, not for the library."""

    def changes(self, since: int) -> LibraryChanges:
        """The descriptions added after version ``since`` (see :class:`LibraryChanges`)."""
        ...


@runtime_checkable
class KeepsGraspCosts(Protocol):
    """A service that keeps what each grasp has cost on the robots it serves
    (docs/method.md §5.7), so the executive can price grasps by it."""

    def record_grasp_attempts(self, attempts: Sequence[tuple[str, float, bool]], key: str | None = None,
                              robot: str | None = None) -> None:
        """Add ``(grasp, robot seconds, success)`` attempts made by ``robot`` (None:
        unnamed; every unnamed record counts as one robot's) to the per-grasp totals in
        one transaction, one robot weighing at most ``learner.costs.ROBOT_WEIGHT``
        attempts of a grasp. ``key``, made once per object by the client, makes a retry
        harmless: a batch whose key is already stored adds nothing. Raises ValueError
        for an attempt that cannot be counted (unknown grasp, seconds not finite >= 0,
        too many, a robot name that is not one key chunk); then nothing is added."""
        ...

    def grasp_costs(self) -> list[GraspCostRecord]:
        """Every grasp's running totals, by name."""
        ...


class LearnerService(Protocol):
    """The shared library and the one way it grows: learning after a grasp."""

    def library(self) -> LibrarySnapshot:
        """The current library with its version."""
        ...

    def learn(self, description: ObjectDescription, key: str | None = None) -> str:
        """Add ``description`` in one transaction and return the id it was stored under.

        An id already in the library is a new encounter of that object, so the
        description is stored as ``id#2``, ``id#3``, ... rather than refused: two robots
        learning the same object at once must both keep what they learned.
        ``key`` is the learn's idempotency key, made once per grasped object by the
        client: a learn whose key is already stored stores nothing and returns the id
        stored the first time, so a retry after a lost reply never duplicates.
        Bumps the version when it stores. Raises ValueError for a description (or key)
        that cannot be stored.
        """
        ...

    def version(self) -> int:
        """A number that grows with every change of the library.

        Cheap by design: a robot polls it before each decision and refetches the
        library only when it moved.
        """
        ...

    def close(self) -> None:
        """Release the store or connection; later calls raise ValueError or
        ConnectionError."""
        ...


MAX_KEY_CHARS = 100
"""Longest idempotency key admitted: a uuid is 36 characters."""


def check_learn_key(key: object) -> str:
    """``key`` if it is a usable idempotency key (a non-empty string of at most
    :data:`MAX_KEY_CHARS` printable characters), else ValueError naming it."""
    if not isinstance(key, str) or not key or len(key) > MAX_KEY_CHARS or not key.isprintable():
        raise ValueError(f"key: an idempotency key is 1 to {MAX_KEY_CHARS} printable characters, got {key!r:.120}")
    return key


_ROBOT_NAME = re.compile(r"[A-Za-z0-9_.-]{1,64}")


def check_robot_name(robot: object) -> str:
    """``robot`` if it can name the robot a grasp record comes from (1 to 64 letters,
    digits, ``_``, ``-`` or ``.``: one chunk of a zenoh key, where the router's access
    control can check it), else ValueError naming it."""
    if not isinstance(robot, str) or not _ROBOT_NAME.fullmatch(robot):
        raise ValueError(f"robot: a robot name is 1 to 64 letters, digits, '_', '-' or '.', got {robot!r:.120}")
    return robot


MAX_GRASP_ATTEMPTS = 1000
"""Most attempts one record may carry: one object's grasps (its step budget is 40 by
default), with room to spare; more is a client gone wrong, refused whole."""

MAX_ATTEMPT_S = 86_400.0
"""Most robot seconds one grasp attempt may cost: a day, far beyond any grasp. Bounding
each attempt (not just requiring it finite) keeps the running totals finite for any
number of records, so ``grasp_costs`` always encodes and a learned price is never inf."""


def check_grasp_attempts(attempts: object) -> list[tuple[str, float, bool]]:
    """``attempts`` as ``(grasp, seconds, success)`` triples if each names a grasp (1 to
    :data:`MAX_KEY_CHARS` printable characters) and costs finite seconds >= 0 and there
    are at most :data:`MAX_GRASP_ATTEMPTS` (each at most :data:`MAX_ATTEMPT_S`); else
    ValueError naming the first bad one.
    Whether the robot knows the grasp is the service's check (it knows the robot)."""
    if not isinstance(attempts, (list, tuple)):
        raise ValueError(f"attempts: must be a list, got {type(attempts).__name__}")
    if len(attempts) > MAX_GRASP_ATTEMPTS:
        raise ValueError(f"attempts: at most {MAX_GRASP_ATTEMPTS} in one record, got {len(attempts)}")
    checked = []
    for i, attempt in enumerate(attempts):
        if not isinstance(attempt, (list, tuple)) or len(attempt) != 3:
            raise ValueError(f"attempts[{i}]: must be [grasp, seconds, success], got {attempt!r:.120}")
        grasp, seconds, success = attempt
        if not isinstance(grasp, str) or not grasp or len(grasp) > MAX_KEY_CHARS or not grasp.isprintable():
            raise ValueError(f"attempts[{i}]: a grasp is 1 to {MAX_KEY_CHARS} printable characters, got {grasp!r:.120}")
        value = _seconds(seconds)
        if not 0 <= value <= MAX_ATTEMPT_S:
            raise ValueError(f"attempts[{i}]: seconds must be a number from 0 to {MAX_ATTEMPT_S:.0f} (a day), "
                             f"got {seconds!r:.120}")
        if not isinstance(success, bool):
            raise ValueError(f"attempts[{i}]: success must be true or false, got {success!r:.120}")
        checked.append((grasp, value, success))
    return checked


def _seconds(value: object) -> float:
    """``value`` as seconds; NaN for anything not a number (a bool is not one)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return math.nan
    try:
        return float(value)
    except OverflowError:  # an integer beyond any float
        return math.inf
