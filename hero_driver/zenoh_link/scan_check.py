"""Does the robot's range scan say what the robot could check? The ``scan-*`` checks of
``csl driver check`` (:mod:`.conformance` runs them) for a driver with the ``scan``
feature (docs/driver-protocol.md, "Scans").

A scan can decode perfectly and still mislead every map built from it: ranges in
centimetres put every wall 2.54 times too far; angles in radians squeeze the room into
six degrees; a scan in the world's frame instead of the robot's is turned by the
heading; a pose corrected by the driver's own localisation, or the clock in
milliseconds, stamps it at the wrong place or time. Verify, don't believe:

- ``scan``: without the feature, ``scan`` is ``unknown_verb``; with it, the reply
  decodes strictly, its beams span at least :data:`MIN_SPAN_DEG` (what a scan for
  finding one's way must see; degrees, not radians) and its pose and clock are those the
  driver publishes while the robot stands (the state before and after it);
- ``scan-repeat``: two scans in a row, standing still, see the same walls (ranges that
  both echoed agree within :func:`agree`);
- ``scan-turn``: after a turn in place of :data:`TURN_DEG`, the scan is the one before
  turned by the reported turn (it is in the robot's frame);
- ``scan-drive``: facing a wall the scan shows square on (a local minimum of range, as
  a flat wall reads around it, with room), a drive of :data:`DRIVE_IN` straight at it
  shortens the range towards it by the distance the reported poses say was driven (the
  ranges are inches); the range is read in the wall's world direction, turned into each
  scan's frame by its reported heading, so a turn that ends a little off still reads
  the same wall.

The robot turns in place and drives a few feet towards a wall the scan shows clear, so
the checks are safe on hardware; they run where the robot stands.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence

from hero_driver.interface import UNKNOWN_VERB, VERB_BY_NAME, DriverError, MoveResult, Pose, RangeScan, RobotState
from hero_driver.zenoh_link.checking import (POSE_TOLERANCE, CheckFailed, Probe, outcome_text, pose_json,
                                              valid_states)

SCAN = VERB_BY_NAME["scan"].feature  # the feature that brings the verb
MIN_SPAN_DEG = 180.0  # a scan's beams span at least this (a front-facing lidar's half turn)
AGREE_IN = 3.0  # two readings of one surface agree within this ...
AGREE_FRAC = 0.1  # ... plus this share of the range (harsh noise: 2% sigma per reading)
REPEAT_SHARE = 0.8  # scan-repeat: at least this share of the beams both scans heard agree
TURN_DEG = 90.0  # scan-turn: the turn in place
TURN_SHARE = 0.6  # ... after which at least this share of the beams heard before and after agree, turned
MIN_SHARED = 3  # fewer beams heard by both scans than this: nothing to compare
DRIVE_IN = 36.0  # scan-drive: the drive straight at a wall
CLEAR_IN = 40.0  # ... which must leave at least this much of the range ahead
SQUARE_DEG = 4.0  # a wall met square on: its range the least, and a flat wall's, within this of the beam
AHEAD_DEG = 3.0  # the range ahead: the least within this of the heading (square on: the wall's distance)
RESCANS = 3  # the range ahead: scans taken at most, until one hears an echo ahead (dropouts, mirrors)
DRIVE_SLACK_IN = 2.0  # the range ahead must shrink by the distance driven within this ...
DRIVE_SLACK_FRAC = 0.25  # ... plus this share of the distance driven ...
DRIVE_RANGE_FRAC = 0.03  # ... plus this share of the range (the noise of the least of a few readings)
STATE_WAIT_S = 1.0  # how long to wait for a state publication


def wrapped(deg: float) -> float:
    """An angle in [-180, 180)."""
    return (deg + 180.0) % 360.0 - 180.0


def range_at(scan: RangeScan, angle_deg: float) -> float | None:
    """The range of ``scan``'s beam nearest ``angle_deg`` (robot frame), when one lies
    within half the scan's mean beam spacing of it (None: no beam looks there)."""
    spacing = 360.0 / len(scan.angles_deg)
    best = min(range(len(scan.angles_deg)), key=lambda i: abs(wrapped(scan.angles_deg[i] - angle_deg)))
    return scan.ranges_in[best] if abs(wrapped(scan.angles_deg[best] - angle_deg)) <= spacing / 2 + 1e-9 else None


def near(scan: RangeScan, angle_deg: float, half_deg: float, neighbours: bool = True) -> list[float]:
    """The ranges of the beams within ``half_deg`` of ``angle_deg``; with
    ``neighbours``, of at least the beam on either side of it too (a coarse scan's
    neighbours lie further off), else of at least the beam nearest it."""
    spacing = 360.0 / len(scan.angles_deg)
    half = max(half_deg, 1.01 * spacing if neighbours else spacing / 2)
    return [r for a, r in zip(scan.angles_deg, scan.ranges_in, strict=True) if abs(wrapped(a - angle_deg)) <= half]


def toward(scan: RangeScan, world_deg: float) -> float:
    """The range toward the world heading ``world_deg``, turned into the scan's frame by
    its reported heading (so a turn that ended a little off still looks at the same
    wall): the least of the beams within AHEAD_DEG of it, or of the one nearest it in a
    coarse scan (whose wide beam holds the rest); inf: no echo."""
    return min(near(scan, wrapped(world_deg - scan.pose.heading_deg), AHEAD_DEG, neighbours=False),
               default=math.inf)


def agree(a: float, b: float) -> bool:
    """Two readings of one surface: within AGREE_IN plus AGREE_FRAC of the larger."""
    return abs(a - b) <= AGREE_IN + AGREE_FRAC * max(a, b)


def compared(before: RangeScan, after: RangeScan, turn_deg: float = 0.0) -> tuple[int, int]:
    """(agreeing, shared): of ``after``'s beams that echoed and whose direction
    ``before`` saw (``turn_deg`` further round) with an echo too, how many agree."""
    shared = agreeing = 0
    for angle, now in zip(after.angles_deg, after.ranges_in, strict=True):
        then = range_at(before, wrapped(angle + turn_deg))
        if math.isfinite(now) and then is not None and math.isfinite(then):
            shared += 1
            agreeing += agree(then, now)
    return agreeing, shared


def square_wall(scan: RangeScan, clear_in: float) -> float | None:
    """A direction (robot frame) in which a wall is met square on with at least
    ``clear_in`` of room: a beam whose range ``r`` is the least of those near it (within
    SQUARE_DEG, and at least two beams to each side: a coarse scan's wide beams make a
    small object look flat over one), each of which echoes and reads what a flat wall
    there would give, ``r / cos`` of its angle off the beam (within :func:`agree`: not a small object
    with the room behind it, nor a corner). Of those, the farthest; of those that agree
    with it, the one whose two neighbours read most alike: the wall's normal, also in the
    middle of the run of coarse beams whose wide cones all hold it. None when there is none."""
    spacing = 360.0 / len(scan.angles_deg)
    found: list[tuple[float, float, float]] = []  # angle, range, how unlike its neighbours read
    for i, (angle, r) in enumerate(zip(scan.angles_deg, scan.ranges_in, strict=True)):
        if not clear_in <= r < scan.range_max_in:
            continue
        around = [(wrapped(a - angle), q) for a, q in zip(scan.angles_deg, scan.ranges_in, strict=True)
                  if abs(wrapped(a - angle)) <= max(SQUARE_DEG, 2.01 * spacing)]
        if all(math.isfinite(q) and q >= r and agree(q, r / math.cos(math.radians(off))) for off, q in around):
            left, right = scan.ranges_in[i - 1], scan.ranges_in[(i + 1) % len(scan.ranges_in)]
            found.append((angle, r, abs(left - right)))
    if not found:
        return None
    farthest = max(r for _, r, _ in found)
    return min((f for f in found if agree(f[1], farthest)), key=lambda f: (f[2], -f[1]))[0]


class ScanChecks:
    """The ``scan``, ``scan-repeat``, ``scan-turn`` and ``scan-drive`` checks on one
    probe; ``features`` gives what the driver's ``hello`` lists (the suite's hello check
    reads it)."""

    def __init__(self, probe: Probe, features: Callable[[], Sequence[str]]) -> None:
        self.probe = probe
        self.features = features
        self.first: RangeScan | None = None  # the scan check's scan, once it passed

    def checks(self) -> list[tuple[str, Callable[[], str]]]:
        return [("scan", self.scan), ("scan-repeat", self.repeat), ("scan-turn", self.turn),
                ("scan-drive", self.drive)]

    def _offered(self) -> bool:
        return SCAN in self.features()

    def _scan(self, what: str) -> RangeScan:
        outcome = self.probe.outcome("scan", {})
        if not isinstance(outcome, RangeScan):
            raise CheckFailed(f"{what}: expected a RangeScan, got {outcome_text(outcome)}")
        return outcome

    def _state_after(self, since: float) -> RobotState:
        """The first state published after ``since``."""
        deadline = time.monotonic() + STATE_WAIT_S
        while time.monotonic() < deadline:
            states = valid_states(self.probe.states_since(since))
            if states:
                return states[0]
            time.sleep(0.05)
        raise CheckFailed(f"no state publication within {STATE_WAIT_S:g} s")

    def scan(self) -> str:
        if not self._offered():
            outcome = self.probe.outcome("scan", {})
            if not isinstance(outcome, DriverError) or outcome.code != UNKNOWN_VERB:
                raise CheckFailed(f"hello does not list the {SCAN} feature, so scan must answer {UNKNOWN_VERB}, "
                                  f"got {outcome_text(outcome)}")
            return f"not checked: the driver does not offer the {SCAN} feature"
        before = self._state_after(time.monotonic())
        scan = self._scan("scan")
        after = self._state_after(time.monotonic())
        span = scan.angles_deg[-1] - scan.angles_deg[0]
        if span < MIN_SPAN_DEG - 1e-9:
            raise CheckFailed(f"the beams span {span:g} deg, from {scan.angles_deg[0]:g} to {scan.angles_deg[-1]:g}: "
                              f"a scan covers at least {MIN_SPAN_DEG:g} deg, its angles in degrees (not radians)")
        for state, when in ((before, "before"), (after, "after")):
            p, q = scan.pose, state.pose
            turn = abs(wrapped(p.heading_deg - q.heading_deg))
            if math.hypot(p.x_in - q.x_in, p.y_in - q.y_in) > POSE_TOLERANCE or turn > POSE_TOLERANCE:
                raise CheckFailed(f"the scan's pose ({p.x_in:.1f}, {p.y_in:.1f}, {p.heading_deg:.1f} deg) is not the "
                                  f"pose published {when} it ({q.x_in:.1f}, {q.y_in:.1f}, {q.heading_deg:.1f} deg): "
                                  "stamp a scan with the pose the driver reports")
        if not before.clock_s <= scan.clock_s <= after.clock_s:
            raise CheckFailed(f"the scan's clock_s {scan.clock_s:g} is not between the clocks published before "
                              f"({before.clock_s:g} s) and after it ({after.clock_s:g} s): the robot clock, in seconds")
        self.first = scan
        heard = sum(math.isfinite(r) for r in scan.ranges_in)
        return (f"{len(scan.angles_deg)} beams, {heard} echoed, {scan.range_min_in:g}-{scan.range_max_in:g} in, "
                f"at the published pose")

    def _needs_first(self) -> RangeScan | None:
        if not self._offered():
            return None
        if self.first is None:
            raise CheckFailed("needs the scan check to pass")
        return self.first

    def repeat(self) -> str:
        first = self._needs_first()
        if first is None:
            return f"not checked: the driver does not offer the {SCAN} feature"
        again = self._scan("a second scan")
        agreeing, shared = compared(first, again)
        if shared < MIN_SHARED:
            return f"not checked: {shared} beams echoed in both scans, fewer than {MIN_SHARED}"
        if agreeing < REPEAT_SHARE * shared:
            raise CheckFailed(f"standing still, two scans agree on {agreeing} of the {shared} beams both heard, "
                              f"expected at least {REPEAT_SHARE:.0%}: the same walls must read the same")
        return f"standing still, {agreeing} of {shared} beams agree"

    def _turn(self, here: Pose, by_deg: float) -> MoveResult:
        """Turn in place from ``here`` (a reported pose) by ``by_deg``."""
        goal = {**pose_json(here), "heading_deg": here.heading_deg + by_deg}
        return self.probe.result("move", {"waypoints": [goal], "face": None})

    def turn(self) -> str:
        if self._needs_first() is None:
            return f"not checked: the driver does not offer the {SCAN} feature"
        before = self._scan("the scan before the turn")
        self._turn(before.pose, TURN_DEG)
        after = self._scan("the scan after the turn")
        turned = wrapped(after.pose.heading_deg - before.pose.heading_deg)
        agreeing, shared = compared(before, after, turned)
        if shared < MIN_SHARED:
            return f"not checked: {shared} beams echoed before and after the turn, fewer than {MIN_SHARED}"
        if agreeing < TURN_SHARE * shared:
            still, _ = compared(before, after)
            raise CheckFailed(f"after a {turned:.0f} deg turn in place, {agreeing} of {shared} beams agree with the "
                              f"scan before turned by it (unturned: {still}): angles are counter-clockwise from the "
                              "robot's heading, in degrees")
        return f"after a {turned:.0f} deg turn in place, {agreeing} of {shared} beams agree with the scan turned by it"

    def _toward(self, world_deg: float, what: str) -> tuple[RangeScan, float]:
        """A scan and its range :func:`toward` ``world_deg``, scanning again (up to
        RESCANS) while it heard nothing there."""
        for _ in range(RESCANS):
            scan = self._scan(what)
            ahead = toward(scan, world_deg)
            if math.isfinite(ahead):
                break
        return scan, ahead

    def drive(self) -> str:
        if self._needs_first() is None:
            return f"not checked: the driver does not offer the {SCAN} feature"
        seen = self._scan("the scan to choose a wall")
        angle = square_wall(seen, DRIVE_IN + CLEAR_IN)
        if angle is None:
            return (f"not checked: no wall met square on with {DRIVE_IN + CLEAR_IN:g} in of room in the scan "
                    "(place the robot in front of one)")
        wall = seen.pose.heading_deg + angle  # the wall's direction in the world
        self._turn(seen.pose, angle)
        ahead, before = self._toward(wall, "the scan facing the wall")
        if not math.isfinite(before):  # a wide beam turned a little off the wall may have it mirrored away
            return (f"not checked: facing the wall the scan showed {seen.ranges_in[seen.angles_deg.index(angle)]:.1f} "
                    f"in away at {angle:g} deg, {RESCANS} scans heard no echo ahead")
        start = ahead.pose
        u = (math.cos(math.radians(wall)), math.sin(math.radians(wall)))
        goal = {"x_in": start.x_in + DRIVE_IN * u[0], "y_in": start.y_in + DRIVE_IN * u[1], "heading_deg": wall}
        moved = self.probe.result("move", {"waypoints": [goal], "face": None})
        if moved.collided:
            raise CheckFailed(f"the scan showed {before:.1f} in clear ahead, yet a {DRIVE_IN:g} in drive collided at "
                              f"({moved.pose.x_in:.1f}, {moved.pose.y_in:.1f})")
        end, after = self._toward(wall, "the scan after the drive")
        driven = (end.pose.x_in - start.x_in) * u[0] + (end.pose.y_in - start.y_in) * u[1]
        if not math.isfinite(after):
            raise CheckFailed(f"the range ahead was {before:.1f} in, and after a {driven:.1f} in drive straight at "
                              f"it no echo came back ahead in {RESCANS} scans")
        slack = DRIVE_SLACK_IN + DRIVE_SLACK_FRAC * abs(driven) + DRIVE_RANGE_FRAC * before
        if abs((before - after) - driven) > slack:
            raise CheckFailed(f"driving {driven:.1f} in straight at a wall took the range ahead from {before:.1f} to "
                              f"{after:.1f} in (by {before - after:.1f}, expected {driven:.1f} within {slack:.1f}): "
                              "ranges are inches from the base centre")
        return f"driving {driven:.1f} in at a wall, the range ahead went from {before:.1f} to {after:.1f} in"
