"""The conformance suite behind ``csl driver check``: is a driver process, written in
any language, a faithful server of ``docs/driver-protocol.md``?

It talks raw zenoh (not :class:`~hero_driver.zenoh_link.client.ZenohDriver`) so that it
can send what a well-behaved client never would (malformed JSON, wrong types, an
unknown verb, another protocol version) and it decodes every reply with the strict
codec, so a driver whose replies the executive would reject fails here first, with
the check and the field named.

The robot must start from its reset pose with nothing within contact range of the
sonar; the suite only turns the robot in place, so it is safe to run on hardware.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import zenoh

from hero_driver.interface import (
    BAD_REQUEST,
    NO_TARGET,
    OUT_OF_RANGE,
    PROTOCOL_VERSION,
    UNKNOWN_PROCEDURE,
    UNKNOWN_VERB,
    DriverError,
    GraspResult,
    MoveResult,
    RobotState,
    SenseResult,
)
from hero_driver.zenoh_link import codec
from hero_driver.zenoh_link.codec import CodecError
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.verbs import BY_NAME
from zenoh_rpc.client import Reply, RpcClient
from zenoh_rpc.config import open_session
from robot_profile import DEFAULT_PROFILE, load_profile

STATE_WINDOW_S = 1.5  # listen this long for periodic state publications
MIN_STATE_PUBLICATIONS = 2  # ... and expect at least this many (the node sends 5 Hz)
TURN_DEG = 10.0  # the move check turns in place by this much
POSE_TOLERANCE = 0.5  # inches or degrees between a move's reply and the next state
NOT_HERE = (OUT_OF_RANGE, NO_TARGET)  # what sensing or grasping from the reset pose may answer


@dataclass(frozen=True)
class CheckResult:
    """One named check: passed or not, and what was seen."""

    name: str
    passed: bool
    detail: str


@dataclass(frozen=True)
class Procedures:
    """Which of the robot's procedures the suite exercises."""

    sense: str  # one with a long range: usable from anywhere
    near: str  # one with the shortest range: out of range from the reset pose
    grasp: str  # a contact grasp: out of range from the reset pose, so nothing is lifted

    @classmethod
    def from_profile(cls, profile: str | Path | None = None) -> Procedures:
        """Pick them from a knowledge profile (default: the HERO 2000's)."""
        loaded = load_profile(DEFAULT_PROFILE if profile is None else profile)
        sensing = sorted(loaded.sensing, key=lambda p: (-p.range_in[1], p.time_s))
        grasping = sorted(loaded.grasping, key=lambda p: (p.range_in[1], p.time_s))
        near = min(sensing, key=lambda p: (p.range_in[1], p.time_s))
        return cls(sensing[0].name, near.name, grasping[0].name)


class CheckFailed(Exception):
    """A check's expectation was not met; the text says what was seen instead."""


class _Probe:
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
        reply = self.ask(verb, _message(fields))
        if reply is None or reply.ok is None:
            raise CheckFailed(_describe(reply))
        return _decoded(verb, reply.ok)

    def outcome(self, verb: str, fields: dict[str, object]) -> Any:
        """Call a verb that may succeed or answer a protocol error: the decoded
        result or the :class:`DriverError`."""
        reply = self.ask(verb, _message(fields))
        if reply is not None and reply.ok is not None:
            return _decoded(verb, reply.ok)
        return _error(reply)

    def refusal(self, verb: str, payload: bytes, codes: Sequence[str], field: str = "") -> str:
        """Send a request that must be refused with one of ``codes`` (and, for a bad
        field, a message naming it); a one-line account of the refusal."""
        error = _error(self.ask(verb, payload))
        if error.code not in codes:
            raise CheckFailed(f"{verb}: expected {' or '.join(codes)}, got {error.code}: {error.message}")
        if field and field not in error.message:
            raise CheckFailed(f"{verb}: {error.code} message does not name '{field}': {error.message}")
        return f"{error.code}: {error.message}"


def _message(fields: dict[str, object]) -> bytes:
    return json.dumps({"v": PROTOCOL_VERSION, **fields}, ensure_ascii=False).encode("utf-8")


def _decoded(verb: str, body: bytes) -> Any:
    try:
        return BY_NAME[verb].decode_result(body)
    except CodecError as exc:
        raise CheckFailed(f"malformed reply: {exc}") from None


def _error(reply: Reply | None) -> DriverError:
    """The protocol error a reply carries; CheckFailed for a result or no reply."""
    if reply is None or reply.err is None:
        raise CheckFailed(_describe(reply) if reply is None else "expected an error reply, got a result")
    try:
        return codec.decode_error(reply.err)
    except CodecError as exc:
        raise CheckFailed(f"malformed error reply: {exc}") from None


def _describe(reply: Reply | None) -> str:
    if reply is None or reply.err is None:
        return "no reply (nothing serves the key)"
    try:
        error = codec.decode_error(reply.err)
    except CodecError as exc:
        return f"malformed error reply: {exc}"
    return f"error reply {error.code}: {error.message}"


def _valid_states(bodies: Sequence[bytes]) -> list[RobotState]:
    states = []
    for body in bodies:
        try:
            states.append(codec.decode_state(body))
        except CodecError as exc:
            raise CheckFailed(f"malformed state publication: {exc}") from None
    return states


# -------------------------------------------------------------------------- the checks


class _Suite:
    """The checks, in the order they run; each returns a detail or raises CheckFailed."""

    def __init__(self, probe: _Probe, procedures: Procedures) -> None:
        self.probe = probe
        self.procedures = procedures
        self.last_state: RobotState | None = None
        self.moved: tuple[float, MoveResult] | None = None

    def checks(self) -> list[tuple[str, Callable[[], str]]]:
        return [
            ("liveliness", self.liveliness),
            ("state-published", self.state_published),
            ("noop", self.noop),
            ("camera", self.camera),
            ("move", self.move),
            ("state-after-move", self.state_after_move),
            ("reset", self.reset),
            ("sense", self.sense),
            ("grasp", self.grasp),
            ("release", self.release),
            ("out-of-range-target", self.out_of_range),
            ("unknown-verb", self.unknown_verb),
            ("unknown-procedure", self.unknown_procedure),
            ("malformed-json", self.malformed_json),
            ("wrong-types", self.wrong_types),
            ("missing-field", self.missing_field),
            ("unknown-field", self.unknown_field),
            ("non-finite-number", self.non_finite),
            ("wrong-version", self.wrong_version),
            ("keeps-serving", self.keeps_serving),
        ]

    def liveliness(self) -> str:
        key = self.probe.rpc.keys.alive
        found = threading.Event()
        finished = threading.Event()
        self.probe.rpc.query_alive(found.set, finished.set, self.probe.timeout_s)
        finished.wait(self.probe.timeout_s + 1.0)
        if not found.is_set():
            raise CheckFailed(f"no liveliness token on {key}")
        return f"token on {key}"

    def state_published(self) -> str:
        since = time.monotonic()
        time.sleep(STATE_WINDOW_S)
        states = _valid_states(self.probe.states_since(since))
        self.last_state = states[-1] if states else None
        if len(states) < MIN_STATE_PUBLICATIONS:
            raise CheckFailed(f"{len(states)} publications on {self.probe.rpc.keys.state} "
                              f"in {STATE_WINDOW_S:g} s, expected at least {MIN_STATE_PUBLICATIONS}")
        return f"{len(states)} valid publications in {STATE_WINDOW_S:g} s"

    def noop(self) -> str:
        self.probe.result("noop", {})
        return "answered"

    def reset(self) -> str:
        state = self.probe.result("reset", {"world": None, "seed": None})
        if state.clock_s != 0:
            raise CheckFailed(f"clock_s is {state.clock_s} after a move and a reset, expected 0")
        return f"pose {_pose_text(state)}"

    def camera(self) -> str:
        image = self.probe.result("camera", {})
        height, width = image.pixels.shape
        return f"{width}x{height} px at {image.inches_per_pixel:g} in/px"

    def move(self) -> str:
        if self.last_state is None:
            raise CheckFailed("needs a state publication to know where to turn in place")
        pose = self.last_state.pose
        goal = {"x_in": pose.x_in, "y_in": pose.y_in, "heading_deg": pose.heading_deg + TURN_DEG}
        sent = time.monotonic()
        result = self.probe.result("move", {"waypoints": [goal], "face": None})
        self.moved = (sent, result)
        return f"turned in place to {_pose_text(result)} in {result.duration_s:g} s"

    def state_after_move(self) -> str:
        if self.moved is None:
            raise CheckFailed("needs the move check to pass")
        sent, result = self.moved
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline:
            for state in _valid_states(self.probe.states_since(sent)):
                if _same_pose(state, result):
                    return f"published {_pose_text(state)}"
            time.sleep(0.05)
        raise CheckFailed(f"no state publication with the move's final pose {_pose_text(result)} within 1 s")

    def sense(self) -> str:
        name = self.procedures.sense
        outcome = self.probe.outcome("sense", {"procedure": name})
        return _procedure_outcome(outcome, SenseResult, name)

    def grasp(self) -> str:
        name = self.procedures.grasp
        outcome = self.probe.outcome("grasp", {"procedure": name})
        return _procedure_outcome(outcome, GraspResult, name)

    def release(self) -> str:
        state = self.probe.result("release", {})
        return f"pose {_pose_text(state)}"

    def out_of_range(self) -> str:
        self.probe.result("reset", {"world": None, "seed": None})
        return self.probe.refusal("sense", _message({"procedure": self.procedures.near}), NOT_HERE)

    def unknown_verb(self) -> str:
        return self.probe.refusal("fly", _message({}), (UNKNOWN_VERB,))

    def unknown_procedure(self) -> str:
        sensed = self.probe.refusal("sense", _message({"procedure": "No-Such-Procedure"}),
                                    (UNKNOWN_PROCEDURE,))
        self.probe.refusal("grasp", _message({"procedure": "No-Such-Grasp"}), (UNKNOWN_PROCEDURE,))
        return sensed

    def malformed_json(self) -> str:
        return self.probe.refusal("sense", b'{"v": 1, "procedure": ', (BAD_REQUEST,))

    def wrong_types(self) -> str:
        detail = self.probe.refusal("sense", _message({"procedure": 42}), (BAD_REQUEST,), "procedure")
        self.probe.refusal("move", _message({"waypoints": "north", "face": None}), (BAD_REQUEST,),
                           "waypoints")
        self.probe.refusal("reset", _message({"world": None, "seed": "seven"}), (BAD_REQUEST,), "seed")
        return detail

    def missing_field(self) -> str:
        detail = self.probe.refusal("sense", _message({}), (BAD_REQUEST,), "procedure")
        self.probe.refusal("move", _message({"waypoints": [{"x_in": 1.0, "heading_deg": 0.0}]}),
                           (BAD_REQUEST,), "y_in")
        return detail

    def unknown_field(self) -> str:
        return self.probe.refusal("sense", _message({"procedure": self.procedures.sense, "speed": 2}),
                                  (BAD_REQUEST,), "speed")

    def non_finite(self) -> str:
        payload = b'{"v": 1, "waypoints": [{"x_in": NaN, "y_in": 0, "heading_deg": 0}], "face": null}'
        return self.probe.refusal("move", payload, (BAD_REQUEST,), "x_in")

    def wrong_version(self) -> str:
        body = {"procedure": self.procedures.sense}
        detail = self.probe.refusal("sense", json.dumps({**body, "v": PROTOCOL_VERSION + 98}).encode(),
                                    (BAD_REQUEST,), "v")
        self.probe.refusal("sense", json.dumps(body).encode(), (BAD_REQUEST,), "v")
        return detail

    def keeps_serving(self) -> str:
        since = time.monotonic()
        self.probe.result("noop", {})
        state = self.probe.result("release", {})
        deadline = time.monotonic() + 1.0
        while not self.probe.states_since(since):
            if time.monotonic() > deadline:
                raise CheckFailed("no state publication after the bad requests")
            time.sleep(0.05)
        return f"still answering at {_pose_text(state)}"


def _pose_text(value: RobotState | MoveResult) -> str:
    pose = value.pose
    return f"({pose.x_in:.1f}, {pose.y_in:.1f}, {pose.heading_deg:.1f} deg)"


def _same_pose(state: RobotState, result: MoveResult) -> bool:
    a, b = state.pose, result.pose
    turn = (a.heading_deg - b.heading_deg + 180.0) % 360.0 - 180.0
    return (abs(a.x_in - b.x_in) <= POSE_TOLERANCE and abs(a.y_in - b.y_in) <= POSE_TOLERANCE
            and abs(turn) <= POSE_TOLERANCE)


def _procedure_outcome(outcome: Any, kind: type, name: str) -> str:
    if isinstance(outcome, DriverError):
        if outcome.code not in NOT_HERE:
            raise CheckFailed(f"expected a result or {' or '.join(NOT_HERE)}, got {outcome.code}: "
                              f"{outcome.message}")
        return f"{outcome.code}: {outcome.message}"
    if not isinstance(outcome, kind) or outcome.procedure != name:
        raise CheckFailed(f"reply does not echo procedure {name!r}")
    return f"{kind.__name__} in {outcome.duration_s:g} s"


def run_checks(robot: str, connect: Sequence[str], *, timeout_s: float = 30.0,
               procedures: Procedures | None = None) -> list[CheckResult]:
    """Run every check against the driver serving ``robot`` at ``connect``."""
    robot_keys(robot)
    if not timeout_s > 0:
        raise ValueError(f"timeout must be a positive number of seconds, got {timeout_s}")
    chosen = procedures if procedures is not None else Procedures.from_profile()
    session = open_session(connect=connect)
    probe = _Probe(session, robot, timeout_s)
    try:
        probe.rpc.wait_alive(timeout_s)  # time to connect; the liveliness check reports a missing token
        results = []
        for name, check in _Suite(probe, chosen).checks():
            try:
                results.append(CheckResult(name, True, check()))
            except CheckFailed as exc:
                results.append(CheckResult(name, False, str(exc)))
        return results
    finally:
        probe.close()
        session.close()


def format_table(results: Sequence[CheckResult]) -> str:
    """The pass/fail table ``csl driver check`` prints."""
    width = max(len("check"), *(len(r.name) for r in results))
    lines = [f"{'check':<{width}}  result  detail"]
    lines += [f"{r.name:<{width}}  {'PASS' if r.passed else 'FAIL':<6}  {r.detail}" for r in results]
    failed = sum(not r.passed for r in results)
    lines.append(f"{len(results)} checks: {len(results) - failed} passed, {failed} failed")
    return "\n".join(lines)
