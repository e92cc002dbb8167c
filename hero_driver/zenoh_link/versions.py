"""Protocol versions and optional features: what this code serves, and how a client
and a driver agree on what to use.

The policy (docs/driver-protocol.md, "Versioning"): an *addition* (a new verb, an
optional field, a new error code a client may meet) is an optional **feature**, named
in the driver's ``hello`` and used by a client only when the driver lists it, so old
drivers keep working with new clients and the other way round. Only a change an old
peer would misread (a field that changes meaning, a required field) is a new
**version**. A client speaks every version it knows and uses the highest one both
ends speak; a driver that predates ``hello`` is taken to serve version 1 and no
features, because that is all there was before ``hello``. ``profile`` adds the robot
profile's name and fingerprint to the ``hello`` reply; ``battery`` adds the charging
dock's pose to it, the ``charge`` verb and the ``battery_empty`` error code.
``blocked_moves`` adds the safety distance to it, the optional ``blocked`` field of the
``move`` reply and the ``wait`` verb (docs/driver-protocol.md, "Moving obstacles").
``scan`` adds the ``scan`` verb alone (docs/driver-protocol.md, "Scans").
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass

from hero_driver.interface import DRIVER_VERBS, PROTOCOL_VERSION, Hello, Pose
from robot_profile import ProfileStamp

PROFILE = "profile"  # the feature: the hello reply names the robot profile the driver serves
BATTERY = "battery"  # the feature: a real battery level, the dock in hello, the charge verb
BLOCKED_MOVES = "blocked_moves"  # the feature: moves stop short of moving obstacles, the wait verb
SUPPORTED_VERSIONS: tuple[int, ...] = (PROTOCOL_VERSION,)
FIELD_FEATURES: tuple[str, ...] = (PROFILE, BATTERY, BLOCKED_MOVES)  # each brings a field of the hello reply
VERB_FEATURES: tuple[str, ...] = tuple(dict.fromkeys(
    verb.feature for verb in DRIVER_VERBS if verb.feature is not None and verb.feature not in FIELD_FEATURES))
"""The features that bring verbs and nothing else (``scan``): a driver offers one when it
has the feature's protocol (``hero_driver.interface.PROTOCOLS``), and the node lists it
in ``hello`` then, so a new feature's verb needs no change here or in the node."""
FEATURES: tuple[str, ...] = FIELD_FEATURES + VERB_FEATURES  # optional features this code serves and uses
BEFORE_HELLO = Hello((1,), ())  # what a driver without ``hello`` serves


@dataclass(frozen=True)
class Greeting:
    """A driver process's whole ``hello`` answer: what it serves, the robot profile it
    serves when it says (the ``profile`` feature; None: it does not say), and where its
    charging dock is (the ``battery`` feature; None: it cannot charge)."""

    served: Hello
    profile: ProfileStamp | None = None
    dock: Pose | None = None
    safety_in: float | None = None  # the blocked_moves feature: how near ahead a mover stops a move


def greeting(profile: ProfileStamp | None, dock: Pose | None = None, safety_in: float | None = None,
             offered: Collection[str] = ()) -> Greeting:
    """What a node of this code answers to ``hello``: every version it speaks, the
    ``profile`` feature only when it has a profile to name, ``battery`` only when
    the driver it serves has a dock to charge at, ``blocked_moves`` only when it
    stops moves for moving obstacles, and each of :data:`VERB_FEATURES` in ``offered``."""
    features = (((PROFILE,) if profile is not None else ()) + ((BATTERY,) if dock is not None else ())
                + ((BLOCKED_MOVES,) if safety_in is not None else ())
                + tuple(feature for feature in VERB_FEATURES if feature in offered))
    return Greeting(Hello(SUPPORTED_VERSIONS, features), profile, dock, safety_in)


class NoCommonVersion(ValueError):
    """The driver and this client share no protocol version; the text is one line."""


@dataclass(frozen=True)
class Agreement:
    """What a client and one driver process use: a version and the features both know."""

    version: int
    features: frozenset[str]


def agree(served: Hello, speaks: Collection[int] = SUPPORTED_VERSIONS,
          knows: Collection[str] = FEATURES) -> Agreement:
    """The highest version in both ``served.versions`` and ``speaks``, with the
    features in both ``served.features`` and ``knows`` (a feature this side does not
    know is ignored: it is optional by definition). NoCommonVersion when none is shared."""
    common = set(served.versions) & set(speaks)
    if not common:
        raise NoCommonVersion(f"the driver serves protocol version {_listed(served.versions)}, "
                              f"this client speaks {_listed(speaks)}: upgrade the older side")
    return Agreement(max(common), frozenset(served.features) & frozenset(knows))


def _listed(versions: Collection[int]) -> str:
    return ", ".join(str(v) for v in sorted(versions))
