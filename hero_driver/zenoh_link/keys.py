"""The key space of the driver protocol: everything a driver serves lives under
``hero/<robot>/`` (the verbs under it are listed in :mod:`.verbs`)."""

from __future__ import annotations

from zenoh_rpc.keys import KeySpace

PREFIX = "hero"


def robot_keys(robot: str) -> KeySpace:
    """The keys of ``robot``; ValueError when the name is not one key chunk."""
    return KeySpace(PREFIX, robot, "robot name")

