"""The driver node: serves any :class:`~hero_driver.interface.Driver` on zenoh.

A hardware team that writes its driver in Python implements the ``Driver`` protocol
and hands it to :func:`serve`; the simulated HERO is served the same way by
``csl driver sim``. The node owns everything protocol-shaped (keys, JSON, error
replies, liveliness, state publications) so that a driver only deals in interface
dataclasses; the transport plumbing it shares with the learner service comes from
:mod:`zenoh_rpc`.

Verbs are serialised: the robot does one thing at a time, and a verb that arrives
while another is still executing is refused at once with ``busy`` rather than queued
(a queue would hide a second controller fighting over the robot and make the
client's per-verb timeouts meaningless). ``noop`` and ``hello`` touch no robot and
are answered even while a verb runs, so a health ping and a client's version
handshake never wait on a move.

Every robot verb is bounded (the verb table's ``bound_s``): a driver whose future
has not completed by then gets it cancelled (a driver that can stop its motors makes
its futures cancellable and stops them when they are), the caller is answered
``timeout`` and the robot is free for the next verb. A result that still arrives
later is logged and dropped. So a hung action costs one verb, never the robot.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Future
from types import MappingProxyType
from typing import Any

import zenoh

from hero_driver.interface import (
    BAD_REQUEST,
    BUSY,
    ERROR_CODES,
    INTERNAL,
    TIMEOUT,
    UNKNOWN_VERB,
    BlockedMoves,
    Charger,
    Driver,
    DriverError,
)
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import MAX_REQUEST_BYTES, CodecError, Request
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.verbs import BY_NAME, NAMES, VERBS, Verb, offers
from hero_driver.zenoh_link.versions import VERB_FEATURES, Greeting, greeting
from robot_profile import ProfileStamp
from zenoh_rpc.server import JSON, RpcServer, payload_of, reply
from zenoh_rpc.config import UserConfig
from zenoh_rpc.serving import serve_until

log = logging.getLogger(__name__)

STATE_PERIOD_S = 0.2  # 5 Hz state publications between verbs


def verb_bounds(overrides: Mapping[str, float] | None = None) -> Mapping[str, float]:
    """The bound of every robot verb: the verb table's, with ``overrides`` (verb name
    to seconds) laid over it. ValueError names a verb that has no bound or a bound
    that is not a positive number of seconds."""
    bounds = {verb.name: verb.bound_s for verb in VERBS if verb.bound_s is not None}
    for name, seconds in (overrides or {}).items():
        if name not in bounds:
            raise ValueError(f"verb bound: {name!r} is not a robot verb (verbs: {', '.join(bounds)})")
        if not (isinstance(seconds, (int, float)) and math.isfinite(seconds) and seconds > 0):
            raise ValueError(f"verb bound: {name} must be a positive number of seconds, got {seconds!r}")
        bounds[name] = float(seconds)
    return MappingProxyType(bounds)


class _Action:
    """One robot verb under way: answered exactly once, by the driver's result or by
    the node's bound, whichever comes first."""

    def __init__(self, verb: Verb, query: zenoh.Query, future: Future[Any], bound_s: float) -> None:
        self.verb, self.query, self.future, self.bound_s = verb, query, future, bound_s
        self._lock = threading.Lock()
        self._answered = False
        self.timer: threading.Timer | None = None

    def claim(self) -> bool:
        """True for the first caller only: the one who answers the query."""
        with self._lock:
            first, self._answered = not self._answered, True
        if first and self.timer is not None:
            self.timer.cancel()
        return first


class DriverNode:
    """Declares the protocol's keys for ``driver`` on ``session`` until :meth:`close`.

    The session stays the caller's: closing the node undeclares what it declared
    (the liveliness token first, so clients stop sending) and leaves the session open.
    """

    def __init__(self, driver: Driver, session: zenoh.Session, *, profile: ProfileStamp | None = None,
                 state_period_s: float = STATE_PERIOD_S, bounds: Mapping[str, float] | None = None) -> None:
        self.driver = driver
        self.bounds = verb_bounds(bounds)  # seconds each robot verb may run before it is cancelled
        self.profile = profile  # hello names it: the robot this node serves
        keys = robot_keys(driver.robot)
        self.robot = keys.name
        self._driver_lock = threading.Lock()  # the driver object is called by one thread at a time
        self._busy_lock = threading.Lock()
        self._busy_verb: str | None = None
        self._action: _Action | None = None  # the robot verb under way, if any
        self._stopping = threading.Event()
        self._publisher = session.declare_publisher(keys.state, encoding=JSON)
        self._publish_state()
        self._ticker = threading.Thread(target=self._tick, args=(state_period_s,),
                                        name=f"hero-{self.robot}-state", daemon=True)
        self._ticker.start()
        # The queryables, then the token: state is already flowing when a client sees it.
        self._server = RpcServer(session, keys, NAMES, self._serve, _error_body,
                                 bad_request=BAD_REQUEST, unknown_verb=UNKNOWN_VERB)

    # ------------------------------------------------------------------ lifecycle

    def close(self) -> None:
        """Stop serving: undeclare the token, the queryables and the publisher."""
        if self._stopping.is_set():
            return
        self._stopping.set()
        self._server.close()
        with self._busy_lock:
            action = self._action
        if action is not None and action.timer is not None:
            action.timer.cancel()
        self._ticker.join()
        self._publisher.undeclare()

    def __enter__(self) -> DriverNode:
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------- queries

    def _serve(self, name: str, query: zenoh.Query) -> None:
        verb = BY_NAME[name]
        try:
            future = self._start(verb, verb.decode_request(payload_of(query)))
        except CodecError as exc:
            self._server.reply_error(query, BAD_REQUEST, str(exc))
            return
        except DriverError as exc:
            self._server.reply_error(query, exc.code, exc.message)
            return
        except Exception as exc:  # the node outlives any driver bug
            log.exception("driver %s failed to start %s", self.robot, name)
            self._server.reply_error(query, INTERNAL, f"{name}: {type(exc).__name__}: {exc}")
            return
        if not verb.touches_robot:
            future.add_done_callback(lambda done: self._answer(verb, query, done))
            return
        action = _Action(verb, query, future, self.bounds[verb.name])
        with self._busy_lock:
            self._action = action
        if not future.done():  # the simulator's verbs are: no timer thread for them
            action.timer = threading.Timer(action.bound_s, self._overrun, (action,))
            action.timer.daemon = True
            action.timer.start()
        future.add_done_callback(lambda _done: self._finish(action))

    def _start(self, verb: Verb, request: Request) -> Future[Any]:
        if not verb.touches_robot:
            return verb.call(self.greeting(), request)
        with self._busy_lock:
            if self._busy_verb is not None:
                raise DriverError(BUSY, f"{verb.name}: the robot is still executing {self._busy_verb}")
            self._busy_verb = verb.name
        try:
            with self._driver_lock:
                return verb.call(self.driver, request)
        except BaseException:
            self._release_busy()
            raise

    def greeting(self) -> Greeting:
        """The answer to ``hello``, asked afresh each time: a ``reset`` may have put the
        robot in a world with another charging dock, or none (no ``battery`` feature)."""
        dock = self.driver.dock() if isinstance(self.driver, Charger) else None
        safety = self.driver.safety_in() if isinstance(self.driver, BlockedMoves) else None
        offered = [feature for feature in VERB_FEATURES if offers(self.driver, feature)]
        return greeting(self.profile, dock, safety, offered)

    def _finish(self, action: _Action) -> None:
        """The driver completed ``action``: answer it, unless its bound already did."""
        if not action.claim():
            if not action.future.cancelled():
                log.warning("driver %s: %s completed after its %g s bound had answered timeout; result dropped",
                            self.robot, action.verb.name, action.bound_s)
            return
        self._release_busy()
        self._publish_state()  # sent ahead of the reply: clients see the new state soon
        self._answer(action.verb, action.query, action.future)

    def _overrun(self, action: _Action) -> None:
        """``action`` outlived its bound: cancel it, answer ``timeout``, free the robot."""
        if not action.claim():
            return
        action.future.cancel()  # stops a driver whose futures are cancellable; a no-op otherwise
        self._release_busy()
        if self._stopping.is_set():
            return
        log.warning("driver %s: %s overran its %g s bound; cancelled", self.robot, action.verb.name, action.bound_s)
        try:
            self._server.reply_error(
                action.query, TIMEOUT, f"{action.verb.name}: overran the driver's bound of {action.bound_s:g} s; cancelled")
        except zenoh.ZError:  # a close racing the bound: the client learns from the token instead
            pass
        self._publish_state()

    def _answer(self, verb: Verb, query: zenoh.Query, done: Future[Any]) -> None:
        try:
            payload = verb.encode_result(done.result())
        except DriverError as exc:
            self._server.reply_error(query, exc.code, exc.message)
        except CodecError as exc:
            log.error("driver %s returned a malformed %s result: %s", self.robot, verb.name, exc)
            self._server.reply_error(query, INTERNAL, f"{verb.name}: driver returned a malformed result: {exc}")
        except Exception as exc:
            log.exception("driver %s failed during %s", self.robot, verb.name)
            self._server.reply_error(query, INTERNAL, f"{verb.name}: {type(exc).__name__}: {exc}")
        else:
            reply(query, payload)

    def _release_busy(self) -> None:
        with self._busy_lock:
            self._busy_verb = None
            self._action = None

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


def _error_body(code: str, message: str) -> bytes:
    if code not in ERROR_CODES:  # a driver's own invention: still answer, as a driver fault
        code, message = INTERNAL, f"driver answered with unknown error code {code!r}: {message}"
    return codec.encode_error(code, message)


def serve(driver: Driver, *, listen: Sequence[str], stop: threading.Event,
          on_ready: Callable[[], None] | None = None, zenoh_config: UserConfig | None = None,
          profile: ProfileStamp | None = None, bounds: Mapping[str, float] | None = None) -> None:
    """Serve ``driver`` on its own session listening on ``listen`` until ``stop`` is set.

    ``profile`` is the robot profile the driver serves, named in the ``hello`` reply so
    a client can refuse a robot it did not plan for (None: the node does not say).

    ``on_ready`` runs once every key is declared (the CLI prints a line there).
    ``zenoh_config`` is the user's zenoh config file: its authentication and access
    control are what keep other sessions from driving the robot (docs/security.md).
    ``bounds`` overrides the verb table's bounds (verb name to seconds; :func:`verb_bounds`).
    Raises ConnectionError (an OSError) when a listen endpoint cannot be opened.
    """
    checked = verb_bounds(bounds)  # refused before a session opens
    serve_until(stop, listen, lambda session: DriverNode(driver, session, profile=profile, bounds=checked),
                on_ready, zenoh_config, max_request_bytes=MAX_REQUEST_BYTES)
