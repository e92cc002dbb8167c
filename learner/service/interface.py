"""What a robot asks of the learner service, wherever the service runs.

The executive holds a ``LearnerService`` and never knows whether the library lives in
its own process or behind zenoh; both implementations honour the same contract, so
the in-process one is the reference the zenoh pair is tested against.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from learner.description import ObjectDescription


class LearnerUnavailable(ConnectionError):
    """The learner service could not be reached, stopped answering, or answered with
    something that is not the protocol: the learner is lost, not the input wrong (the
    command line tells the two apart by exit status)."""


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
