"""Does the robot turn, and take the time, that its replies say? And is it free when
it says so?

A driver can answer every verb in perfect JSON and still mislead every episode: a
heading in radians, or counted clockwise, sends the robot the wrong way to each test
position; a turn answered but not made leaves the sonar aimed at empty floor;
durations in milliseconds make a 45 s sweep cost 12.5 robot hours in the learned
grasp costs; a busy flag freed just after the reply refuses the executive's next
verb. These checks of ``csl driver check`` (:mod:`.conformance` runs them) hold the
driver to what docs/driver-protocol.md says:

- ``turns``: turns in place of TURNS_DEG, each answered with the heading changed by
  the asked amount (degrees, counter-clockwise from +x), and each seen in the
  overhead camera's heading marker (band images, or through the calibration the
  suite was given; a real camera's image without one is "not checked");
- ``durations``: each move's and a sense's ``duration_s`` within TIME_FACTOR of what
  the robot profile's speeds and procedure times give, and ``clock_s`` advancing by
  the durations;
- ``busy-release``: BUSY_CHAIN verbs, each sent the instant the previous reply
  arrived, none refused ``busy``: the robot is free before its reply is sent.

The turns and the durations share one series of moves (made once, by whichever check
runs first), so a real robot turns through them once.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType

from camera_model.bands import looks_like_bands
from hero_driver.interface import BUSY, NO_TARGET, OUT_OF_RANGE, DriverError, MoveResult, Pose, RobotState
from hero_driver.zenoh_link.camera_check import MappingError, Vision, robot_drawn, undistorted
from hero_driver.zenoh_link.checking import CheckFailed, Probe, decoded, describe, error_of, message, pose_json
from robot_profile import DEFAULT_PROFILE, RobotMotion, RobotProfile, load_profile
from zenoh_rpc.client import Reply

TURNS_DEG = (10.0, -10.0, -90.0, 90.0)  # the turns in place, in this order: back where it began
# A reply's heading may miss the asked one by the robot's own heading error: 5 sigma of
# the simulator's harsh preset (odometry_heading_deg 4). A heading in radians (a 90 deg
# turn answered as 1.6), counted clockwise (180 deg off on a 90 deg turn) or a turn not
# made (90 deg off) lies far outside it on the 90 deg turns.
REPLY_TURN_TOLERANCE_DEG = 20.0
# The camera sees the heading the robot truly has, which the reply reports: only the
# reading of the heading marker separates them (a small disc 2/3 of the base radius
# ahead of its centre: a few degrees per image, by bands or through a calibration), and
# a turn is two images. A turn made the other way round (20 deg off on a 10 deg turn)
# or not made (10 off; 90 off on the 90 deg turns) lies outside.
CAMERA_TURN_TOLERANCE_DEG = 8.0
# Durations may be this many times shorter or longer than the profile gives. The
# simulator's durations are the profile's formulas exactly under every noise preset
# (noise moves where the robot ends, never how long it took), so the factor is for a
# real robot's departures from its profile (acceleration, settling, a slower image
# pipeline); the unit mistakes it is there to catch are factors of 60 and 1000.
TIME_FACTOR = 3.0
# clock_s must advance by the durations within this share of them, plus (upwards) the
# wall-clock time between the two readings: a robot whose clock counts idle time too.
CLOCK_SLACK = 0.1
DRIVE_IN = 3.0  # the durations check drives this far straight ahead (short of sonar contact range)
FACE_AT_IN = 100.0  # ... after facing a point this far ahead (a move with `face`: sonar centring)
BUSY_CHAIN = 20  # verbs sent back to back, each on the previous reply


@dataclass(frozen=True)
class Timing:
    """What the robot profile says verbs take: the base's speeds and each sensing
    procedure's ``time_s``."""

    motion: RobotMotion
    sense_s: Mapping[str, float]

    @classmethod
    def from_profile(cls, profile: str | Path | RobotProfile | None = None) -> Timing:
        """From a robot profile, loaded or its file (default: the HERO 2000's)."""
        loaded = profile if isinstance(profile, RobotProfile) else load_profile(
            DEFAULT_PROFILE if profile is None else profile)
        return cls(loaded.robot.motion, MappingProxyType({p.name: float(p.time_s) for p in loaded.sensing}))


@dataclass(frozen=True)
class Turn:
    """One turn in place: what was asked, what the replies said, what the camera saw
    (the marker's bearing before and after; None: not read)."""

    asked_deg: float
    before: Pose
    result: MoveResult
    seen_before_deg: float | None
    seen_after_deg: float | None


@dataclass(frozen=True)
class _Turned:
    """The series of turns, with the clock read before and after them."""

    turns: tuple[Turn, ...]
    clock: _ClockSpan
    camera_note: str  # why the camera was not read ("" when it was)
    camera_failure: str  # what was wrong with an image ("" when nothing was)


@dataclass(frozen=True)
class _ClockSpan:
    """Two readings of ``clock_s`` (by ``release`` replies) and the wall-clock time between."""

    before_s: float
    after_s: float
    wall_s: float


def _wrapped(deg: float) -> float:
    """A heading difference in [-180, 180)."""
    return (deg + 180.0) % 360.0 - 180.0


class MotionChecks:
    """The ``turns``, ``durations`` and ``busy-release`` checks on one probe.

    ``sense`` is the sensing procedure the durations check applies where the robot
    stands (a long-range one); ``vision`` reads a real camera's images (None: band
    images, others not checked)."""

    def __init__(self, probe: Probe, timing: Timing, sense: str, vision: Vision | None = None) -> None:
        self.probe = probe
        self.timing = timing
        self.sense = sense
        self.vision = vision
        self._turned: _Turned | CheckFailed | None = None

    def checks(self) -> list[tuple[str, Callable[[], str]]]:
        return [("turns", self.turns), ("durations", self.durations), ("busy-release", self.busy_release)]

    # ------------------------------------------------------------------ the turns

    def _series(self) -> _Turned:
        """Make the turns once; later calls get the same record (or the same failure)."""
        if self._turned is None:
            try:
                self._turned = self._turn()
            except CheckFailed as exc:
                self._turned = exc
        if isinstance(self._turned, CheckFailed):
            raise CheckFailed(f"turning in place: {self._turned}")
        return self._turned

    def _turn(self) -> _Turned:
        start, wall = self._clock_reading()
        here = start.pose
        camera = _Camera(self.probe, self.vision)
        seen = camera.heading(here)
        turns = []
        for asked in TURNS_DEG:
            goal = {"x_in": here.x_in, "y_in": here.y_in, "heading_deg": _wrapped(here.heading_deg) + asked}
            result = self.probe.result("move", {"waypoints": [goal], "face": None})
            if result.collided:
                raise CheckFailed(f"a turn in place of {asked:+g} deg answered collided at {_pose_text(result.pose)}: "
                                  "give the robot room to turn")
            after = camera.heading(result.pose)
            turns.append(Turn(asked, here, result, seen, after))
            here, seen = result.pose, after
        end, wall_end = self._clock_reading()
        return _Turned(tuple(turns), _ClockSpan(start.clock_s, end.clock_s, wall_end - wall), camera.note,
                       camera.failure)

    def _clock_reading(self) -> tuple[RobotState, float]:
        """The robot's state by a ``release`` (a no-op with an empty hand) and when it came."""
        state = self.probe.result("release", {})
        return state, time.monotonic()

    def turns(self) -> str:
        """Each turn answered with the heading changed by the asked amount (within
        REPLY_TURN_TOLERANCE_DEG), and the camera's marker turned as the reply says
        (within CAMERA_TURN_TOLERANCE_DEG)."""
        series = self._series()
        if series.camera_failure:
            raise CheckFailed(f"camera: {series.camera_failure}")
        worst_reply, worst_seen = 0.0, 0.0
        for turn in series.turns:  # the replies first: a heading in the wrong unit is named as such
            said = _wrapped(turn.result.pose.heading_deg - turn.before.heading_deg)
            off = abs(said - turn.asked_deg)
            if off > REPLY_TURN_TOLERANCE_DEG:
                raise CheckFailed(f"asked a turn in place of {turn.asked_deg:+g} deg: the reply's heading went from "
                                  f"{turn.before.heading_deg:.1f} to {turn.result.pose.heading_deg:.1f} "
                                  f"({said:+.1f} deg){_reply_hint(turn, said)}")
            worst_reply = max(worst_reply, off)
        for turn in series.turns:
            if turn.seen_before_deg is None or turn.seen_after_deg is None:
                continue
            said = _wrapped(turn.result.pose.heading_deg - turn.before.heading_deg)
            seen = _wrapped(turn.seen_after_deg - turn.seen_before_deg)
            if abs(seen - said) > CAMERA_TURN_TOLERANCE_DEG:
                raise CheckFailed(f"asked a turn in place of {turn.asked_deg:+g} deg: the reply says {said:+.1f} deg, "
                                  f"the camera's heading marker turned {seen:+.1f} deg{_seen_hint(said, seen)}")
            worst_seen = max(worst_seen, abs(seen - said))
        asked = ", ".join(f"{t.asked_deg:+g}" for t in series.turns)
        camera = (f"the camera's heading marker turned as they say (within {worst_seen:.1f} deg)" if not series.camera_note
                  else f"camera not checked: {series.camera_note}")
        return f"turns of {asked} deg answered within {worst_reply:.1f} deg of the asked; {camera}"

    # ------------------------------------------------------------------ durations

    def durations(self) -> str:
        """The turns', a sense's, a face move's and a short drive's ``duration_s``
        within TIME_FACTOR of the profile's, and ``clock_s`` advancing by them."""
        motion = self.timing.motion
        series = self._series()
        for turn in series.turns:
            turning_s = abs(turn.asked_deg) / motion.turn_deg_per_s
            _within(f"a {turn.asked_deg:+g} deg turn in place", turn.result.duration_s, turning_s,
                    motion.vision_s + turning_s, f"turn_deg_per_s {motion.turn_deg_per_s:g}, vision_s {motion.vision_s:g}")
        _clock_follows("the turns", series.clock, sum(t.result.duration_s for t in series.turns))
        sensed = self._sense()
        start, wall = self._clock_reading()
        ahead = math.radians(start.pose.heading_deg)
        x, y = start.pose.x_in, start.pose.y_in
        face = [x + FACE_AT_IN * math.cos(ahead), y + FACE_AT_IN * math.sin(ahead)]
        faced = self.probe.result("move", {"waypoints": [pose_json(start.pose)], "face": face})
        _within(f"a move facing a point {FACE_AT_IN:g} in ahead", faced.duration_s,
                motion.centring_s if faced.centred else 0.0, motion.vision_s + motion.centring_s,
                f"centring_s {motion.centring_s:g}, vision_s {motion.vision_s:g}")
        here = faced.pose
        h = math.radians(here.heading_deg)
        goal = {"x_in": here.x_in + DRIVE_IN * math.cos(h), "y_in": here.y_in + DRIVE_IN * math.sin(h),
                "heading_deg": here.heading_deg}
        driven = self.probe.result("move", {"waypoints": [goal], "face": None})
        if driven.collided:
            raise CheckFailed(f"a drive of {DRIVE_IN:g} in straight ahead answered collided at "
                              f"{_pose_text(driven.pose)}: give the robot room ahead")
        driving_s = DRIVE_IN / motion.speed_in_per_s
        _within(f"a drive of {DRIVE_IN:g} in", driven.duration_s, driving_s, motion.vision_s + driving_s,
                f"speed_in_per_s {motion.speed_in_per_s:g}, vision_s {motion.vision_s:g}")
        end, wall_end = self._clock_reading()
        _clock_follows("a face move and a drive", _ClockSpan(start.clock_s, end.clock_s, wall_end - wall),
                       faced.duration_s + driven.duration_s)
        return (f"turns, a face move and a {DRIVE_IN:g} in drive took what the profile's speeds give "
                f"(within {TIME_FACTOR:g}x), and clock_s advanced by them; {sensed}")

    def _sense(self) -> str:
        """Apply the sensing procedure where the robot stands: its duration against its
        ``time_s`` and the clock against the duration; said "not checked" when nothing
        is in range (the reset pose of the shipped lab has nothing ahead)."""
        name = self.sense
        time_s = self.timing.sense_s.get(name)
        if time_s is None:
            return f"sense not checked: {name!r} is not a sensing procedure of the profile given"
        start, wall = self._clock_reading()
        outcome = self.probe.outcome("sense", {"procedure": name})
        if isinstance(outcome, DriverError):
            if outcome.code not in (OUT_OF_RANGE, NO_TARGET):
                raise CheckFailed(f"sense {name}: expected a result, {OUT_OF_RANGE} or {NO_TARGET}, got "
                                  f"{outcome.code}: {outcome.message}")
            return f"sense not checked: nothing to sense from here ({outcome.code}: {outcome.message})"
        _within(f"sense {name}", outcome.duration_s, time_s, time_s, f"its time_s {time_s:g}")
        end, wall_end = self._clock_reading()
        _clock_follows(f"sense {name}", _ClockSpan(start.clock_s, end.clock_s, wall_end - wall), outcome.duration_s)
        return f"sense {name} took {outcome.duration_s:g} s (time_s {time_s:g})"

    # ------------------------------------------------------------------ busy

    def busy_release(self) -> str:
        """BUSY_CHAIN verbs (a move to where the robot stands and a release, in turn),
        each sent the instant the previous reply arrived: none may be refused ``busy``,
        since the protocol frees the robot before it replies."""
        here = pose_json(self.probe.result("release", {}).pose)
        chain = _Chain(self.probe, [("move", message({"waypoints": [here], "face": None})) if i % 2 == 0
                                    else ("release", message({})) for i in range(BUSY_CHAIN)])
        replies = chain.run()
        previous = ["release", *chain.verbs]  # the first goes on the reply to the release that found the pose
        for i, (verb, reply) in enumerate(zip(chain.verbs, replies), start=1):
            if reply is None or reply.late:
                raise CheckFailed(f"verb {i} of the chain ({verb}): no reply before the timeout")
            if reply.ok is not None:
                decoded(verb, reply.ok)
                continue
            error = error_of(reply)
            if error.code == BUSY:
                raise CheckFailed(f"verb {i} of {BUSY_CHAIN} ({verb}), sent the instant the reply to the "
                                  f"{previous[i - 1]} before it arrived, was refused busy ({error.message}): free the "
                                  "robot before sending a reply")
            raise CheckFailed(f"verb {i} of the chain ({verb}): {describe(reply)}")
        return f"{BUSY_CHAIN} verbs (move and release in turn), each sent on the previous reply: none refused busy"


class _Camera:
    """Reads the robot's heading from overhead images, through the calibrated vision
    when the suite has one, else by the grey bands; after the first image it cannot
    read it stops reading and says why: a real camera's image without a calibration
    is not checked (:attr:`note`, as the other image checks do), an image that shows
    no robot is a failure (:attr:`failure`)."""

    def __init__(self, probe: Probe, vision: Vision | None) -> None:
        self.probe = probe
        self.vision = vision
        self.note = ""
        self.failure = ""

    def heading(self, pose: Pose) -> float | None:
        """The heading the camera shows for the robot near ``pose``; None when not read."""
        if self.note or self.failure:
            return None
        image = self.probe.result("camera", {})
        try:
            if self.vision is not None:
                robot = self.vision(image).robot
                if robot is None:
                    raise MappingError("the calibrated vision finds no robot")
                return robot.heading_deg
            return robot_drawn(image, pose).heading_deg
        except MappingError as exc:
            if self.vision is None and not looks_like_bands(undistorted(image)):
                self.note = ("the image is not drawn in the grey bands (a real camera's?): needs "
                             "--camera-calibration FILE")
            else:
                self.failure = str(exc)
            return None


class _Chain:
    """Verbs sent one after another from the reply callback of the one before (no
    thread in between: as soon as a client could), stopping at the first error."""

    def __init__(self, probe: Probe, calls: list[tuple[str, bytes]]) -> None:
        self.probe = probe
        self.calls = calls
        self.verbs = [verb for verb, _ in calls]
        self.replies: list[Reply | None] = []
        self.finished = threading.Event()

    def run(self) -> list[Reply | None]:
        self._send(0)
        self.finished.wait(len(self.calls) * (self.probe.timeout_s + 1.0))
        return list(self.replies)

    def _send(self, i: int) -> None:
        if i == len(self.calls):
            self.finished.set()
            return
        verb, payload = self.calls[i]
        got: list[Reply] = []

        def on_reply(reply: Reply) -> None:
            if got:
                return
            got.append(reply)
            self.replies.append(reply)
            if reply.ok is not None and not reply.late:
                self._send(i + 1)
            else:
                self.finished.set()

        def on_done(_late: bool) -> None:
            if not got:
                self.replies.append(None)
                self.finished.set()

        self.probe.rpc.send(verb, payload, self.probe.timeout_s, on_reply, on_done)


def _within(what: str, duration_s: float, low_s: float, high_s: float, basis: str) -> None:
    """``duration_s`` within TIME_FACTOR of [low_s, high_s]; CheckFailed naming the
    verb, the value and what the profile gives."""
    if low_s / TIME_FACTOR <= duration_s <= high_s * TIME_FACTOR:
        return
    given = f"{low_s:g} s" if low_s == high_s else f"{low_s:g}-{high_s:g} s"
    unit = (" (milliseconds? durations are seconds)" if duration_s > high_s * 100 else
            " (minutes? durations are seconds)" if 0 < duration_s < low_s / 30 else "")
    raise CheckFailed(f"{what} answered duration_s {duration_s:g}; the profile gives {given} ({basis}), "
                      f"at most {TIME_FACTOR:g}x off{unit}")


def _clock_follows(what: str, span: _ClockSpan, durations_s: float) -> None:
    """``clock_s`` advanced by ``durations_s`` across ``span`` (within CLOCK_SLACK of
    them; upwards also by the wall-clock time between the readings)."""
    advanced = span.after_s - span.before_s
    low = durations_s * (1.0 - CLOCK_SLACK)
    high = durations_s * (1.0 + CLOCK_SLACK) + span.wall_s
    if low <= advanced <= high:
        return
    raise CheckFailed(f"clock_s went from {span.before_s:g} to {span.after_s:g} (+{advanced:g} s) over {what}, whose "
                      f"durations add up to {durations_s:g} s: the clock must advance by the robot time its verbs "
                      "take, in seconds")


def _reply_hint(turn: Turn, said: float) -> str:
    """Why a reply's heading may be off: radians, the wrong sign, no turn."""
    as_degrees = _wrapped(math.degrees(turn.result.pose.heading_deg) - math.degrees(turn.before.heading_deg))
    if abs(as_degrees - turn.asked_deg) <= REPLY_TURN_TOLERANCE_DEG:
        return ": a heading in radians? headings are degrees"
    if abs(said + turn.asked_deg) <= REPLY_TURN_TOLERANCE_DEG:
        return ": the wrong way round? headings count counter-clockwise from +x"
    if abs(said) <= REPLY_TURN_TOLERANCE_DEG:
        return ": no turn"
    return ""


def _seen_hint(said: float, seen: float) -> str:
    if abs(seen) <= CAMERA_TURN_TOLERANCE_DEG:
        return ": the robot did not turn, or the reply is not where it is"
    if abs(seen + said) <= CAMERA_TURN_TOLERANCE_DEG:
        return ": it turned the other way round (headings count counter-clockwise from +x, seen from above)"
    return ""


def _pose_text(pose: Pose) -> str:
    return f"({pose.x_in:.1f}, {pose.y_in:.1f}, {pose.heading_deg:.1f} deg)"
