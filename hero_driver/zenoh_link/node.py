"""The driver node: serves any :class:`~hero_driver.interface.Driver` on zenoh.

A hardware team that writes its driver in Python implements the ``Driver`` protocol
and hands it to :func:`serve`; the simulated HERO is served the same way by
``csl driver sim``. The node owns everything protocol-shaped (keys, JSON, error
replies, liveliness, state publications) so that a driver only deals in interface
dataclasses.

Verbs are serialised: the robot does one thing at a time, and a verb that arrives
while another is still executing is refused at once with ``busy`` rather than queued
(a queue would hide a second controller fighting over the robot and make the
client's per-verb timeouts meaningless). ``noop`` touches no robot and is answered
even while a verb runs, so it stays usable as a health ping.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from typing import Any

import zenoh

from hero_driver.interface import (
    BAD_REQUEST,
    BUSY,
    ERROR_CODES,
    INTERNAL,
    UNKNOWN_VERB,
    Driver,
    DriverError,
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
from hero_driver.zenoh_link.config import open_session

log = logging.getLogger(__name__)

STATE_PERIOD_S = 0.2  # 5 Hz state publications between verbs


class DriverNode:
    """Declares the protocol's keys for ``driver`` on ``session`` until :meth:`close`.

    The session stays the caller's: closing the node undeclares what it declared
    (the liveliness token first, so clients stop sending) and leaves the session open.
    """

    def __init__(self, driver: Driver, session: zenoh.Session, *,
                 state_period_s: float = STATE_PERIOD_S) -> None:
        self.driver = driver
        self.robot = keys.check_robot(driver.robot)
        self._session = session
        self._driver_lock = threading.Lock()  # the driver object is called by one thread at a time
        self._busy_lock = threading.Lock()
        self._busy_verb: str | None = None
        self._stopping = threading.Event()
        self._publisher = session.declare_publisher(keys.state_key(self.robot),
                                                    encoding=zenoh.Encoding.APPLICATION_JSON)
        self._queryables = [
            session.declare_queryable(keys.rpc_key(self.robot, verb), self._handler(verb),
                                      complete=True)
            for verb in keys.VERBS
        ]
        self._queryables.append(
            session.declare_queryable(keys.rpc_prefix(self.robot), self._on_other_key))
        self._publish_state()
        self._ticker = threading.Thread(target=self._tick, args=(state_period_s,),
                                        name=f"hero-{self.robot}-state", daemon=True)
        self._ticker.start()
        # Declared last: a client that sees the token finds every queryable in place.
        self._token = session.liveliness().declare_token(keys.alive_key(self.robot))

    # ------------------------------------------------------------------ lifecycle

    def close(self) -> None:
        """Stop serving: undeclare the token, the queryables and the publisher."""
        if self._stopping.is_set():
            return
        self._stopping.set()
        self._token.undeclare()
        for queryable in self._queryables:
            queryable.undeclare()
        self._ticker.join()
        self._publisher.undeclare()

    def __enter__(self) -> DriverNode:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------- queries

    def _handler(self, verb: str) -> Callable[[zenoh.Query], None]:
        exact_key = keys.rpc_key(self.robot, verb)

        def on_query(query: zenoh.Query) -> None:
            # A wildcard query (hero/r1/rpc/*) also reaches this queryable; it must not
            # run the verb. The catch-all answers it.
            if str(query.key_expr) != exact_key:
                query.drop()
                return
            self._serve(verb, query)

        return on_query

    def _on_other_key(self, query: zenoh.Query) -> None:
        key = str(query.key_expr)
        verb = key.removeprefix(keys.rpc_key(self.robot, ""))
        if verb in keys.VERBS and "/" not in verb:
            query.drop()  # served by the verb's own queryable
        elif any(c in key for c in "*$"):
            _reply_error(query, BAD_REQUEST, f"{key}: verbs must be addressed by their exact key")
        else:
            _reply_error(query, UNKNOWN_VERB,
                         f"{verb!r} is not a verb (known: {', '.join(keys.VERBS)})")

    def _serve(self, verb: str, query: zenoh.Query) -> None:
        try:
            request = codec.decode_request(verb, _payload(query))
            future = self._start(verb, request)
        except CodecError as exc:
            _reply_error(query, BAD_REQUEST, str(exc))
            return
        except DriverError as exc:
            _reply_error(query, exc.code, exc.message)
            return
        except Exception as exc:  # the node outlives any driver bug
            log.exception("driver %s failed to start %s", self.robot, verb)
            _reply_error(query, INTERNAL, f"{verb}: {type(exc).__name__}: {exc}")
            return
        future.add_done_callback(lambda done: self._finish(verb, query, done))

    def _start(self, verb: str, request: Request) -> Future[Any]:
        if verb == keys.NOOP:
            done: Future[None] = Future()
            done.set_result(None)
            return done
        with self._busy_lock:
            if self._busy_verb is not None:
                raise DriverError(BUSY, f"{verb}: the robot is still executing {self._busy_verb}")
            self._busy_verb = verb
        try:
            with self._driver_lock:
                return _call(self.driver, verb, request)
        except BaseException:
            self._release_busy()
            raise

    def _finish(self, verb: str, query: zenoh.Query, done: Future[Any]) -> None:
        if verb != keys.NOOP:
            self._release_busy()
            self._publish_state()  # sent ahead of the reply: clients see the new state soon
        try:
            payload = codec.encode_result(verb, done.result())
        except DriverError as exc:
            _reply_error(query, exc.code, exc.message)
        except CodecError as exc:
            log.error("driver %s returned a malformed %s result: %s", self.robot, verb, exc)
            _reply_error(query, INTERNAL, f"{verb}: driver returned a malformed result: {exc}")
        except Exception as exc:
            log.exception("driver %s failed during %s", self.robot, verb)
            _reply_error(query, INTERNAL, f"{verb}: {type(exc).__name__}: {exc}")
        else:
            query.reply(query.key_expr, payload, encoding=zenoh.Encoding.APPLICATION_JSON)
            query.drop()

    def _release_busy(self) -> None:
        with self._busy_lock:
            self._busy_verb = None

    # --------------------------------------------------------------------- state

    def _tick(self, period_s: float) -> None:
        while not self._stopping.wait(period_s):
            self._publish_state()

    def _publish_state(self) -> None:
        if self._stopping.is_set():
            return
        try:
            with self._driver_lock:
                state = self.driver.state()
            payload = codec.encode_state(state)
        except Exception as exc:  # a bad state must not stop the node; clients see none
            log.error("driver %s: cannot publish its state: %s", self.robot, exc)
            return
        try:
            self._publisher.put(payload)
        except zenoh.ZError:
            if not self._stopping.is_set():  # only a close racing this put is expected
                raise


def _call(driver: Driver, verb: str, request: Request) -> Future[Any]:
    """Start ``verb`` on the driver with the decoded request."""
    match verb, request:
        case "move", MoveRequest(waypoints=waypoints, face=face):
            return driver.move(list(waypoints), face)
        case "sense", ProcedureRequest(procedure=procedure):
            return driver.sense(procedure)
        case "grasp", ProcedureRequest(procedure=procedure):
            return driver.grasp(procedure)
        case "reset", ResetRequest(world=world, seed=seed):
            return driver.reset(world, seed)
        case "release", EmptyRequest():
            return driver.release()
        case "camera", EmptyRequest():
            return driver.camera()
    raise ValueError(f"no driver call for {verb} with {request!r}")


def _payload(query: zenoh.Query) -> bytes:
    return b"" if query.payload is None else query.payload.to_bytes()


def _reply_error(query: zenoh.Query, code: str, message: str) -> None:
    if code not in ERROR_CODES:  # a driver's own invention: still answer, as a driver fault
        code, message = INTERNAL, f"driver answered with unknown error code {code!r}: {message}"
    query.reply_err(codec.encode_error(code, message), encoding=zenoh.Encoding.APPLICATION_JSON)
    query.drop()


def serve(driver: Driver, *, listen: Sequence[str], stop: threading.Event,
          on_ready: Callable[[], None] | None = None) -> None:
    """Serve ``driver`` on its own session listening on ``listen`` until ``stop`` is set.

    ``on_ready`` runs once every key is declared (the CLI prints a line there).
    Raises OSError when a listen endpoint cannot be opened.
    """
    session = open_session(listen=listen)
    try:
        with DriverNode(driver, session):
            if on_ready is not None:
                on_ready()
            stop.wait()
    finally:
        session.close()
