"""The zenoh client: a :class:`~hero_driver.interface.Driver` whose robot is another
process (the simulated HERO node or a hardware driver) reached through zenoh.

Every verb sends one query and returns a future at once; the reply, an error reply,
the query's deadline or the driver's liveliness token vanishing completes it, so a
behaviour never blocks a tick on the network. The client follows the driver's
liveliness token rather than its connection: when the token goes, in-flight verbs
fail with ``unavailable`` and new ones fail at once; when a driver process (the same
or a new one) declares the token again, the same client object simply works again,
because zenoh routes the queries to whoever serves the keys.

Each driver process that appears is first asked ``hello``: the client uses the
highest protocol version both ends speak and refuses, with one line, a driver it
shares none with (:mod:`.versions` states the policy).

Futures complete on zenoh's network thread: a done-callback must be quick and must
never wait on another verb's future there.
"""

from __future__ import annotations

import inspect
import logging
import threading
from collections.abc import Callable, Iterable, Mapping, Sequence
from concurrent.futures import Future, InvalidStateError
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import zenoh

from hero_driver.interface import (
    BAD_REQUEST,
    INTERNAL,
    TIMEOUT,
    UNAVAILABLE,
    UNKNOWN_VERB,
    DriverError,
    Pose,
    RobotState,
    protocol_method,
)
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError, EmptyRequest, Request
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.state_check import StateCheck
from hero_driver.zenoh_link.verbs import BY_NAME, VERBS, Verb
from hero_driver.zenoh_link.versions import BEFORE_HELLO, VERB_FEATURES, Agreement, Greeting, NoCommonVersion, agree
from robot_profile import ProfileStamp
from zenoh_rpc.client import Reply, RpcClient
from zenoh_rpc.config import UserConfig, close_session, open_session
from zenoh_rpc.endpoints import DRIVER_ENDPOINT

log = logging.getLogger(__name__)


@dataclass(frozen=True, init=False)
class VerbTimeouts:
    """Wall-clock seconds a verb may take before its future fails with ``timeout``.

    Built as ``VerbTimeouts(move_s=0.3)``: every verb not named keeps its default
    from the verb table, generous because a real HERO moves at half an inch a second
    and a fine sonar sweep takes minutes; the simulator answers in milliseconds.
    """

    seconds: tuple[tuple[str, float], ...]
    _by_verb: Mapping[str, float] = field(init=False, repr=False, compare=False)  # of() runs on every call

    def __init__(self, **overrides: float) -> None:
        known = {f"{verb.name}_s": verb.timeout_s for verb in VERBS}
        for name, value in overrides.items():
            if name not in known:
                raise TypeError(f"VerbTimeouts has no {name!r} (verbs: {', '.join(known)})")
            if not value > 0:
                raise ValueError(f"{name} must be a positive number of seconds, got {value}")
        chosen = {**known, **overrides}
        object.__setattr__(self, "seconds", tuple((name.removesuffix("_s"), float(chosen[name]))
                                                  for name in known))
        object.__setattr__(self, "_by_verb", MappingProxyType(dict(self.seconds)))

    @classmethod
    def of_verbs(cls, seconds: Iterable[tuple[str, float]]) -> VerbTimeouts:
        """From (verb, seconds) pairs, as a command line gives them: ValueError, one
        line, for a name that is not a verb or a verb given twice."""
        chosen: dict[str, float] = {}
        for verb, value in seconds:
            if verb not in BY_NAME:
                raise ValueError(f"{verb!r} is not a verb (verbs: {', '.join(BY_NAME)})")
            if verb in chosen:
                raise ValueError(f"{verb} is given twice")
            chosen[verb] = value
        return cls(**{f"{verb}_s": value for verb, value in chosen.items()})

    def of(self, verb: str) -> float:
        """The timeout of ``verb``."""
        return self._by_verb[verb]


def _robot_verbs(cls: type) -> type:
    """Give the client one method per robot verb of the verb table, so a verb added to
    the table needs no method written here: each has the signature and the docstring
    of the ``Driver`` protocol's declaration (``hero_driver.interface``), which makes
    the client a ``Driver`` (and a ``Charger``, a ``BlockedMoves``) method for method."""
    for verb in VERBS:
        if verb.touches_robot:
            setattr(cls, verb.name, _verb_method(cls, verb))
    return cls


def _verb_method(cls: type, verb: Verb) -> Callable[..., Future[Any]]:
    """``cls``'s method for ``verb``: its arguments, checked against the protocol's
    signature as a written method's would be (TypeError at the call), become the
    fields of the same names of the verb's request, sent by :meth:`ZenohDriver._call`."""
    declared = protocol_method(verb.driver_verb)
    signature = inspect.signature(declared)
    names = verb.driver_verb.args

    def method(self: ZenohDriver, *args: Any, **kwargs: Any) -> Future[Any]:
        given = signature.bind(self, *args, **kwargs)
        given.apply_defaults()
        return self._call(verb.name, lambda: verb.request.value(**{name: given.arguments[name] for name in names}))

    method.__name__ = verb.name
    method.__qualname__ = f"{cls.__name__}.{verb.name}"
    method.__module__ = cls.__module__
    method.__doc__ = declared.__doc__
    method.__signature__ = signature  # type: ignore[attr-defined]
    method.__annotations__ = dict(declared.__annotations__)
    return method


@_robot_verbs
class ZenohDriver:
    """Drives the robot served on ``hero/<robot>/...`` by some driver process.

    ``connect`` lists the driver nodes' endpoints, reached with the user's zenoh config
    file ``zenoh_config`` (credentials, TLS) if given; pass ``session`` instead to
    share an open session (the client then leaves it open on :meth:`close`). The
    constructor waits up to ``discover_s`` for a driver's liveliness token, so a
    driver that is already up is usable straight away; one that starts later is
    picked up when its token appears (see :attr:`alive`, :meth:`wait_ready`).
    Either way the driver is asked ``hello`` first; a driver that shares no protocol
    version with this client is refused with ``DriverError(unavailable)`` (raised by
    the constructor or :meth:`wait_ready`, and by every verb's future).
    """

    def __init__(self, robot: str = "r1", *, connect: Sequence[str] = (DRIVER_ENDPOINT,),
                 timeouts: VerbTimeouts = VerbTimeouts(), session: zenoh.Session | None = None,
                 discover_s: float = 1.0, zenoh_config: UserConfig | None = None) -> None:
        self._keys = robot_keys(robot)
        self.robot = self._keys.name
        self.timeouts = timeouts
        self._owns_session = session is None
        self._session = open_session(connect=connect, user=zenoh_config) if session is None else session
        self._rpc = RpcClient(self._session, self._keys)
        self._lock = threading.Condition()
        self._alive = False
        self._liveliness_events = 0  # bumped by every token change, to ignore stale queries
        self._state: RobotState | None = None
        self._agreement: Agreement | None = None  # with the live driver, once it answered hello
        self._greeting: Greeting | None = None  # its hello (profile, dock), once agreed on a version
        self._refusal: str | None = None  # why the live driver cannot be used, if it cannot
        self._pending: set[_Call] = set()
        self._check = StateCheck()  # what a state publication may say, from what was asked
        self.refused_states = 0  # publications nothing asked of the robot explains (each logged)
        self._closed = False
        self._state_sub = self._session.declare_subscriber(self._keys.state, self._on_state)
        self._token_sub = self._rpc.watch_alive(self._on_token)
        self._query_liveliness()
        with self._lock:  # the session may still be connecting: give the token a moment
            if self._lock.wait_for(lambda: self._alive, discover_s):
                self._lock.wait_for(self._greeted, self.timeouts.of("hello") + 1.0)
            refusal = self._refusal
        if refusal is not None:
            self.close()
            raise DriverError(UNAVAILABLE, refusal)

    # ------------------------------------------------------------------ liveness

    @property
    def alive(self) -> bool:
        """True while a driver's liveliness token for this robot is visible."""
        with self._lock:
            return self._alive

    @property
    def agreement(self) -> Agreement | None:
        """The protocol version and features agreed with the live driver; None until
        it has answered ``hello`` (or while none is alive or it cannot be used)."""
        with self._lock:
            return self._agreement

    @property
    def profile(self) -> ProfileStamp | None:
        """The robot profile the live driver says it serves (the ``profile`` feature);
        None when it does not say (a driver from before the feature) or has not yet
        answered ``hello``. A caller compares it with the profile it plans with."""
        with self._lock:
            return None if self._greeting is None else self._greeting.profile

    def dock(self) -> Pose | None:
        """Where the live driver's base charges (the ``battery`` feature, from its
        ``hello``); None without the feature or before ``hello`` was answered, which
        leaves the executive's low-battery guard off."""
        with self._lock:
            return None if self._greeting is None else self._greeting.dock

    def safety_in(self) -> float | None:
        """How near ahead a moving obstacle stops the live driver's moves (the
        ``blocked_moves`` feature, from its ``hello``); None without the feature or
        before ``hello`` was answered, which leaves the blocked-move branch off."""
        with self._lock:
            return None if self._greeting is None else self._greeting.safety_in

    def wait_ready(self, timeout_s: float) -> bool:
        """Wait until a driver is alive, agreed on a version and published its state;
        False on timeout. Raises ``DriverError(unavailable)`` when the live driver
        shares no protocol version with this client."""
        with self._lock:
            ready = self._lock.wait_for(
                lambda: self._refusal is not None or (self._alive and self._greeted() and self._state is not None),
                timeout_s)
            refusal = self._refusal
        if refusal is not None:
            raise DriverError(UNAVAILABLE, refusal)
        return ready

    def wait_gone(self, timeout_s: float) -> bool:
        """Wait until no driver is alive; False on timeout."""
        with self._lock:
            return self._lock.wait_for(lambda: not self._alive, timeout_s)

    def _on_token(self, appeared: bool) -> None:
        if appeared:
            with self._lock:
                self._liveliness_events += 1
                self._alive = not self._closed
                self._lock.notify_all()
            self._greet()
            return
        with self._lock:
            self._liveliness_events += 1
            orphans = self._lose_driver()
        for call in orphans:
            call.fail(DriverError(UNAVAILABLE, f"{call.verb}: driver for {self.robot} went away"))
        # Another process may still hold a token under the same name.
        self._query_liveliness()

    def _lose_driver(self) -> set[_Call]:
        """With the lock held: no driver, no state; the verbs in flight, to fail."""
        self._alive = False
        self._state = None
        self._check.forget()
        self._agreement = self._refusal = self._greeting = None
        orphans, self._pending = self._pending, set()
        self._lock.notify_all()
        return orphans

    def _query_liveliness(self) -> None:
        """Ask which tokens exist now (the subscriber only reports changes)."""
        with self._lock:
            generation = self._liveliness_events
            if self._closed:
                return  # a token change racing close(): the session is going away

        def on_found() -> None:
            with self._lock:
                if self._liveliness_events != generation or self._closed:
                    return
                self._alive = True
                self._lock.notify_all()
            self._greet()

        try:
            self._rpc.query_alive(on_found)
        except zenoh.ZError:
            if not self._closed:  # closed between the check above and the query: nothing to ask
                raise

    # ----------------------------------------------------------------- versions

    def _greeted(self) -> bool:
        """With the lock held: the live driver's hello is settled, either way."""
        return self._agreement is not None or self._refusal is not None

    def _greet(self) -> None:
        """Ask the driver that just appeared what it serves, and agree on a version."""
        with self._lock:
            if self._closed:
                return
            generation = self._liveliness_events
            self._agreement = self._refusal = self._greeting = None
        self.hello().add_done_callback(lambda answered: self._settle(generation, answered))

    def _settle(self, generation: int, answered: Future[Greeting]) -> None:
        try:
            greeting = answered.result()
        except DriverError as exc:
            # No hello (unknown_verb), no catch-all to say so (unavailable), or a
            # hello that failed: the protocol as it was before hello, version 1.
            if exc.code != UNKNOWN_VERB:
                log.warning("driver %s did not answer hello (%s); assuming protocol version 1", self.robot, exc)
            greeting = Greeting(BEFORE_HELLO)
        try:
            agreement, refusal = agree(greeting.served), None
        except NoCommonVersion as exc:
            agreement, refusal = None, f"robot {self.robot}: {exc}"
        with self._lock:
            if self._liveliness_events == generation and self._alive and not self._closed:
                self._agreement, self._refusal = agreement, refusal
                self._greeting = greeting if agreement is not None else None
                self._lock.notify_all()

    # --------------------------------------------------------------------- state

    def _on_state(self, sample: zenoh.Sample) -> None:
        try:
            state = codec.decode_state(sample.payload.to_bytes())
        except CodecError as exc:
            log.warning("ignoring malformed state on %s: %s", sample.key_expr, exc)
            return
        self._set_state(state, published=True)

    def _set_state(self, state: RobotState, published: bool = False) -> None:
        """Believe ``state``: a verb's own reply always, a publication when what was
        asked of the robot explains it (:class:`StateCheck`); one that nothing explains
        is refused, counted and logged, and the last believed state stays. A stale
        publication (older than the state believed) is dropped without a count."""
        with self._lock:
            if not self._alive:
                return
            if published and self._check.stale(state):
                log.debug("%s: stale state publication dropped (clock %.1f s)", self.robot, state.clock_s)
                return
            why = self._check.judge(state) if published else ""
            if why:
                self.refused_states += 1
                log.warning("%s: state publication refused: %s", self.robot, why)
                return
            if not published:
                self._check.last = state
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
    # The robot verbs (move, sense, grasp, release, camera, reset, charge, wait) are
    # made from the verb table by _robot_verbs; the node's own verbs are written here.

    def noop(self) -> Future[None]:
        """Round trip to the driver node without touching the robot (health, benchmark)."""
        return self._call("noop", EmptyRequest)

    def hello(self) -> Future[Greeting]:
        """Which protocol versions and optional features the driver process serves,
        and the robot profile when it says."""
        return self._call("hello", EmptyRequest)

    def _call(self, verb: str, build: Callable[[], Request]) -> Future[Any]:
        """Send ``verb``; ``build`` makes the request lazily so that a caller's bad
        argument (``tuple(None)``) lands in the future like every other failure."""
        future: Future[Any] = Future()
        future.set_running_or_notify_cancel()  # a robot verb under way cannot be called back
        try:
            payload = BY_NAME[verb].encode_request(build())
        except (CodecError, TypeError) as exc:
            future.set_exception(DriverError(BAD_REQUEST, f"{verb}: {exc}"))
            return future
        call = _Call(self, verb, future, self.timeouts.of(verb))
        with self._lock:
            lacking = self._lacking(verb)
            if lacking:
                future.set_exception(DriverError(UNKNOWN_VERB, lacking))
                return future
            if self._closed:
                refusal = "the client is closed"
            elif not self._alive:
                refusal = f"no driver serves {self.robot} (no token on {self._keys.alive})"
            elif self._refusal is not None:
                refusal = self._refusal
            else:
                refusal = ""
                self._pending.add(call)
                self._check.started(verb)
        if refusal:
            future.set_exception(DriverError(UNAVAILABLE, f"{verb}: {refusal}"))
            return future
        try:
            # Futures complete on zenoh's thread: behaviours poll ``done()`` in
            # ``update`` rather than block in a done-callback.
            self._rpc.send(verb, payload, call.timeout_s, call.on_reply, call.on_done)
        except zenoh.ZError as exc:
            call.fail(DriverError(UNAVAILABLE, f"{verb}: {exc}"))
        return future

    def _lacking(self, verb: str) -> str:
        """With the lock held: why the live driver cannot serve ``verb``, a verb of a
        feature that brings only verbs (:data:`~.versions.VERB_FEATURES`) which its
        ``hello`` did not list; "" otherwise, or before its ``hello`` is answered. Such
        a verb is used only with a driver that lists its feature (docs/driver-protocol.md,
        Versioning), so it fails here at once, as the driver would answer it."""
        row = BY_NAME[verb]
        feature = row.driver_verb.feature if row.touches_robot else None
        if feature not in VERB_FEATURES or self._agreement is None or feature in self._agreement.features:
            return ""
        return f"{verb}: this driver has no {feature} feature (see its hello)"

    def _forget(self, call: _Call, pose: Pose | None = None) -> None:
        """``call`` is over; ``pose``: where its reply says the robot ended, if it says."""
        with self._lock:
            if call in self._pending:
                self._pending.discard(call)
                self._check.finished(call.verb, pose)

    def close(self) -> None:
        """Stop following the driver; pending and later verbs fail with ``unavailable``."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            orphans = self._lose_driver()
        for call in orphans:
            call.fail(DriverError(UNAVAILABLE, f"{call.verb}: the client is closed"))
        self._token_sub.undeclare()
        self._state_sub.undeclare()
        if self._owns_session:
            close_session(self._session)

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

    def on_reply(self, reply: Reply) -> None:
        if reply.ok is not None:
            try:
                result = BY_NAME[self.verb].decode_result(reply.ok)
            except CodecError as exc:
                self.fail(DriverError(INTERNAL, f"{self.verb}: malformed reply from the driver: {exc}"))
                return
            if isinstance(result, RobotState):
                self.client._set_state(result)
            self._complete(lambda: self.future.set_result(result), getattr(result, "pose", None))
            return
        try:
            error = codec.decode_error(reply.err or b"")
        except CodecError as exc:
            if reply.late:  # zenoh's own plain-text end of an unanswered query
                error = self._timeout()
            else:
                error = DriverError(INTERNAL, f"{self.verb}: malformed error reply from the driver: {exc}")
        self.fail(error)

    def on_done(self, late: bool) -> None:
        if late:
            self.fail(self._timeout())
        else:
            self.fail(DriverError(UNAVAILABLE, f"{self.verb}: no driver answered on "
                                  f"{self.client._keys.rpc(self.verb)}"))

    def _timeout(self) -> DriverError:
        return DriverError(TIMEOUT, f"{self.verb}: no reply within {self.timeout_s:g} s")

    def fail(self, error: DriverError) -> None:
        self._complete(lambda: self.future.set_exception(error))

    def _complete(self, settle: Callable[[], None], pose: Pose | None = None) -> None:
        self.client._forget(self, pose)
        try:
            settle()
        except InvalidStateError:
            pass  # already completed by an earlier reply, the deadline or the token
