"""The key space of one service: everything it serves lives under ``<prefix>/<name>/``.

Deriving every key from one value means a server, its clients and any test tool
cannot drift apart, and a name that would smuggle a key-expression wildcard (``*``,
``$*``) or an extra chunk (``/``) into a key is refused before any key is built.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_CHUNK = re.compile(r"[A-Za-z0-9_.-]+")


def check_chunk(name: str, what: str = "name") -> str:
    """Return ``name`` if it is usable as one key chunk; ValueError naming ``what``
    (``"robot name"``) otherwise."""
    if not isinstance(name, str) or not _CHUNK.fullmatch(name):
        raise ValueError(f"{what} {name!r} must be letters, digits, '_', '-' or '.' (one key chunk)")
    return name


@dataclass(frozen=True)
class KeySpace:
    """``<prefix>/<name>/...``: the keys one named server declares.

    ``what`` is how an error calls the name (``"robot name"``, ``"learner name"``).
    """

    prefix: str
    name: str
    what: str = "name"

    def __post_init__(self) -> None:
        check_chunk(self.name, self.what)

    @property
    def root(self) -> str:
        return f"{self.prefix}/{self.name}"

    @property
    def alive(self) -> str:
        """The liveliness token declared while the server serves."""
        return f"{self.root}/alive"

    @property
    def state(self) -> str:
        """Where a server publishes its state, if it has one."""
        return f"{self.root}/state"

    @property
    def rpc_root(self) -> str:
        """The prefix of every verb key, with its trailing ``/``."""
        return f"{self.root}/rpc/"

    @property
    def rpc_all(self) -> str:
        """Every key below ``rpc/``: where unknown verbs and wildcards are refused."""
        return f"{self.rpc_root}**"

    def rpc(self, verb: str) -> str:
        """The queryable that answers ``verb`` (any chunk: the server refuses
        names that are not its verbs)."""
        return f"{self.rpc_root}{verb}"
