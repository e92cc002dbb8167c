"""Every vendor mistake a fixture: a driver written from the
docs with one realistic mistake in it must end its run non-zero with the reason.

Each mistake is the simulator altered the way a vendor's driver would get it wrong
(docs/vendor-guide.md), run in-process on the lab (7 unseen test objects, the example
library) like the other episode tests; the extra field in the sense reply goes through
a real driver node and the zenoh client on 127.0.0.1, where replies are decoded. The run
is judged as ``csl run`` judges it (``executive.exit_status.run_status``).
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from collections import Counter
from collections.abc import Callable
from concurrent.futures import Future
from dataclasses import replace
from pathlib import Path
from typing import Any, TypeVar

import pytest
import zenoh

from behaviours.services import Params
from executive.defaults import EXAMPLE_LIBRARY
from executive.executive import Executive
from executive.exit_status import ALL_HANDLED, LOST, SOME_FAILED, WRONG_UNIT_MIN, run_status
from hero_driver.interface import (INTERNAL, OUT_OF_RANGE, DriverError, GraspResult, MoveResult, RobotState,
                                  SenseResult)
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.verbs import Verb
from learner.library.format import read_library_json
from learner.service.local import LocalLearner
from robot_profile import load_profile
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session
from zenoh_rpc.server import reply

T = TypeVar("T")
REPO = Path(__file__).resolve().parents[2]
PROFILE = load_profile()
ARM_ONLY = Params(use_appearance=False)


def _settled(value: T | DriverError) -> Future[T]:
    future: Future[T] = Future()
    if isinstance(value, DriverError):
        future.set_exception(value)
    else:
        future.set_result(value)
    return future


def _then(future: Future[Any], change: Callable[[Any], Any]) -> Future[Any]:
    """The simulator's settled ``future`` with its result changed as the mistake does."""
    error = future.exception()
    return future if error is not None else _settled(change(future.result()))


class InternalGrasps(SimulatedHero):
    """Answers `internal` to every grasp (its gripper controller throws)."""

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return _settled(DriverError(INTERNAL, f"grasp: gripper controller: unexpected state in {procedure}"))


class InternalSenses(SimulatedHero):
    """Answers `internal` to every sensing (its sonar board resets on each sweep)."""

    def sense(self, procedure: str) -> Future[SenseResult]:
        return _settled(DriverError(INTERNAL, f"sense: sonar board reset during {procedure}"))


class StuckFinger(SimulatedHero):
    """The finger infrared sensor stuck at "held": every grasp is reported holding."""

    releases = 0

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return _then(super().grasp(procedure), lambda result: replace(result, success=True))

    def release(self) -> Future[RobotState]:
        self.releases += 1
        return super().release()


class SonarCentimetres(SimulatedHero):
    """Ranges and lengths in centimetres: the driver's own range check compares the sonar's
    6 in (15.2 cm) with the profile's inches and refuses every 6 in procedure; the lengths
    it does measure come out 2.54 times too large."""

    def _refused(self, procedure: str) -> DriverError | None:
        spec = PROFILE.knowledge()
        ranges = [p.range_in for p in (*spec.sensing, *spec.grasping) if p.name == procedure]
        if ranges and ranges[0][1] < 15.24:
            return DriverError(OUT_OF_RANGE, f"{procedure}: object at 15.2 outside {ranges[0][0]:g}-{ranges[0][1]:g}")
        return None

    def sense(self, procedure: str) -> Future[SenseResult]:
        refused = self._refused(procedure)
        if refused is not None:
            return _settled(refused)
        inches = {f.name for p in PROFILE.knowledge().sensing for f in p.features if f.unit == "in"}
        return _then(super().sense(procedure), lambda result: replace(result, values={
            k: (v * 2.54 if v is not None and k in inches else v) for k, v in result.values.items()}))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        refused = self._refused(procedure)
        return super().grasp(procedure) if refused is None else _settled(refused)


class Milliseconds(SimulatedHero):
    """Every duration in milliseconds."""

    def move(self, waypoints: Any, face: Any = None) -> Future[MoveResult]:
        return _then(super().move(waypoints, face), lambda r: replace(r, duration_s=r.duration_s * 1000))

    def sense(self, procedure: str) -> Future[SenseResult]:
        return _then(super().sense(procedure), lambda r: replace(r, duration_s=r.duration_s * 1000))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return _then(super().grasp(procedure), lambda r: replace(r, duration_s=r.duration_s * 1000))


class NoEchoAsMinusOne(SimulatedHero):
    """A sonar stuck deaf, its driver writing "no echo" as -1 where the protocol says
    null: every sweep reads -1 degrees."""

    def sense(self, procedure: str) -> Future[SenseResult]:
        return _then(super().sense(procedure), lambda r: replace(r, values={k: -1.0 for k in r.values}))


def _episode(driver: Any, folder: Path, params: Params = Params()) -> tuple[int, str, list[str],
                                                                         list[dict[str, Any]], list[Any]]:
    """The lab played to the end with ``driver``: exit status, why, closing lines, events, records."""
    learner = LocalLearner(folder / "library.sqlite", seed_library=read_library_json(EXAMPLE_LIBRARY))
    executive = Executive(driver, learner, profile=PROFILE, params=params)
    try:
        result = executive.run()
    finally:
        executive.shutdown()
        learner.close()
    events = list(executive.log.events)
    status, why, lines = run_status([r.outcome for r in result.objects], events, driver.robot)
    return status, why, lines, events, result.objects


def _kinds(events: list[dict[str, Any]], kind: str) -> list[dict[str, Any]]:
    return [e for e in events if e["event"] == kind]


def test_the_plain_simulator_exits_0_with_nothing_doubted(tmp_path: Path) -> None:
    status, why, lines, events, records = _episode(SimulatedHero("r1", world="lab"), tmp_path)
    assert (status, why, lines) == (ALL_HANDLED, "all 7 objects were handled", [])
    assert not any(e["event"] in ("driver_fault", "implausible", "grasp_unverified", "grasp_cost_ignored")
                   for e in events)
    assert all(r.verified for r in records)


def test_internal_to_every_grasp_is_seven_driver_faults_not_failed_grasps(tmp_path: Path) -> None:
    status, why, lines, events, _ = _episode(InternalGrasps("r1", world="lab"), tmp_path)
    faults = _kinds(events, "driver_fault")
    assert faults and {e["verb"] for e in faults} == {"grasp"}
    assert status == LOST
    assert lines[0].startswith(f"{len(faults)} driver faults (grasp: {len(faults)}): driver r1 failed verbs")
    assert why.startswith(lines[0])


def test_internal_to_every_sense_is_counted_under_sense(tmp_path: Path) -> None:
    status, _, lines, events, _ = _episode(InternalSenses("r1", world="lab"), tmp_path)
    faults = _kinds(events, "driver_fault")
    assert faults and {e["verb"] for e in faults} == {"sense"}
    assert status == LOST and lines[0].startswith(f"{len(faults)} driver faults (sense: {len(faults)})")


def test_a_finger_stuck_at_held_never_reports_an_object_grasped_on_the_floor(tmp_path: Path) -> None:
    hero = StuckFinger("r1", world="lab")
    status, why, lines, events, records = _episode(hero, tmp_path)
    unverified = _kinds(events, "grasp_unverified")
    assert unverified and all(e["driver"] == "r1" for e in unverified)
    truths = hero.truth()  # the simulator's truth, for the test only
    for record in records:
        if record.outcome == "grasped":  # nothing reported grasped lies on the floor
            x, y = record.region.centroid
            truth = min(truths, key=lambda t: (t.x_in - x) ** 2 + (t.y_in - y) ** 2)
            assert truth.held or truth.binned, (record.index, truth.name)
    assert {e["object"] for e in unverified} <= {r.index for r in records if r.outcome == "failed"}
    learned = {e["object"] for e in _kinds(events, "learn")}
    assert not learned & {e["object"] for e in unverified}  # nothing learned from them
    assert hero.releases == len(_kinds(events, "learn")) + len(unverified)  # the hand opened after each
    assert status == LOST and any(line.startswith(f"driver r1 suspect: {len(unverified)} grasps reported held")
                                  for line in lines)


def test_sonar_in_centimetres_is_nothing_really_done(tmp_path: Path) -> None:
    status, why, lines, events, records = _episode(SonarCentimetres("r1", world="lab"), tmp_path)
    assert not any(r.outcome == "grasped" for r in records)
    assert status == SOME_FAILED and why.startswith("nothing really done: no object of 7 was grasped")
    assert any(line.endswith("check the sonar's unit and the robot's range check against the profile")
               for line in lines)


def test_durations_in_milliseconds_are_left_out_of_the_learned_grasp_costs(tmp_path: Path) -> None:
    status, _, lines, events, _ = _episode(Milliseconds("r1", world="lab"), tmp_path)
    ignored = _kinds(events, "grasp_cost_ignored")
    grasps = _kinds(events, "grasp")
    assert ignored and len(ignored) == len(grasps)  # every executed grasp, none counted
    assert all(e["seconds"] == 1000 * e["expected"] for e in ignored)  # the simulator takes time_s exactly
    assert status == LOST and any("grasp durations implausible" in line for line in lines)


def test_a_deaf_sonar_writing_minus_one_is_implausible_and_never_followed(tmp_path: Path) -> None:
    # the lab's objects are told apart by the camera alone; without it the robot sweeps them
    status, _, lines, events, records = _episode(NoEchoAsMinusOne("r1", world="lab"), tmp_path, ARM_ONLY)
    implausible = _kinds(events, "implausible")
    sensed = _kinds(events, "sense")
    assert sensed and len(implausible) == len(sensed)  # each sweep yields one feature, each -1
    assert all(e["value"] == -1.0 and e["why"] == "outside the feature's span [0, 180] deg" for e in implausible)
    assert not _kinds(events, "branch") and not _kinds(events, "unreliable")  # never matched, never "unreliable"
    per_feature = Counter(e["feature"] for e in implausible)
    wrong = sorted(f for f, n in per_feature.items() if n >= WRONG_UNIT_MIN)  # every value of each implausible
    assert wrong, per_feature
    counts = ", ".join(f"{f}: {per_feature[f]} of {per_feature[f]}" for f in wrong)
    assert lines[0] == (f"driver r1 suspect: most values of {', '.join(wrong)} were implausible ({counts}); "
                        "check that sensor's unit against the profile")
    assert status == LOST  # whatever the objects' outcomes: the sonar is broken


class ExtraFieldNode(DriverNode):
    """A driver node whose sense reply carries one field the protocol does not define."""

    def _answer(self, verb: Verb, query: zenoh.Query, done: Future[Any]) -> None:
        if verb.name != "sense" or done.exception() is not None:
            super()._answer(verb, query, done)
            return
        body = json.loads(verb.encode_result(done.result()))
        body["confidence"] = 0.9
        reply(query, json.dumps(body).encode())


@pytest.mark.zenoh
def test_an_extra_field_in_the_sense_reply_is_driver_faults_over_zenoh(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    with open_session(listen=[endpoint]) as server, ExtraFieldNode(SimulatedHero("vx", world="lab"), server):
        driver = ZenohDriver("vx", connect=[endpoint], discover_s=5.0)
        try:
            status, why, lines, events, _ = _episode(driver, tmp_path, ARM_ONLY)
        finally:
            driver.close()
    faults = _kinds(events, "driver_fault")
    assert faults and {e["verb"] for e in faults} == {"sense"}
    assert all("malformed reply" in e["message"] for e in faults)
    assert status == LOST and lines[0].startswith(f"{len(faults)} driver faults (sense: {len(faults)})")


@pytest.mark.zenoh
@pytest.mark.slow
def test_csl_run_says_how_many_driver_faults_in_one_line_and_exits_3(tmp_path: Path) -> None:
    endpoint = free_endpoint()
    env = {**os.environ, "PYTHONPATH": str(REPO), "CSL_HOME": str(tmp_path)}
    with open_session(listen=[endpoint]) as server, ExtraFieldNode(SimulatedHero("vy", world="lab"), server):
        proc = subprocess.run(
            [sys.executable, "-m", "csl_cli", "run", "--driver", "zenoh", "--robot", "vy", "--connect", endpoint,
             "--no-appearance", "--out", str(tmp_path / "out"), "--no-plots"],
            cwd=REPO, env=env, capture_output=True, text=True, timeout=300)
    assert proc.returncode == LOST, proc.stderr
    faults = [line for line in proc.stderr.splitlines() if "driver faults" in line]
    assert len(faults) == 1 and re.fullmatch(
        r"csl: (\d+) driver faults \(sense: \1\): driver vy failed verbs \(`internal` or malformed replies\); "
        r"look at the robot", faults[0])
    assert "Traceback" not in proc.stderr
    assert proc.stdout.splitlines()[-1].startswith(f"exit status 3: {faults[0].removeprefix('csl: ')}; ")
