"""What every conformance check is made of (:mod:`.conformance` and the checks beside
it): a raw probe of one robot's keys that can send what a well-behaved client never
would, the strict decoding of its replies, and the one-line failures a check raises.
Kept apart from the suite so that a group of checks can live in a module of its own
without importing the suite that runs it."""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import zenoh

from hero_driver.interface import PROTOCOL_VERSION, DriverError, MoveResult, Pose, RobotState
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.verbs import BY_NAME
from zenoh_rpc.client import Reply, RpcClient

POSE_TOLERANCE = 0.5  # inches or degrees between a move's reply and the next state


@dataclass(frozen=True)
class CheckResult:
    """One named check: passed or not, and what was seen."""

    name: str
    passed: bool
    detail: str



class CheckFailed(Exception):
    """A check's expectation was not met; the text says what was seen instead."""


def run_check(name: str, check: Callable[[], str]) -> CheckResult:
    """``check()``'s result as ``name``'s: passed with what it saw, or failed with
    what :class:`CheckFailed` said."""
    try:
        return CheckResult(name, True, check())
    except CheckFailed as exc:
        return CheckResult(name, False, str(exc))


class Probe:
    """Raw queries and state publications of one robot on one session."""

    def __init__(self, session: zenoh.Session, robot: str, timeout_s: float) -> None:
        self.rpc = RpcClient(session, robot_keys(robot))
        self.timeout_s = timeout_s
        self._states: list[tuple[float, bytes]] = []
        self._lock = threading.Lock()
        self._subscriber = session.declare_subscriber(self.rpc.keys.state, self._on_state)

    def _on_state(self, sample: zenoh.Sample) -> None:
        with self._lock:
            self._states.append((time.monotonic(), sample.payload.to_bytes()))

    def states_since(self, since: float) -> list[bytes]:
        with self._lock:
            return [body for at, body in self._states if at >= since]

    def close(self) -> None:
        self._subscriber.undeclare()

    def ask(self, verb: str, payload: bytes) -> Reply | None:
        """Send ``payload`` to ``rpc/<verb>``: the one reply (CheckFailed for more),
        or None when none came."""
        answer = self.rpc.ask(verb, payload, self.timeout_s)
        if answer.late:  # zenoh ends an unanswered query with a plain-text error reply of its own
            raise CheckFailed("no reply before the timeout")
        if len(answer.replies) > 1:
            raise CheckFailed(f"{len(answer.replies)} replies to one query, expected exactly one")
        return answer.first

    def result(self, verb: str, fields: dict[str, object]) -> Any:
        """Call a verb that must succeed; its decoded result."""
        reply = self.ask(verb, message(fields))
        if reply is None or reply.ok is None:
            raise CheckFailed(describe(reply))
        return decoded(verb, reply.ok)

    def outcome(self, verb: str, fields: dict[str, object]) -> Any:
        """Call a verb that may succeed or answer a protocol error: the decoded
        result or the :class:`DriverError`."""
        reply = self.ask(verb, message(fields))
        if reply is not None and reply.ok is not None:
            return decoded(verb, reply.ok)
        return error_of(reply)

    def refusal(self, verb: str, payload: bytes, codes: Sequence[str], field: str = "") -> str:
        """Send a request that must be refused with one of ``codes`` (and, for a bad
        field, a message naming it); a one-line account of the refusal."""
        error = error_of(self.ask(verb, payload))
        if error.code not in codes:
            raise CheckFailed(f"{verb}: expected {' or '.join(codes)}, got {error.code}: {error.message}")
        if field and field not in error.message:
            raise CheckFailed(f"{verb}: {error.code} message does not name '{field}': {error.message}")
        return f"{error.code}: {error.message}"


def message(fields: dict[str, object]) -> bytes:
    return json.dumps({"v": PROTOCOL_VERSION, **fields}, ensure_ascii=False).encode("utf-8")


def decoded(verb: str, body: bytes) -> Any:
    try:
        return BY_NAME[verb].decode_result(body)
    except CodecError as exc:
        raise CheckFailed(f"malformed reply: {exc}") from None


def error_of(reply: Reply | None) -> DriverError:
    """The protocol error a reply carries; CheckFailed for a result or no reply."""
    if reply is None or reply.err is None:
        raise CheckFailed(describe(reply) if reply is None else "expected an error reply, got a result")
    try:
        return codec.decode_error(reply.err)
    except CodecError as exc:
        raise CheckFailed(f"malformed error reply: {exc}") from None


def describe(reply: Reply | None) -> str:
    if reply is None or reply.err is None:
        return "no reply (nothing serves the key)"
    try:
        error = codec.decode_error(reply.err)
    except CodecError as exc:
        return f"malformed error reply: {exc}"
    return f"error reply {error.code}: {error.message}"


def valid_states(bodies: Sequence[bytes]) -> list[RobotState]:
    states = []
    for body in bodies:
        try:
            states.append(codec.decode_state(body))
        except CodecError as exc:
            raise CheckFailed(f"malformed state publication: {exc}") from None
    return states



class Timed:
    """One query sent without waiting: its first reply and when it came."""

    def __init__(self) -> None:
        self.sent = time.monotonic()
        self.reply: Reply | None = None
        self.at = 0.0
        self.finished = threading.Event()

    def on_reply(self, reply: Reply) -> None:
        if self.reply is None:
            self.reply, self.at = reply, time.monotonic()

    def on_done(self, _late: bool) -> None:
        self.finished.set()


def pose_json(pose: Pose) -> dict[str, float]:
    return {"x_in": pose.x_in, "y_in": pose.y_in, "heading_deg": pose.heading_deg}


def pose_text(value: RobotState | MoveResult) -> str:
    pose = value.pose
    return f"({pose.x_in:.1f}, {pose.y_in:.1f}, {pose.heading_deg:.1f} deg)"


def same_pose(state: RobotState, result: MoveResult) -> bool:
    a, b = state.pose, result.pose
    turn = (a.heading_deg - b.heading_deg + 180.0) % 360.0 - 180.0
    return (abs(a.x_in - b.x_in) <= POSE_TOLERANCE and abs(a.y_in - b.y_in) <= POSE_TOLERANCE
            and abs(turn) <= POSE_TOLERANCE)



def outcome_text(outcome: object) -> str:
    return f"{outcome.code}: {outcome.message}" if isinstance(outcome, DriverError) else type(outcome).__name__
