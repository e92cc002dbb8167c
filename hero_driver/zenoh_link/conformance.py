"""The conformance suite behind ``csl driver check``: is a driver process, written in
any language, a faithful server of ``docs/driver-protocol.md``?

It talks raw zenoh (not :class:`~hero_driver.zenoh_link.client.ZenohDriver`) so that it
can send what a well-behaved client never would (malformed JSON, wrong types, an
unknown verb, another protocol version) and it decodes every reply with the strict
codec, so a driver whose replies the executive would reject fails here first, with
the check and the field named.

The camera checks read band images by their grey bands and a real camera's images
through its calibration, with the executive's vision (``vision``, given by ``csl driver
check --camera-calibration``); a non-band image without one is "not checked".

The robot must start from its reset pose with nothing within contact range of the
sonar; the suite turns the robot in place and drives it a few inches straight ahead
(:mod:`.motion_check`), so it is safe to run on hardware. The reference checks after it
(:mod:`.reference_check`), which drive round objects an operator placed, run only once
the operator was asked (or said ``--placed`` when starting the suite, or the driver, a
simulator, placed them itself).
Against a robot nobody serves (no token, no answer), and against a driver that names
another robot profile than the one given, it stops after one line: every later check
would only repeat that.

:func:`shutdown_order` is the one check the suite cannot run by itself, since it needs
the driver to stop: it pings while someone stops the driver and tells whether the
liveliness token went before the queryables did.
"""

from __future__ import annotations

import json
import math
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import zenoh

from camera_model.bands import looks_like_bands
from camera_model.image import CameraImage
from hero_driver.interface import (
    BAD_REQUEST, BUSY, NO_TARGET, OUT_OF_RANGE, PROTOCOL_VERSION, UNKNOWN_PROCEDURE, UNKNOWN_VERB, DriverError, GraspResult, MoveResult, Pose, RobotState, SenseResult,
)
from hero_driver.sim.catalogue import load_catalogue
from hero_driver.sim.worldfile import WORLDS_DIR, load_world
from hero_driver.zenoh_link.camera_check import (MappingError, PlacedObject, Sight, Vision, check_objects_drawn,
                                                 check_objects_seen, check_robot_drawn, check_robot_seen, undistorted)
from hero_driver.zenoh_link.checking import (POSE_TOLERANCE, CheckFailed, CheckResult, Probe, Timed, decoded, describe,
                                              error_of, message, outcome_text, pose_json, pose_text, same_pose,
                                              run_check, valid_states)
from hero_driver.zenoh_link.keys import robot_keys
from hero_driver.zenoh_link.motion_check import MotionChecks, Timing
from hero_driver.zenoh_link.reference_check import NOT_CHECKED, Reference, reference_checks
from hero_driver.zenoh_link.scan_check import ScanChecks
from hero_driver.zenoh_link.verbs import VERBS
from hero_driver.zenoh_link.versions import NoCommonVersion, agree
from zenoh_rpc.client import Reply, RpcClient
from zenoh_rpc.config import UserConfig, open_session
from hero_driver.zenoh_link.versions import BATTERY, BLOCKED_MOVES, Greeting
from robot_profile import DEFAULT_PROFILE, ProfileStamp, RobotProfile, load_profile

STATE_WINDOW_S = 1.5  # listen this long for periodic state publications
MIN_STATE_PUBLICATIONS = 2  # ... and expect at least this many (the node sends 5 Hz)
TURN_DEG = 10.0  # the move check turns in place by this much
FACE_AHEAD_IN = 100.0  # ... and then faces a point this far straight ahead
NOT_HERE = (OUT_OF_RANGE, NO_TARGET)  # what sensing or grasping from the reset pose may answer
BUSY_PROBE_S = 0.1  # while the busy check's turn runs, a release goes every this often
BUSY_PROBES = 20  # ... at most this many
KNOWN_WORLD = "lab"  # the shipped world the reset-objects check restores (hero_driver/worlds/lab.json)
CROSSING_WORLD = "crossing"  # the shipped world of the blocked-moves check (hero_driver/worlds/crossing.json)
CROSSING_DRIVE_IN = 170.0  # ... which drives this far straight ahead, across the person's line
WAIT_CHECK_S = 1.0  # ... and waits this long first
START_TOLERANCE_IN = 1.0  # the reset pose vs the world's start pose (inches, degrees)
PING_PERIOD_S = 0.02  # the shutdown check sends a noop this often ...
PING_TIMEOUT_S = 2.0  # ... each waiting this long for its reply
WARM_PINGS = 5  # ... and stops the driver once this many were answered
WARM_S = 1.0  # ... or this long after the first, whichever comes first
SHUTDOWN_RACE_S = 0.25  # a noop sent this close before the token's DELETE arrived may miss the driver
NEEDS_CALIBRATION = ("not checked: the image is not drawn in the grey bands (a real camera's?): needs "
                     "--camera-calibration FILE (csl camera calibrate, docs/camera.md)")


@dataclass(frozen=True)
class Procedures:
    """Which of the robot's procedures the suite exercises."""

    sense: str  # one with a long range: usable from anywhere
    near: str  # one with the shortest range: out of range from the reset pose
    grasp: str  # a contact grasp: out of range from the reset pose, so nothing is lifted

    @classmethod
    def from_profile(cls, profile: str | Path | RobotProfile | None = None) -> Procedures:
        """Pick them from a knowledge profile, loaded or its file (default: the HERO 2000's)."""
        loaded = profile if isinstance(profile, RobotProfile) else load_profile(
            DEFAULT_PROFILE if profile is None else profile)
        sensing = sorted(loaded.sensing, key=lambda p: (-p.range_in[1], p.time_s))
        grasping = sorted(loaded.grasping, key=lambda p: (p.range_in[1], p.time_s))
        near = min(sensing, key=lambda p: (p.range_in[1], p.time_s))
        return cls(sensing[0].name, near.name, grasping[0].name)


# -------------------------------------------------------------------------- the checks


class _Suite:
    """The checks, in the order they run; each returns a detail or raises CheckFailed."""

    def __init__(self, probe: Probe, procedures: Procedures, profile: ProfileStamp | None = None,
                 vision: Vision | None = None, timing: Timing | None = None) -> None:
        self.probe = probe
        self.procedures = procedures
        self.profile = profile  # what the driver should serve; None: not compared
        self.vision = vision  # how a real camera's images are read; None: band images
        self.last_state: RobotState | None = None
        self.moved: tuple[float, MoveResult] | None = None
        self.image: CameraImage | None = None
        self.greeting: Greeting | None = None
        self.motion = MotionChecks(probe, timing or Timing.from_profile(), procedures.sense, vision)
        self.scans = ScanChecks(probe, lambda: () if self.greeting is None else self.greeting.served.features)
        self.lab_refused = False  # reset-objects found a driver that cannot restore KNOWN_WORLD (a real robot)

    def checks(self) -> list[tuple[str, Callable[[], str]]]:
        return [
            ("liveliness", self.liveliness),
            ("state-published", self.state_published),
            ("noop", self.noop),
            ("hello", self.hello),
            ("profile", self.profile_served),
            ("camera", self.camera),
            ("camera-mapping", self.camera_mapping),
            ("move", self.move),
            ("state-after-move", self.state_after_move),
            ("busy", self.busy),
            *self.motion.checks(),  # turns, durations, busy-release (motion_check.py)
            ("reset", self.reset),
            ("reset-objects", self.reset_objects),
            ("sense", self.sense),
            ("grasp", self.grasp),
            ("release", self.release),
            ("charge", self.charge),
            ("blocked-moves", self.blocked_moves),
            *self.scans.checks(),  # scan, scan-repeat, scan-turn, scan-drive (scan_check.py)
            ("out-of-range-target", self.out_of_range),
            ("unknown-verb", self.unknown_verb),
            ("unknown-procedure", self.unknown_procedure),
            ("malformed-json", self.malformed_json),
            ("not-utf8", self.not_utf8),
            ("not-an-object", self.not_an_object),
            ("every-verb", self.every_verb),
            ("wildcard-silence", self.wildcard_silence),
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
        states = valid_states(self.probe.states_since(since))
        self.last_state = states[-1] if states else None
        if len(states) < MIN_STATE_PUBLICATIONS:
            raise CheckFailed(f"{len(states)} publications on {self.probe.rpc.keys.state} "
                              f"in {STATE_WINDOW_S:g} s, expected at least {MIN_STATE_PUBLICATIONS}")
        return f"{len(states)} valid publications in {STATE_WINDOW_S:g} s"

    def noop(self) -> str:
        self.probe.result("noop", {})
        return "answered"

    def hello(self) -> str:
        outcome = self.probe.outcome("hello", {})
        if isinstance(outcome, DriverError):
            if outcome.code != UNKNOWN_VERB:
                raise CheckFailed(f"expected a Hello or {UNKNOWN_VERB}, got {outcome.code}: {outcome.message}")
            return "no hello: used as protocol version 1 with no optional features"
        self.greeting = outcome
        served = outcome.served
        try:
            agreement = agree(served)
        except NoCommonVersion as exc:
            raise CheckFailed(str(exc)) from None
        features = ", ".join(served.features) or "none"
        profile = "" if outcome.profile is None else (
            f"; profile: {outcome.profile.name} (sha256 {outcome.profile.sha256[:12]})")
        return (f"serves versions {', '.join(map(str, served.versions))} (using {agreement.version}); "
                f"features: {features}{profile}")

    def profile_served(self) -> str:
        """The robot profile the driver names in ``hello`` is the one the suite was
        given (a mismatch has already stopped the suite in :func:`run_checks`)."""
        named = None if self.greeting is None else self.greeting.profile
        if named is None:
            return "not checked: the driver does not offer the profile feature"
        if self.profile is None:
            return f"not compared (no profile given): the driver serves {_stamp_text(named)}"
        problem = _profile_mismatch(named, self.profile)
        if problem:
            raise CheckFailed(problem)
        return f"serves {_stamp_text(named)}, as given"

    def reset_objects(self) -> str:
        """Reset the shipped world KNOWN_WORLD and look: the robot at the world's start
        pose and every object drawn where the world file puts it. A driver that cannot
        restore that world refuses it ``bad_request`` (as the protocol asks), which
        leaves the check to a driver that can, and its sensing and grasping to the
        reference checks."""
        outcome = self.probe.outcome("reset", {"world": KNOWN_WORLD, "seed": None})
        if isinstance(outcome, DriverError):
            if outcome.code != BAD_REQUEST:
                raise CheckFailed(f"reset to world {KNOWN_WORLD!r}: expected a state or {BAD_REQUEST}, "
                                  f"got {outcome.code}: {outcome.message}")
            self.lab_refused = True
            return f"not checked: the driver cannot restore world {KNOWN_WORLD!r} ({outcome.message})"
        start, placed = known_world()
        pose = outcome.pose
        turn = (pose.heading_deg - start.heading_deg + 180.0) % 360.0 - 180.0
        if math.hypot(pose.x_in - start.x_in, pose.y_in - start.y_in) > START_TOLERANCE_IN or \
                abs(turn) > START_TOLERANCE_IN:
            raise CheckFailed(f"reset to world {KNOWN_WORLD!r} answered the pose {pose_text(outcome)}, the "
                              f"world's start is ({start.x_in:g}, {start.y_in:g}, {start.heading_deg:g} deg)")
        image = self.probe.result("camera", {})
        try:
            found = self._read_image(image, lambda sight: check_objects_seen(sight, placed),
                                     lambda: check_objects_drawn(image, placed))
        except CheckFailed as exc:
            raise CheckFailed(f"world {KNOWN_WORLD!r}: {exc}") from None
        return NEEDS_CALIBRATION if found is None else f"world {KNOWN_WORLD!r}: {found}"

    def _read_image(self, image: CameraImage, seen: Callable[[Sight], str], drawn: Callable[[], str]) -> str | None:
        """One image check: through the calibrated vision when the suite has one, else
        by the grey bands. An image that fails the bands and is not drawn in them (a
        real camera's) is not checked (None): failing it would blame a good camera,
        passing it would vouch for a reading nobody made."""
        try:
            return seen(self.vision(image)) if self.vision is not None else drawn()
        except MappingError as exc:
            if self.vision is None and not looks_like_bands(undistorted(image)):
                return None
            raise CheckFailed(str(exc)) from None

    def reset(self) -> str:
        state = self.probe.result("reset", {"world": None, "seed": None})
        if state.clock_s != 0:
            raise CheckFailed(f"clock_s is {state.clock_s} after a move and a reset, expected 0")
        return f"pose {pose_text(state)}"

    def camera(self) -> str:
        image = self.probe.result("camera", {})
        self.image = image
        height, width = image.pixels.shape
        return f"{width}x{height} px at {image.inches_per_pixel:g} in/px"

    def camera_mapping(self) -> str:
        image, state = self.image, self.last_state
        if image is None or state is None:
            raise CheckFailed("needs the camera and state-published checks to pass")
        found = self._read_image(image, lambda sight: check_robot_seen(sight, state.pose),
                                 lambda: check_robot_drawn(image, state.pose))
        return NEEDS_CALIBRATION if found is None else found

    def busy(self) -> str:
        """A turn in place and, every 0.1 s while it runs, a release: a release that
        arrives while the turn runs must be refused ``busy`` at once, never held until
        the turn ends (a queue) nor run alongside it. One sent in the turn's last 0.1 s
        may meet it finished, and the first may overtake the turn on the way: neither
        counts against the driver."""
        if self.moved is None:
            raise CheckFailed("needs the move check to pass")
        pose = self.moved[1].pose
        turn = message({"waypoints": [{"x_in": pose.x_in, "y_in": pose.y_in,
                                        "heading_deg": pose.heading_deg - TURN_DEG}], "face": None})
        first = Timed()
        self.probe.rpc.send("move", turn, self.probe.timeout_s, first.on_reply, first.on_done)
        releases: list[Timed] = []
        while not first.finished.wait(BUSY_PROBE_S) and len(releases) < BUSY_PROBES:
            release = Timed()
            self.probe.rpc.send("release", message({}), self.probe.timeout_s, release.on_reply, release.on_done)
            releases.append(release)
        for call in (first, *releases):
            if not call.finished.wait(self.probe.timeout_s + 1.0) or call.reply is None:
                raise CheckFailed("no reply to the turn or to a release sent during it")
        if first.reply.ok is None:
            raise CheckFailed(f"the turn: {describe(first.reply)}")
        decoded("move", first.reply.ok)
        took_ms = (first.at - first.sent) * 1000
        during = [r for r in releases if r.sent <= first.at - BUSY_PROBE_S]
        refused, held, ran = 0, 0, 0
        for release in during:
            if release.reply.ok is not None:
                decoded("release", release.reply.ok)
                held, ran = held + (release.at > first.at), ran + (release.at <= first.at)
                continue
            error = error_of(release.reply)
            if error.code != BUSY:
                raise CheckFailed(f"release during a turn: expected busy, got {error.code}: {error.message}")
            refused += 1
        if held:
            raise CheckFailed(f"{held} release(s) sent during a {took_ms:.0f} ms turn were held until it ended "
                              "and then run: a verb arriving while one runs must be refused busy at once")
        if ran and not refused:
            raise CheckFailed(f"{ran} release(s) ran while a {took_ms:.0f} ms turn was running: refuse them busy")
        if refused:
            return f"{refused} release(s) refused busy during a {took_ms:.0f} ms turn"
        return f"the turn took {took_ms:.0f} ms, too short to overlap: busy not exercised"

    def move(self) -> str:
        """A turn in place, then a move that stays put facing a point ahead: both
        forms of the request, each reply decoded strictly (no field more or less)."""
        if self.last_state is None:
            raise CheckFailed("needs a state publication to know where to turn in place")
        pose = self.last_state.pose
        goal = {"x_in": pose.x_in, "y_in": pose.y_in, "heading_deg": pose.heading_deg + TURN_DEG}
        turned = self.probe.result("move", {"waypoints": [goal], "face": None})
        here = turned.pose
        ahead = math.radians(here.heading_deg)
        face = [here.x_in + FACE_AHEAD_IN * math.cos(ahead), here.y_in + FACE_AHEAD_IN * math.sin(ahead)]
        sent = time.monotonic()
        result = self.probe.result("move", {"waypoints": [pose_json(here)], "face": face})
        self.moved = (sent, result)
        return f"turned in place to {pose_text(result)} in {turned.duration_s + result.duration_s:g} s"

    def state_after_move(self) -> str:
        if self.moved is None:
            raise CheckFailed("needs the move check to pass")
        sent, result = self.moved
        deadline = time.monotonic() + 1.0
        while time.monotonic() < deadline:
            for state in valid_states(self.probe.states_since(sent)):
                if same_pose(state, result):
                    return f"published {pose_text(state)}"
            time.sleep(0.05)
        raise CheckFailed(f"no state publication with the move's final pose {pose_text(result)} within 1 s")

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
        return f"pose {pose_text(state)}"

    def charge(self) -> str:
        """The optional ``battery`` feature's verb. Without the feature ``charge`` must be
        an unknown verb (what a driver from before it answers); with it, charging from
        the reset pose either charges (the dock is within reach there) or is
        ``out_of_range``."""
        features = () if self.greeting is None else self.greeting.served.features
        outcome = self.probe.outcome("charge", {})
        if BATTERY not in features:
            if not isinstance(outcome, DriverError) or outcome.code != UNKNOWN_VERB:
                raise CheckFailed(f"hello does not list the {BATTERY} feature, so charge must answer "
                                  f"{UNKNOWN_VERB}, got {outcome_text(outcome)}")
            return f"not checked: the driver does not offer the {BATTERY} feature"
        if isinstance(outcome, DriverError):
            if outcome.code != OUT_OF_RANGE:
                raise CheckFailed(f"charge from the reset pose: expected a state or {OUT_OF_RANGE}, "
                                  f"got {outcome.code}: {outcome.message}")
            return f"{OUT_OF_RANGE} away from the dock: {outcome.message}"
        return f"charged at the dock: pose {pose_text(outcome)}"

    def blocked_moves(self) -> str:
        """The optional ``blocked_moves`` feature, checked in the shipped world
        ``crossing`` (a person pacing across the robot's way; read on the checking
        machine), since a driver may offer it only where something moves. There, after
        a fresh ``hello``: without the feature ``wait`` must be an unknown verb; with
        it, ``wait`` answers a state and a move straight through the person's line must
        end blocked (or clear), never ``collided``: a driver that ignores movers drives
        into the person. A driver that cannot restore ``crossing`` answers
        ``bad_request`` and passes as "not checked". The suite goes on in ``lab``."""
        reset = self.probe.outcome("reset", {"world": CROSSING_WORLD, "seed": None})
        if isinstance(reset, DriverError):
            if reset.code != BAD_REQUEST:
                raise CheckFailed(f"reset to {CROSSING_WORLD}: expected a state or {BAD_REQUEST}, "
                                  f"got {reset.code}: {reset.message}")
            return f"not checked: the driver cannot restore {CROSSING_WORLD}"
        try:
            hello = self.probe.outcome("hello", {})
            features = hello.served.features if isinstance(hello, Greeting) else ()
            waited = self.probe.outcome("wait", {"seconds": WAIT_CHECK_S})
            if BLOCKED_MOVES not in features:
                if not isinstance(waited, DriverError) or waited.code != UNKNOWN_VERB:
                    raise CheckFailed(f"hello does not list the {BLOCKED_MOVES} feature, so wait must answer "
                                      f"{UNKNOWN_VERB}, got {outcome_text(waited)}")
                return f"not checked: the driver does not offer the {BLOCKED_MOVES} feature"
            if not isinstance(waited, RobotState):
                raise CheckFailed(f"wait {WAIT_CHECK_S:g} s: expected a state, got {outcome_text(waited)}")
            here = waited.pose
            goal = {"x_in": here.x_in + CROSSING_DRIVE_IN, "y_in": here.y_in, "heading_deg": here.heading_deg}
            moved = self.probe.result("move", {"waypoints": [goal], "face": None})
        finally:
            self.probe.outcome("reset", {"world": KNOWN_WORLD, "seed": None})
        if moved.collided:
            raise CheckFailed(f"a move through {CROSSING_WORLD}'s moving obstacle collided at {pose_text(moved)}: "
                              f"with {BLOCKED_MOVES} it must stop short and answer blocked")
        if moved.blocked is None:
            return f"the move through {CROSSING_WORLD} met no one (clear at {pose_text(moved)})"
        o = moved.blocked
        return f"stopped short at {pose_text(moved)}, blocked by an obstacle at ({o.x_in:.1f}, {o.y_in:.1f})"

    def out_of_range(self) -> str:
        self.probe.result("reset", {"world": None, "seed": None})
        return self.probe.refusal("sense", message({"procedure": self.procedures.near}), NOT_HERE)

    def unknown_verb(self) -> str:
        return self.probe.refusal("fly", message({}), (UNKNOWN_VERB,))

    def unknown_procedure(self) -> str:
        sensed = self.probe.refusal("sense", message({"procedure": "No-Such-Procedure"}),
                                    (UNKNOWN_PROCEDURE,))
        self.probe.refusal("grasp", message({"procedure": "No-Such-Grasp"}), (UNKNOWN_PROCEDURE,))
        return sensed

    def malformed_json(self) -> str:
        return self.probe.refusal("sense", b'{"v": 1, "procedure": ', (BAD_REQUEST,))

    def not_utf8(self) -> str:
        return self.probe.refusal("sense", b'{"v": 1, "procedure": "H-Sweep-5\xb0"}', (BAD_REQUEST,))

    def not_an_object(self) -> str:
        detail = self.probe.refusal("sense", b'[1, "H-Sweep-5"]', (BAD_REQUEST,))
        self.probe.refusal("noop", b'"noop"', (BAD_REQUEST,))
        return detail

    def every_verb(self) -> str:
        """Every verb of the verb table (:mod:`.verbs`) has its queryable, which reads
        its request strictly: a JSON array, which no verb could run, is refused
        ``bad_request``. A verb the driver need not serve may be ``unknown_verb``: an
        optional feature's verb when ``hello`` does not list the feature, and ``hello``
        itself for a driver from before it. So a verb added to the table is asked of
        every driver with no check of its own; what its answer means is for a check of
        its own, where the verb has meaning worth checking."""
        features = () if self.greeting is None else self.greeting.served.features
        served, absent = [], []
        for verb in VERBS:
            feature = verb.driver_verb.feature if verb.touches_robot else None
            optional = (feature is not None and feature not in features) or (
                verb.name == "hello" and self.greeting is None)
            codes = (BAD_REQUEST, UNKNOWN_VERB) if optional else (BAD_REQUEST,)
            try:
                refused = self.probe.refusal(verb.name, b"[]", codes)
            except CheckFailed as exc:  # named by the verb, once
                text = str(exc)
                raise CheckFailed(text if text.startswith(f"{verb.name}: ") else f"{verb.name}: {text}") from None
            (absent if refused.startswith(UNKNOWN_VERB) else served).append(verb.name)
        not_served = f"; not served (optional here): {', '.join(absent)}" if absent else ""
        return f"{len(served)} verbs refuse a JSON array bad_request: {', '.join(served)}{not_served}"

    def wildcard_silence(self) -> str:
        """A wildcard query reaches every verb's queryable: exactly one reply, an error,
        and the robot does not turn."""
        before = self._published_pose()
        turn = {"waypoints": [{"x_in": before.x_in, "y_in": before.y_in,
                               "heading_deg": before.heading_deg + 90.0}], "face": None}
        detail = self.probe.refusal("*", message(turn), (BAD_REQUEST,))
        after = self._published_pose()
        if abs((after.heading_deg - before.heading_deg + 180.0) % 360.0 - 180.0) > POSE_TOLERANCE:
            raise CheckFailed(f"the robot turned from {before.heading_deg:.1f} to {after.heading_deg:.1f} deg "
                              "on a wildcard query: a verb's queryable must answer only its exact key")
        return detail

    def _published_pose(self) -> Pose:
        """The pose of the next state publication."""
        start = time.monotonic()
        deadline = start + 1.0
        while time.monotonic() < deadline:
            states = valid_states(self.probe.states_since(start))
            if states:
                return states[-1].pose
            time.sleep(0.05)
        raise CheckFailed("no state publication within 1 s")

    def wrong_types(self) -> str:
        detail = self.probe.refusal("sense", message({"procedure": 42}), (BAD_REQUEST,), "procedure")
        self.probe.refusal("move", message({"waypoints": "north", "face": None}), (BAD_REQUEST,),
                           "waypoints")
        self.probe.refusal("reset", message({"world": None, "seed": "seven"}), (BAD_REQUEST,), "seed")
        return detail

    def missing_field(self) -> str:
        detail = self.probe.refusal("sense", message({}), (BAD_REQUEST,), "procedure")
        self.probe.refusal("move", message({"waypoints": [{"x_in": 1.0, "heading_deg": 0.0}]}),
                           (BAD_REQUEST,), "y_in")
        return detail

    def unknown_field(self) -> str:
        return self.probe.refusal("sense", message({"procedure": self.procedures.sense, "speed": 2}),
                                  (BAD_REQUEST,), "speed")

    def non_finite(self) -> str:
        details = [self.probe.refusal("move", b'{"v": 1, "waypoints": [{"x_in": %s, "y_in": 0, "heading_deg": 0}], '
                                      b'"face": null}' % word, (BAD_REQUEST,), "x_in")
                   for word in (b"NaN", b"Infinity", b"-Infinity")]
        return details[0]

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
        return f"still answering at {pose_text(state)}"


def known_world(world: str = KNOWN_WORLD) -> tuple[Pose, tuple[PlacedObject, ...]]:
    """The robot's start pose and the objects of a shipped world file (the installed
    ``hero_driver/worlds/<world>.json``, whatever the working folder holds), with their
    footprint areas from the object catalogue."""
    catalogue = load_catalogue([g.name for g in load_profile(DEFAULT_PROFILE).grasping])
    spec = load_world(WORLDS_DIR / f"{world}.json", catalogue)
    placed = []
    for item in spec.objects:
        footprint = catalogue[item.entry_id].footprint
        area = (math.pi * footprint.radius_in**2 if footprint.shape == "circle"
                else footprint.length_in * footprint.width_in)
        placed.append(PlacedObject(item.entry_id, item.x_in, item.y_in, area))
    return Pose(*spec.robot), tuple(placed)


def _stamp_text(stamp: ProfileStamp) -> str:
    return f"{stamp.name} (sha256 {stamp.sha256[:12]})"


def _profile_mismatch(named: ProfileStamp, given: ProfileStamp) -> str:
    """One line when the driver serves another robot than ``given``; "" when the same."""
    if named.sha256 == given.sha256:
        return ""
    return (f"the driver serves robot profile {_stamp_text(named)}, not {_stamp_text(given)} as given: "
            "check it with its own profile (--profile FILE)")


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
               procedures: Procedures | None = None, zenoh_config: UserConfig | None = None,
               profile: ProfileStamp | None = None, vision: Vision | None = None,
               timing: Timing | None = None, reference: Reference | None = None) -> list[CheckResult]:
    """Run every check against the driver serving ``robot`` at ``connect``; ``zenoh_config``
    is the user's zenoh file (credentials, TLS) for a driver that requires them.
    ``profile`` is the stamp of the robot profile the driver should serve: a driver
    that names another in ``hello`` stops the suite with one line (None: not compared).
    ``vision`` reads a real camera's images (:func:`camera_check.calibrated_reader`;
    None: the images are band images, and the image checks skip any that is not).
    ``timing`` is what the robot profile says verbs take (None: the HERO 2000's).
    ``reference`` is the placed objects of the reference checks (:mod:`.reference_check`),
    run last when it asks for them always, or when the driver cannot restore
    KNOWN_WORLD; such a driver without one fails the check ``reference``."""
    robot_keys(robot)
    if not timeout_s > 0:
        raise ValueError(f"timeout must be a positive number of seconds, got {timeout_s}")
    chosen = procedures if procedures is not None else Procedures.from_profile()
    session = open_session(connect=connect, user=zenoh_config)
    probe = Probe(session, robot, timeout_s)
    try:
        if not probe.rpc.wait_alive(timeout_s) and probe.rpc.ask("noop", message({}), timeout_s).first is None:
            return [CheckResult("liveliness", False, f"nothing serves robot {robot} at {', '.join(connect)}: "
                                f"no token on {probe.rpc.keys.alive} and no answer to noop within {timeout_s:g} s "
                                "(is the driver running, under this robot name, at this endpoint?)")]
        mismatch = _named_profile_mismatch(probe, profile)
        if mismatch:
            return [CheckResult("profile", False, mismatch)]
        suite = _Suite(probe, chosen, profile, vision, timing)
        results = [run_check(name, check) for name, check in suite.checks()]
        return results + _reference_results(probe, reference, suite.lab_refused)
    finally:
        probe.close()
        session.close()


def _reference_results(probe: Probe, reference: Reference | None, lab_refused: bool) -> list[CheckResult]:
    """The reference checks, when asked for or needed. A driver that cannot restore
    KNOWN_WORLD has had its sensing and grasping tried against nothing (``no_target``
    passes ``sense`` and ``grasp``), so without a reference it fails, never passes."""
    if reference is not None and (reference.always or lab_refused):
        return reference_checks(probe, reference)
    return [CheckResult("reference", False, NOT_CHECKED)] if lab_refused else []


def _named_profile_mismatch(probe: Probe, profile: ProfileStamp | None) -> str:
    """One line when the driver's ``hello`` names another profile than ``profile``;
    "" otherwise, including when it names none or ``hello`` fails (its own checks say)."""
    if profile is None:
        return ""
    try:
        outcome = probe.outcome("hello", {})
    except CheckFailed:
        return ""
    if isinstance(outcome, DriverError) or outcome.profile is None:
        return ""
    return _profile_mismatch(outcome.profile, profile)


@dataclass(frozen=True)
class _Ping:
    """One noop of the shutdown check: when it went, and whether it was answered."""

    sent: float
    answered: threading.Event
    ended: threading.Event


def shutdown_order(robot: str, connect: Sequence[str], stop: Callable[[], None] | None = None, *,
                   timeout_s: float = 30.0, zenoh_config: UserConfig | None = None) -> CheckResult:
    """The ``shutdown-order`` check: ping ``noop`` every PING_PERIOD_S while the driver
    stops (``stop()`` stops it, run on another thread; None: wait up to ``timeout_s``
    for someone to stop it) and pass when every noop sent while the token was still
    visible got its reply. A driver that undeclares its queryables (or closes its
    session) before its token leaves clients sending into nothing while they still
    see it alive; the protocol asks for the token first. A noop sent within
    SHUTDOWN_RACE_S before the token's DELETE arrived may cross it and is not held
    against the driver."""
    keys = robot_keys(robot)
    session = open_session(connect=connect, user=zenoh_config)
    rpc = RpcClient(session, keys)
    gone = threading.Event()
    gone_at: list[float] = []

    def on_change(alive: bool) -> None:
        if not alive and not gone.is_set():
            gone_at.append(time.monotonic())
            gone.set()

    watcher = rpc.watch_alive(on_change)
    pings: list[_Ping] = []
    try:
        if not rpc.wait_alive(timeout_s):
            return CheckResult("shutdown-order", False, f"no token on {keys.alive} within {timeout_s:g} s")
        stopping = threading.Thread(target=stop or (lambda: None), name=f"stop-{robot}", daemon=True)
        started = time.monotonic()
        deadline = started + timeout_s
        while not gone.wait(PING_PERIOD_S) and time.monotonic() < deadline:
            pings.append(_send_ping(rpc))
            warm = sum(p.answered.is_set() for p in pings) >= WARM_PINGS or time.monotonic() > started + WARM_S
            if warm and stopping.ident is None:  # the driver stops while noops are under way
                stopping.start()
        for ping in pings:
            ping.ended.wait(PING_TIMEOUT_S + 1.0)
        if stopping.ident is not None:
            stopping.join(timeout_s)  # the caller gets the driver stopped, as it asked
    finally:
        watcher.undeclare()
        session.close()
    if not gone_at:
        return CheckResult("shutdown-order", False, f"the token on {keys.alive} was still there "
                           f"{timeout_s:g} s later: the driver did not stop, or kept its token")
    missed = [p for p in pings if not p.answered.is_set() and p.sent < gone_at[0] - SHUTDOWN_RACE_S]
    if missed:
        return CheckResult("shutdown-order", False, f"{len(missed)} noop(s) sent while the token was still "
                           f"visible got no reply, the first {gone_at[0] - missed[0].sent:.2f} s before it went: "
                           "undeclare the token first, then the queryables")
    answered = sum(p.answered.is_set() for p in pings)
    return CheckResult("shutdown-order", True, f"token went first: {answered} of {len(pings)} noops answered, "
                       "none sent while it was visible went unanswered")


def _send_ping(rpc: RpcClient) -> _Ping:
    ping = _Ping(time.monotonic(), threading.Event(), threading.Event())

    def on_reply(reply: Reply) -> None:
        if reply.ok is not None and not reply.late:
            ping.answered.set()

    try:
        rpc.send("noop", message({}), PING_TIMEOUT_S, on_reply, lambda _late: ping.ended.set())
    except zenoh.ZError:
        ping.ended.set()
    return ping


def format_table(results: Sequence[CheckResult]) -> str:
    """The pass/fail table ``csl driver check`` prints."""
    width = max(len("check"), *(len(r.name) for r in results))
    lines = [f"{'check':<{width}}  result  detail"]
    lines += [f"{r.name:<{width}}  {'PASS' if r.passed else 'FAIL':<6}  {r.detail}" for r in results]
    failed = sum(not r.passed for r in results)
    lines.append(f"{len(results)} checks: {len(results) - failed} passed, {failed} failed")
    return "\n".join(lines)
