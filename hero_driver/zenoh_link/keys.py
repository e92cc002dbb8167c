"""The key scheme of the driver protocol: everything a driver serves lives under
``hero/<robot>/``.

Keeping the names in one module means the node, the client and the conformance
suite cannot drift apart, and a robot name that would smuggle a key-expression
wildcard (``*``, ``$*``) or an extra chunk (``/``) into a key is refused up front.
"""

from __future__ import annotations

import re

PREFIX = "hero"

# Verbs served as queryables on hero/<robot>/rpc/<verb>. ``noop`` touches no robot:
# it is the health ping and the round-trip benchmark.
ROBOT_VERBS = ("move", "sense", "grasp", "release", "camera", "reset")
NOOP = "noop"
VERBS = ROBOT_VERBS + (NOOP,)

_ROBOT_NAME = re.compile(r"[A-Za-z0-9_.-]+")


def check_robot(robot: str) -> str:
    """Return ``robot`` if it is usable as one key chunk; ValueError otherwise."""
    if not isinstance(robot, str) or not _ROBOT_NAME.fullmatch(robot):
        raise ValueError(
            f"robot name {robot!r} must be letters, digits, '_', '-' or '.' (one key chunk)"
        )
    return robot


def alive_key(robot: str) -> str:
    """The liveliness token a driver node declares while it serves ``robot``."""
    return f"{PREFIX}/{check_robot(robot)}/alive"


def state_key(robot: str) -> str:
    """Where the driver node publishes :class:`~hero_driver.interface.RobotState`."""
    return f"{PREFIX}/{check_robot(robot)}/state"


def rpc_key(robot: str, verb: str) -> str:
    """The queryable that carries out ``verb`` (any chunk; unknown ones are refused by
    the node with ``unknown_verb``)."""
    return f"{PREFIX}/{check_robot(robot)}/rpc/{verb}"


def rpc_prefix(robot: str) -> str:
    """Every key below ``rpc/``: the node's catch-all for verbs it does not know."""
    return f"{PREFIX}/{check_robot(robot)}/rpc/**"
