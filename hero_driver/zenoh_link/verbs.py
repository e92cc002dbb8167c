"""The verb table of the driver protocol: one row per verb, everything about it.

A verb used to be spread over the key list, the codec's dispatch tables, the
client's timeouts and the node's driver call, and adding one meant finding all four.
Here a row holds its name, its request type, the codecs of its request and reply,
its default timeout and how the node calls the driver; the node, the client and the
conformance suite read the table, and ``tests/hero_driver/test_zenoh_verbs.py``
holds ``docs/driver-protocol.md`` to it. A new verb is a row here plus its method and
its row on the ``Driver`` side (``hero_driver.interface``: the protocol and
``DRIVER_VERBS``, which ``tests/hero_driver/test_driver_verbs.py`` holds this table
to) and its ``ZenohDriver`` method (docs/conventions.md, "Adding a driver verb"); a
verb the node answers itself (``noop``, ``hello``) has no ``Driver`` method.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass
from typing import Any, TypeVar

from hero_driver.interface import UNKNOWN_VERB, BlockedMoves, Charger, DriverError
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import (
    CodecError,
    EmptyRequest,
    Json,
    MoveRequest,
    ProcedureRequest,
    Request,
    ResetRequest,
    WaitRequest,
)

T = TypeVar("T")


@dataclass(frozen=True)
class Verb:
    """One verb: ``hero/<robot>/rpc/<name>``.

    ``call`` starts the verb on a driver with the decoded request. A verb whose
    ``touches_robot`` is false is the node's own: its call is given the node's
    :class:`~.versions.Greeting` instead of the driver, and the node answers it at once,
    even while a robot verb runs, and never refuses it as ``busy``.

    ``timeout_s`` is how long a client waits by default; ``bound_s`` how long the
    driver node lets the robot work on it before it cancels the action, answers
    ``timeout`` and frees the robot. The bound is a little shorter than the timeout,
    so a client on its defaults hears the driver's ``timeout`` rather than its own
    (and finds the robot free, not ``busy``, for the next verb).
    """

    name: str
    request: type
    request_in: Callable[[Json], Request]
    request_out: Callable[[Any], Json]
    result_out: Callable[[Any], Json]
    result_in: Callable[[Json], Any]
    timeout_s: float
    call: Callable[[Any, Any], Future[Any]]  # (the Driver, or the node's Greeting; the request)
    bound_s: float | None = None  # None: the node answers at once (noop, hello)
    touches_robot: bool = True

    def encode_request(self, request: Request) -> bytes:
        """The query payload (the verb is the key, not part of the body)."""
        if not isinstance(request, self.request):
            raise CodecError(f"message: expected a {self.request.__name__}, got {type(request).__name__}")
        return codec.dumps(self.request_out(request))

    def decode_request(self, data: bytes) -> Request:
        """The request a query carried; CodecError (``bad_request``) for one that is
        too large (:data:`~.codec.MAX_REQUEST_BYTES`) or breaks the protocol."""
        return self.request_in(codec.loads_request(data))

    def encode_result(self, result: object) -> bytes:
        """The reply body for what the driver returned."""
        return codec.dumps(self.result_out(result))

    def decode_result(self, data: bytes) -> Any:
        """The interface value a reply carries."""
        return self.result_in(codec.loads(data))


VERBS: tuple[Verb, ...] = (
    Verb("move", MoveRequest, codec.move_request_in, codec.move_request_out,
         codec.move_result_out, codec.move_result_in, 900.0,
         lambda driver, request: driver.move(list(request.waypoints), request.face), bound_s=870.0),
    Verb("sense", ProcedureRequest, codec.procedure_request_in, codec.procedure_request_out,
         codec.sense_result_out, codec.sense_result_in, 300.0,
         lambda driver, request: driver.sense(request.procedure), bound_s=285.0),
    Verb("grasp", ProcedureRequest, codec.procedure_request_in, codec.procedure_request_out,
         codec.grasp_result_out, codec.grasp_result_in, 300.0,
         lambda driver, request: driver.grasp(request.procedure), bound_s=285.0),
    Verb("release", EmptyRequest, codec.empty_request_in, codec.empty_request_out,
         codec.state_out, codec.state_in, 120.0,
         lambda driver, _request: driver.release(), bound_s=110.0),
    Verb("camera", EmptyRequest, codec.empty_request_in, codec.empty_request_out,
         codec.camera_out, codec.camera_in, 30.0,
         lambda driver, _request: driver.camera(), bound_s=25.0),
    Verb("reset", ResetRequest, codec.reset_request_in, codec.reset_request_out,
         codec.state_out, codec.state_in, 120.0,
         lambda driver, request: driver.reset(request.world, request.seed), bound_s=110.0),
    # The battery feature: with the base at the dock, charge until full.
    Verb("charge", EmptyRequest, codec.empty_request_in, codec.empty_request_out,
         codec.state_out, codec.state_in, 7200.0, lambda driver, _request: _charge(driver), bound_s=7170.0),
    # The blocked_moves feature: stand still while a moving obstacle passes (at most an hour).
    Verb("wait", WaitRequest, codec.wait_request_in, codec.wait_request_out,
         codec.state_out, codec.state_in, 3660.0, lambda driver, request: _wait(driver, request.seconds),
         bound_s=3630.0),
    # The health ping and the round-trip benchmark.
    Verb("noop", EmptyRequest, codec.empty_request_in, codec.empty_request_out,
         codec.noop_out, codec.noop_in, 5.0, lambda _greeting, _request: _settled(None), touches_robot=False),
    # Which protocol versions and optional features this node serves, and which robot profile.
    Verb("hello", EmptyRequest, codec.empty_request_in, codec.empty_request_out,
         codec.hello_out, codec.hello_in, 5.0, lambda greeting, _request: _settled(greeting), touches_robot=False),
)

def _charge(driver: Any) -> Future[Any]:
    """``charge`` on a driver without the battery feature is a verb it does not have."""
    if not isinstance(driver, Charger):
        raise DriverError(UNKNOWN_VERB, "charge: this driver has no battery feature (see its hello)")
    return driver.charge()


def _wait(driver: Any, seconds: float) -> Future[Any]:
    """``wait`` on a driver without the blocked_moves feature is a verb it does not have."""
    if not isinstance(driver, BlockedMoves) or driver.safety_in() is None:
        raise DriverError(UNKNOWN_VERB, "wait: this driver has no blocked_moves feature (see its hello)")
    return driver.wait(seconds)


def _settled(value: T) -> Future[T]:
    future: Future[T] = Future()
    future.set_result(value)
    return future


BY_NAME: Mapping[str, Verb] = {verb.name: verb for verb in VERBS}
NAMES: tuple[str, ...] = tuple(BY_NAME)
