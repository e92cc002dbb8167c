"""What a robot asks of the learner service, wherever the service runs.

The executive holds a ``LearnerService`` and never knows whether the library lives in
its own process or behind zenoh; both implementations honour the same contract, so
the in-process one is the reference the zenoh pair is tested against.
"""

from __future__ import annotations

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
    descriptions: tuple[ObjectDescription, ...]


class LearnerService(Protocol):
    """The shared library and the one way it grows: learning after a grasp."""

    def library(self) -> LibrarySnapshot:
        """The current library with its version."""
        ...

    def learn(self, description: ObjectDescription) -> str:
        """Add ``description`` in one transaction and return the id it was stored under.

        An id already in the library is a new encounter of that object, so the
        description is stored as ``id#2``, ``id#3``, ... rather than refused: two robots
        learning the same object at once must both keep what they learned.
        Bumps the version. Raises ValueError for a description that cannot be stored.
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
