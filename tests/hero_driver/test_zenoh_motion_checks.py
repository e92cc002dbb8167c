"""The ``turns``, ``durations`` and ``busy-release`` checks of ``csl driver check``
(hero_driver/zenoh_link/motion_check.py): the simulated HERO passes them; each
mutant here, the simulator with one vendor mistake of turn conventions, time units
or busy timing, served in-process by the real node, fails the check named for it.
The checks run on their own here (a probe of the suite's kind), not the whole suite:
test_zenoh_conformance.py and test_zenoh_mutants.py run them in it."""

from __future__ import annotations

import dataclasses
import json
import math
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from pathlib import Path
from typing import TypeVar

import pytest
import zenoh

from hero_driver.interface import MoveResult, Pose, RobotState, SenseResult
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.checking import CheckResult, Probe, run_check
from hero_driver.zenoh_link.conformance import Procedures
from hero_driver.zenoh_link.motion_check import MotionChecks, Timing
from hero_driver.zenoh_link.node import DriverNode, _Action
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

T = TypeVar("T")
HOLD_S = 0.25  # how long the late-freeing node keeps the robot busy after its reply
AHEAD = {  # a world with a box 50 in straight ahead of the start pose: the sense is in range
    "name": "ahead", "room": {"width_in": 240, "depth_in": 180}, "furniture": [],
    "robot": {"x_in": 30, "y_in": 90, "heading_deg": 0},
    "objects": [{"id": "closed-box-10x10x10/upright", "x_in": 96, "y_in": 90, "yaw_deg": 0}],
}


def _then(future: Future[T], change: Callable[[T], T]) -> Future[T]:
    """The settled ``future``'s value changed by ``change`` (the simulator's futures are done)."""
    out: Future[T] = Future()
    try:
        out.set_result(change(future.result()))
    except Exception as exc:  # a DriverError passes through as it came
        out.set_exception(exc)
    return out


def _heading(pose: Pose, heading_deg: float) -> Pose:
    return Pose(pose.x_in, pose.y_in, heading_deg)


class ReportsRadians(SimulatedHero):
    """Reads headings in degrees, as asked, but reports every heading in radians."""

    def _out(self, pose: Pose) -> Pose:
        return _heading(pose, math.radians(pose.heading_deg))

    def state(self) -> RobotState:
        state = super().state()
        return dataclasses.replace(state, pose=self._out(state.pose))

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        return _then(super().move(waypoints, face), lambda r: dataclasses.replace(r, pose=self._out(r.pose)))

    def release(self) -> Future[RobotState]:
        return _then(super().release(), lambda s: dataclasses.replace(s, pose=self._out(s.pose)))


class Clockwise(SimulatedHero):
    """Counts headings clockwise, in what it is asked and in what it reports: every
    reply agrees with the request, and the robot turns the other way round."""

    def state(self) -> RobotState:
        state = super().state()
        return dataclasses.replace(state, pose=_heading(state.pose, -state.pose.heading_deg))

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        mirrored = [_heading(w, -w.heading_deg) for w in waypoints]
        return _then(super().move(mirrored, face),
                     lambda r: dataclasses.replace(r, pose=_heading(r.pose, -r.pose.heading_deg)))

    def release(self) -> Future[RobotState]:
        return _then(super().release(), lambda s: dataclasses.replace(s, pose=_heading(s.pose, -s.pose.heading_deg)))


class TurnsOnPaper(SimulatedHero):
    """Answers a turn in place with the asked heading, and reports it ever after, but
    the base never turns (the camera draws where it truly points)."""

    claimed: float | None = None

    def _out(self, pose: Pose) -> Pose:
        return pose if self.claimed is None else _heading(pose, self.claimed)

    def state(self) -> RobotState:
        state = super().state()
        return dataclasses.replace(state, pose=self._out(state.pose))

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        here = self.world.pose
        if face is None and all(math.hypot(w.x_in - here.x_in, w.y_in - here.y_in) < 0.5 for w in waypoints):
            self.claimed = waypoints[-1].heading_deg % 360.0
            held = [_heading(w, here.heading_deg) for w in waypoints]
            return _then(super().move(held, None), lambda r: dataclasses.replace(r, pose=self._out(r.pose)))
        return _then(super().move(waypoints, face), lambda r: dataclasses.replace(r, pose=self._out(r.pose)))

    def release(self) -> Future[RobotState]:
        return _then(super().release(), lambda s: dataclasses.replace(s, pose=self._out(s.pose)))


class Milliseconds(SimulatedHero):
    """Reports every move's and sense's duration in milliseconds (its clock in seconds)."""

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        return _then(super().move(waypoints, face), lambda r: dataclasses.replace(r, duration_s=r.duration_s * 1000))

    def sense(self, procedure: str) -> Future[SenseResult]:
        return _then(super().sense(procedure), lambda r: dataclasses.replace(r, duration_s=r.duration_s * 1000))


class SenseInMinutes(SimulatedHero):
    """Reports a sense's duration in minutes; moves are right."""

    def sense(self, procedure: str) -> Future[SenseResult]:
        return _then(super().sense(procedure), lambda r: dataclasses.replace(r, duration_s=r.duration_s / 60))


class StoppedClock(SimulatedHero):
    """Its clock_s never leaves 0."""

    def state(self) -> RobotState:
        return dataclasses.replace(super().state(), clock_s=0.0)

    def release(self) -> Future[RobotState]:
        return _then(super().release(), lambda s: dataclasses.replace(s, clock_s=0.0))


def _answer_then_free(self: DriverNode, action: _Action) -> None:
    """DriverNode._finish with the order the other way round: the reply goes first and
    the robot is freed HOLD_S later (a driver that clears its busy flag after
    replying, on a timer so that the node's thread goes on serving meanwhile)."""
    if not action.claim():
        return
    self._publish_state()
    self._answer(action.verb, action.query, action.future)
    timer = threading.Timer(HOLD_S, self._release_busy)
    timer.daemon = True
    timer.start()


def run_motion_checks(driver: SimulatedHero, server: zenoh.Session, endpoint: str,
                      names: Sequence[str] = ("turns", "durations", "busy-release")) -> dict[str, CheckResult]:
    """The named checks, as the suite runs them, against ``driver`` served on ``server``."""
    results = {}
    with DriverNode(driver, server), open_session(connect=[endpoint]) as session:
        probe = Probe(session, driver.robot, 5.0)
        try:
            assert probe.rpc.wait_alive(5.0)
            checks = MotionChecks(probe, Timing.from_profile(), Procedures.from_profile().sense)
            results.update((name, run_check(name, check)) for name, check in checks.checks() if name in names)
        finally:
            probe.close()
    return results


def failed(results: dict[str, CheckResult]) -> set[str]:
    return {name for name, result in results.items() if not result.passed}


@pytest.fixture
def ahead(tmp_path: Path) -> Path:
    path = tmp_path / "ahead.json"
    path.write_text(json.dumps(AHEAD), encoding="utf-8")
    return path


@pytest.mark.parametrize("preset", ["mild", "paper", "harsh"])
def test_the_simulator_passes_in_the_lab(server: zenoh.Session, endpoint: str, preset: str) -> None:
    results = run_motion_checks(SimulatedHero("plain", noise=NoiseConfig.preset(preset)), server, endpoint)
    assert failed(results) == set(), results
    assert results["turns"].detail.startswith("turns of +10, -10, -90, +90 deg answered within ")
    assert "the camera's heading marker turned as they say" in results["turns"].detail
    # the lab's reset pose (30, 30, 0) faces no object: the sense is not timed, and says so
    assert results["durations"].detail.endswith("sense not checked: nothing to sense from here (no_target: "
                                                "V-Sweep-5°: no object in front of the sonar)")
    assert results["busy-release"].detail.startswith("20 verbs (move and release in turn)")


def test_the_simulator_passes_with_a_sense_in_range(server: zenoh.Session, endpoint: str, ahead: Path) -> None:
    results = run_motion_checks(SimulatedHero("near", world=ahead), server, endpoint, ("durations",))
    assert failed(results) == set(), results
    # V-Sweep-5°: time_s 42 in the HERO 2000's profile, which the simulator charges exactly
    assert results["durations"].detail.endswith("sense V-Sweep-5° took 42 s (time_s 42)")


def test_headings_reported_in_radians_fail_turns(server: zenoh.Session, endpoint: str) -> None:
    results = run_motion_checks(ReportsRadians("rad", noise=NoiseConfig.off()), server, endpoint, ("turns",))
    # The +10 and -10 deg turns answer a change of under 0.2 "deg", within the tolerance
    # a robot's own heading error needs; the suite asks each turn from the heading last
    # answered, so the -10 deg turn ends at -9.83 deg (6.11 in radians) and the -90 deg
    # turn at -83.83 deg (276.17 deg, 4.82 in radians): a change of -1.3 "deg".
    assert results["turns"].detail == ("asked a turn in place of -90 deg: the reply's heading went from 6.1 to 4.8 "
                                       "(-1.3 deg): a heading in radians? headings are degrees")


def test_a_clockwise_robot_fails_turns_by_the_camera(server: zenoh.Session, endpoint: str) -> None:
    """Its replies agree with every request; only the camera sees it turn the other way."""
    results = run_motion_checks(Clockwise("cw"), server, endpoint, ("turns",))
    assert not results["turns"].passed
    assert results["turns"].detail.startswith("asked a turn in place of +10 deg: the reply says +")
    assert results["turns"].detail.endswith(": it turned the other way round (headings count counter-clockwise "
                                            "from +x, seen from above)")


def test_a_turn_answered_but_not_made_fails_turns(server: zenoh.Session, endpoint: str) -> None:
    results = run_motion_checks(TurnsOnPaper("paper"), server, endpoint, ("turns",))
    assert not results["turns"].passed
    assert results["turns"].detail.startswith("asked a turn in place of +10 deg: the reply says +10.0 deg, the "
                                              "camera's heading marker turned ")
    assert results["turns"].detail.endswith(": the robot did not turn, or the reply is not where it is")


def test_durations_in_milliseconds_fail_durations(server: zenoh.Session, endpoint: str) -> None:
    results = run_motion_checks(Milliseconds("ms"), server, endpoint, ("turns", "durations"))
    assert failed(results) == {"durations"}
    # a 10 deg turn: vision 5 s + 10 deg at 5 deg/s = 7 s, answered as 7000
    assert results["durations"].detail == ("a +10 deg turn in place answered duration_s 7000; the profile gives 2-7 s "
                                           "(turn_deg_per_s 5, vision_s 5), at most 3x off (milliseconds? durations "
                                           "are seconds)")


def test_a_sense_in_minutes_fails_durations(server: zenoh.Session, endpoint: str, ahead: Path) -> None:
    results = run_motion_checks(SenseInMinutes("min", world=ahead), server, endpoint, ("durations",))
    # V-Sweep-5° takes 42 s: 0.7 minutes
    assert results["durations"].detail == ("sense V-Sweep-5° answered duration_s 0.7; the profile gives 42 s (its "
                                           "time_s 42), at most 3x off (minutes? durations are seconds)")


def test_a_clock_that_does_not_advance_fails_durations(server: zenoh.Session, endpoint: str) -> None:
    results = run_motion_checks(StoppedClock("stopped", noise=NoiseConfig.off()), server, endpoint, ("durations",))
    # the four turns: 7 + 7 + 23 + 23 s (vision 5 s each, 10 and 90 deg at 5 deg/s)
    assert results["durations"].detail == ("clock_s went from 0 to 0 (+0 s) over the turns, whose durations add up "
                                           "to 60 s: the clock must advance by the robot time its verbs take, in "
                                           "seconds")


def test_a_robot_freed_after_its_reply_fails_busy_release(server: zenoh.Session, endpoint: str,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(DriverNode, "_finish", _answer_then_free)
    results = run_motion_checks(SimulatedHero("late"), server, endpoint, ("busy-release",))
    assert not results["busy-release"].passed
    assert "arrived, was refused busy (" in results["busy-release"].detail
    assert results["busy-release"].detail.endswith("): free the robot before sending a reply")
