"""The verb table of the driver protocol: one row per verb, everything the wire needs.

A verb used to be spread over the key list, the codec's dispatch tables, the
client's timeouts, the node's driver call, the client's method, the schema fields
and the conformance suite, and adding one meant finding them all. Here a row holds
its name, the message shapes of its request and reply (:class:`.codec.Message`), its
default timeout and the driver's bound; everything else about it comes from its row
of the driver's own table (``hero_driver.interface.DRIVER_VERBS``): the node calls
the driver's method of the same name with the request's fields as its arguments,
refuses a feature's verb on a driver without the feature (and lists in ``hello`` a
feature that brings only verbs, :data:`.versions.VERB_FEATURES`), and the client's
method is made from the row (:mod:`.client`). The node, the client, the schemas and the
conformance suite read this table; ``tests/hero_driver/test_zenoh_verbs.py`` holds
``docs/driver-protocol.md`` to it and ``tests/hero_driver/test_driver_verbs.py`` holds
it to the driver's table (docs/conventions.md, "Adding a driver verb"). A verb the
node answers itself (``noop``, ``hello``) has no ``Driver`` method.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any

from hero_driver.interface import (
    PROTOCOLS,
    UNKNOWN_VERB,
    VERB_BY_NAME,
    BlockedMoves,
    Charger,
    DriverError,
    DriverVerb,
)
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import (
    EMPTY,
    GRASPED,
    GREETING,
    IMAGE,
    MOVE,
    MOVED,
    NOTHING,
    PROCEDURE,
    RESET,
    SCANNED,
    SENSED,
    STATE,
    WAIT,
    CodecError,
    Message,
    Request,
)
from hero_driver.zenoh_link.versions import BATTERY, BLOCKED_MOVES, Greeting

OFFERS: Mapping[str, Callable[[Any], bool]] = {
    BATTERY: lambda driver: isinstance(driver, Charger),
    BLOCKED_MOVES: lambda driver: isinstance(driver, BlockedMoves) and driver.safety_in() is not None,
}
"""Whether a driver offers an optional feature that brings a field of ``hello`` too, so
its verbs are served; any other feature (:data:`.versions.VERB_FEATURES`) is offered by
a driver that has the feature's protocol, as the node's ``hello`` lists it."""


def offers(driver: Any, feature: str) -> bool:
    """Whether ``driver`` offers the optional ``feature``."""
    check = OFFERS.get(feature)
    return check(driver) if check is not None else isinstance(driver, PROTOCOLS[feature])


@dataclass(frozen=True)
class Verb:
    """One verb: ``hero/<robot>/rpc/<name>``.

    ``request`` and ``reply`` are the message shapes it sends and answers; a robot
    verb's request carries exactly its ``Driver`` method's arguments as fields, by
    name. A verb whose ``touches_robot`` is false is the node's own: ``answer`` gives
    its reply from the node's :class:`~.versions.Greeting`, and the node answers it at
    once, even while a robot verb runs, and never refuses it as ``busy``.

    ``timeout_s`` is how long a client waits by default; ``bound_s`` how long the
    driver node lets the robot work on it before it cancels the action, answers
    ``timeout`` and frees the robot. The bound is a little shorter than the timeout,
    so a client on its defaults hears the driver's ``timeout`` rather than its own
    (and finds the robot free, not ``busy``, for the next verb).
    """

    name: str
    request: Message
    reply: Message
    timeout_s: float
    bound_s: float | None = None  # None: the node answers at once (noop, hello)
    answer: Callable[[Greeting], object] | None = None  # a node verb's reply; None: a robot verb

    @property
    def touches_robot(self) -> bool:
        return self.answer is None

    @property
    def driver_verb(self) -> DriverVerb:
        """The row of the driver's table this robot verb carries."""
        return VERB_BY_NAME[self.name]

    def call(self, driver: Any, request: Request) -> Future[Any]:
        """Start the verb: a robot verb on ``driver`` (a ``Driver``), its method given
        the request's fields of the same names, in the order the driver's row lists
        its arguments; a node verb answers from ``driver``, the node's Greeting, at
        once. ``unknown_verb`` for a feature's verb on a driver without the feature
        (what a driver from before the feature answers)."""
        if self.answer is not None:
            return settled(self.answer(driver))
        feature = self.driver_verb.feature
        if feature is not None and not offers(driver, feature):
            raise DriverError(UNKNOWN_VERB, f"{self.name}: this driver has no {feature} feature (see its hello)")
        method = getattr(driver, self.name)
        return method(*(getattr(request, name) for name in self.driver_verb.args))

    def encode_request(self, request: Request) -> bytes:
        """The query payload (the verb is the key, not part of the body)."""
        if not isinstance(request, self.request.value):
            raise CodecError(f"message: expected a {self.request.value.__name__}, got {type(request).__name__}")
        return codec.dumps(self.request.write(request))

    def decode_request(self, data: bytes) -> Request:
        """The request a query carried; CodecError (``bad_request``) for one that is
        too large (:data:`~.codec.MAX_REQUEST_BYTES`) or breaks the protocol."""
        return self.request.read(codec.loads_request(data))

    def encode_result(self, result: object) -> bytes:
        """The reply body for what the driver returned."""
        return codec.dumps(self.reply.write(result))

    def decode_result(self, data: bytes) -> Any:
        """The interface value a reply carries."""
        return self.reply.read(codec.loads(data))


VERBS: tuple[Verb, ...] = (
    Verb("move", MOVE, MOVED, 900.0, 870.0),
    Verb("sense", PROCEDURE, SENSED, 300.0, 285.0),
    Verb("grasp", PROCEDURE, GRASPED, 300.0, 285.0),
    Verb("release", EMPTY, STATE, 120.0, 110.0),
    Verb("camera", EMPTY, IMAGE, 30.0, 25.0),
    Verb("reset", RESET, STATE, 120.0, 110.0),
    # The battery feature: with the base at the dock, charge until full.
    Verb("charge", EMPTY, STATE, 7200.0, 7170.0),
    # The blocked_moves feature: stand still while a moving obstacle passes (at most an hour).
    Verb("wait", WAIT, STATE, 3660.0, 3630.0),
    # The scan feature: one planar range scan where the robot stands (a sonar sweep takes minutes).
    Verb("scan", EMPTY, SCANNED, 300.0, 285.0),
    # The health ping and the round-trip benchmark.
    Verb("noop", EMPTY, NOTHING, 5.0, answer=lambda _greeting: None),
    # Which protocol versions and optional features this node serves, and which robot profile.
    Verb("hello", EMPTY, GREETING, 5.0, answer=lambda greeting: greeting),
)


def settled(value: Any) -> Future[Any]:
    """A future already done with ``value``."""
    future: Future[Any] = Future()
    future.set_result(value)
    return future


BY_NAME: Mapping[str, Verb] = {verb.name: verb for verb in VERBS}
NAMES: tuple[str, ...] = tuple(BY_NAME)
