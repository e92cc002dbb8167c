"""The zenoh client: a :class:`~hero_driver.interface.Driver` whose robot is another
process (the simulated HERO node or a hardware driver) reached through zenoh.

Every verb sends one query and returns a future at once; the reply, an error reply,
the query's deadline or the driver's liveliness token vanishing completes it, so a
behaviour never blocks a tick on the network. The client follows the driver's
liveliness token rather than its connection: when the token goes, in-flight verbs
fail with ``unavailable`` and new ones fail at once; when a driver process (the same
or a new one) declares the token again, the same client object simply works again,
because zenoh routes the queries to whoever serves the keys.

Futures complete on zenoh's network thread: a done-callback must be quick and must
never wait on another verb's future there.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Future, InvalidStateError
from dataclasses import dataclass, fields
from typing import Any

import zenoh

from hero_driver.interface import (
    BAD_REQUEST,
    INTERNAL,
    TIMEOUT,
    UNAVAILABLE,
    CameraImage,
    DriverError,
    GraspResult,
    MoveResult,
    Pose,
    RobotState,
    SenseResult,
)
from hero_driver.zenoh_link import codec, keys
from hero_driver.zenoh_link.codec import (
    CodecError,
    EmptyRequest,
    MoveRequest,
    ProcedureRequest,
    Request,
    ResetRequest,
)
from hero_driver.zenoh_link.config import DEFAULT_ENDPOINT, open_session

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class VerbTimeouts:
    """Wall-clock seconds a verb may take before its future fails with ``timeout``.

    Generous by default because a real HERO moves at half an inch a second and a
    fine sonar sweep takes minutes; the simulator answers in milliseconds.
    """

    move_s: float = 900.0
    sense_s: float = 300.0
    grasp_s: float = 300.0
    release_s: float = 120.0
    camera_s: float = 30.0
    reset_s: float = 120.0
    noop_s: float = 5.0

    def __post_init__(self) -> None:
        for spec in fields(self):
            value = getattr(self, spec.name)
            if not value > 0:
                raise ValueError(f"{spec.name} must be a positive number of seconds, got {value}")

    def of(self, verb: str) -> float:
        """The timeout of ``verb``."""
        return float(getattr(self, f"{verb}_s"))


class ZenohDriver:
    """Drives the robot served on ``hero/<robot>/...`` by some driver process.

    ``connect`` lists the driver nodes' endpoints; pass ``session`` instead to share
    an open session (the client then leaves it open on :meth:`close`). The
    constructor waits up to ``discover_s`` for a driver's liveliness token, so a
    driver that is already up is usable straight away; one that starts later is
    picked up when its token appears (see :attr:`alive`, :meth:`wait_ready`).
    """

    def __init__(self, robot: str = "r1", *, connect: Sequence[str] = (DEFAULT_ENDPOINT,),
                 timeouts: VerbTimeouts = VerbTimeouts(), session: zenoh.Session | None = None,
                 discover_s: float = 1.0) -> None:
        self.robot = keys.check_robot(robot)
        self.timeouts = timeouts
        self._owns_session = session is None
        self._session = open_session(connect=connect) if session is None else session
        self._lock = threading.Condition()
        self._alive = False
        self._liveliness_events = 0  # bumped by every token change, to ignore stale queries
        self._state: RobotState | None = None
        self._pending: set[_Call] = set()
        self._closed = False
        self._state_sub = self._session.declare_subscriber(keys.state_key(robot), self._on_state)
        liveliness = self._session.liveliness()
        self._token_sub = liveliness.declare_subscriber(keys.alive_key(robot), self._on_token)
        self._query_liveliness()
        with self._lock:  # the session may still be connecting: give the token a moment
            self._lock.wait_for(lambda: self._alive, discover_s)

    # ------------------------------------------------------------------ liveness

    @property
    def alive(self) -> bool:
        """True while a driver's liveliness token for this robot is visible."""
        with self._lock:
            return self._alive

    def wait_ready(self, timeout_s: float) -> bool:
        """Wait until a driver is alive and has published its state; False on timeout."""
        with self._lock:
            return self._lock.wait_for(lambda: self._alive and self._state is not None, timeout_s)

    def wait_gone(self, timeout_s: float) -> bool:
        """Wait until no driver is alive; False on timeout."""
        with self._lock:
            return self._lock.wait_for(lambda: not self._alive, timeout_s)

    def _on_token(self, sample: zenoh.Sample) -> None:
        if sample.kind == zenoh.SampleKind.PUT:
            with self._lock:
                self._liveliness_events += 1
                self._alive = not self._closed
                self._lock.notify_all()
            return
        with self._lock:
            self._liveliness_events += 1
            self._alive = False
            self._state = None
            orphans, self._pending = self._pending, set()
            self._lock.notify_all()
        for call in orphans:
            call.fail(DriverError(UNAVAILABLE, f"{call.verb}: driver for {self.robot} went away"))
        # Another process may still hold a token under the same name.
        self._query_liveliness()

    def _query_liveliness(self) -> None:
        """Ask which tokens exist now (the subscriber only reports changes)."""
        with self._lock:
            generation = self._liveliness_events
            if self._closed:
                return  # a token change racing close(): the session is going away

        def on_reply(reply: zenoh.Reply) -> None:
            if reply.ok is None:
                return
            with self._lock:
                if self._liveliness_events == generation and not self._closed:
                    self._alive = True
                    self._lock.notify_all()

        try:
            self._session.liveliness().get(keys.alive_key(self.robot), on_reply)
        except zenoh.ZError:
            if not self._closed:  # closed between the check above and the query: nothing to ask
                raise

    # --------------------------------------------------------------------- state

    def _on_state(self, sample: zenoh.Sample) -> None:
        try:
            state = codec.decode_state(sample.payload.to_bytes())
        except CodecError as exc:
            log.warning("ignoring malformed state on %s: %s", sample.key_expr, exc)
            return
        self._set_state(state)

    def _set_state(self, state: RobotState) -> None:
        with self._lock:
            if self._alive:
                self._state = state
                self._lock.notify_all()

    def state(self) -> RobotState:
        """The latest state the live driver published (or returned from ``release`` or
        ``reset``). Raises ``DriverError(unavailable)`` while no driver is alive or
        before the new driver's first publication."""
        with self._lock:
            if self._state is None:
                raise DriverError(UNAVAILABLE, f"no current state for {self.robot}: "
                                  f"{'none published yet' if self._alive else 'no driver alive'}")
            return self._state

    # --------------------------------------------------------------------- verbs

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        return self._call("move", lambda: MoveRequest(tuple(waypoints), None if face is None else tuple(face)))

    def sense(self, procedure: str) -> Future[SenseResult]:
        return self._call("sense", lambda: ProcedureRequest(procedure))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return self._call("grasp", lambda: ProcedureRequest(procedure))

    def release(self) -> Future[RobotState]:
        return self._call("release", EmptyRequest)

    def camera(self) -> Future[CameraImage]:
        return self._call("camera", EmptyRequest)

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        return self._call("reset", lambda: ResetRequest(world, seed))

    def noop(self) -> Future[None]:
        """Round trip to the driver node without touching the robot (health, benchmark)."""
        return self._call("noop", EmptyRequest)

    def _call(self, verb: str, build: Callable[[], Request]) -> Future[Any]:
        """Send ``verb``; ``build`` makes the request lazily so that a caller's bad
        argument (``tuple(None)``) lands in the future like every other failure."""
        future: Future[Any] = Future()
        future.set_running_or_notify_cancel()  # a robot verb under way cannot be called back
        try:
            payload = codec.encode_request(build())
        except (CodecError, TypeError) as exc:
            future.set_exception(DriverError(BAD_REQUEST, f"{verb}: {exc}"))
            return future
        call = _Call(self, verb, future, self.timeouts.of(verb))
        with self._lock:
            if self._closed:
                refusal = "the client is closed"
            elif not self._alive:
                refusal = f"no driver serves {self.robot} (no token on {keys.alive_key(self.robot)})"
            else:
                refusal = ""
                self._pending.add(call)
        if refusal:
            future.set_exception(DriverError(UNAVAILABLE, f"{verb}: {refusal}"))
            return future
        try:
            # Replies are handled on zenoh's own thread (indirect=False): it halves the
            # round trip's tail, at the price that a future's done-callbacks run there
            # and must not block (behaviours poll ``done()`` in ``update`` instead).
            self._session.get(keys.rpc_key(self.robot, verb),
                              zenoh.handlers.Callback(call.on_reply, call.on_done, indirect=False),
                              payload=payload, encoding=zenoh.Encoding.APPLICATION_JSON,
                              consolidation=zenoh.ConsolidationMode.NONE, timeout=call.timeout_s)
        except zenoh.ZError as exc:
            call.fail(DriverError(UNAVAILABLE, f"{verb}: {exc}"))
        return future

    def _forget(self, call: _Call) -> None:
        with self._lock:
            self._pending.discard(call)

    def close(self) -> None:
        """Stop following the driver; pending and later verbs fail with ``unavailable``."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            self._alive = False
            self._state = None
            orphans, self._pending = self._pending, set()
            self._lock.notify_all()
        for call in orphans:
            call.fail(DriverError(UNAVAILABLE, f"{call.verb}: the client is closed"))
        self._token_sub.undeclare()
        self._state_sub.undeclare()
        if self._owns_session:
            self._session.close()

    def __enter__(self) -> ZenohDriver:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()


class _Call:
    """One verb in flight: the first reply, the deadline or the driver's departure
    completes its future, whichever comes first."""

    def __init__(self, client: ZenohDriver, verb: str, future: Future[Any], timeout_s: float) -> None:
        self.client = client
        self.verb = verb
        self.future = future
        self.timeout_s = timeout_s
        self.started = time.monotonic()

    def _timed_out(self) -> bool:
        # zenoh finishes a query that outlived its timeout with a plain-text error
        # reply and then the drop; both are recognised by the time they arrive.
        return time.monotonic() - self.started >= self.timeout_s * 0.99

    def on_reply(self, reply: zenoh.Reply) -> None:
        if reply.ok is not None:
            try:
                result = codec.decode_result(self.verb, reply.ok.payload.to_bytes())
            except CodecError as exc:
                self.fail(DriverError(INTERNAL, f"{self.verb}: malformed reply from the driver: {exc}"))
                return
            if isinstance(result, RobotState):
                self.client._set_state(result)
            self.succeed(result)
            return
        try:
            error = codec.decode_error(reply.err.payload.to_bytes())
        except CodecError as exc:
            if self._timed_out():
                error = self._timeout()
            else:
                error = DriverError(INTERNAL, f"{self.verb}: malformed error reply from the driver: {exc}")
        self.fail(error)

    def on_done(self) -> None:
        if self._timed_out():
            self.fail(self._timeout())
        else:
            self.fail(DriverError(UNAVAILABLE, f"{self.verb}: no driver answered on "
                                  f"{keys.rpc_key(self.client.robot, self.verb)}"))

    def _timeout(self) -> DriverError:
        return DriverError(TIMEOUT, f"{self.verb}: no reply within {self.timeout_s:g} s")

    def succeed(self, result: Any) -> None:
        self.client._forget(self)
        try:
            self.future.set_result(result)
        except InvalidStateError:
            pass  # already completed by an earlier reply, the deadline or the token

    def fail(self, error: DriverError) -> None:
        self.client._forget(self)
        try:
            self.future.set_exception(error)
        except InvalidStateError:
            pass  # already completed by an earlier reply, the deadline or the token
