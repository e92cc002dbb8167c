"""The reference checks of ``csl driver check`` (hero_driver/zenoh_link/reference_check.py):
a driver that cannot restore the lab, like a real robot, has its sensing and grasping
checked on objects placed on its floor, and a driver with a vendor's mistake in what
it senses or grasps fails the check that names it."""

from __future__ import annotations

import dataclasses
import io
import json
import math
import re
from collections.abc import Iterator, Sequence
from concurrent.futures import Future
from pathlib import Path

import pytest
import zenoh

from camera_model.board import load_board
from csl_cli.main import main
from hero_driver.interface import BAD_REQUEST, DriverError, GraspResult, RobotState, SenseResult
from hero_driver.sim import camera as sim_camera
from hero_driver.sim.render_board import board_path
from hero_driver.sim_driver import SimulatedHero
from hero_driver.shipped import WORLDS_DIR
from hero_driver.zenoh_link import verbs
from hero_driver.zenoh_link.checking import CheckResult, Probe
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.reference_check import (
    DEFAULT_OBJECTS, LIBRARY, NOT_CHECKED, NOT_PLACED, Reference, reference_checks, reference_objects,
)
from planner.segmentation import calibrated_camera
from robot_profile import DEFAULT_PROFILE, load_profile
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

PROFILE = load_profile(DEFAULT_PROFILE)
BOX, CAN = DEFAULT_OBJECTS
REFERENCE_CHECKS = {"reference-objects", "reference-sensing", "reference-stale", "reference-grasp",
                    "reference-wrong-grasp"}
# The shipped world of the reference check: the two default objects where an operator
# might put them, the box at (150, 100) turned 30 deg (so a yaw drawn the other way round
# is 60 deg off), the can at (70, 110).
WORLD = WORLDS_DIR / "reference.json"


class RealRobot(SimulatedHero):
    """A driver that, like a real robot, cannot restore a named world."""

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        if world is not None:
            return _failed(DriverError(BAD_REQUEST, "a real robot cannot restore a world"))
        return super().reset(None, seed)


class Centimetres(RealRobot):
    """Reports the sonar's lengths in centimetres: every inch feature times 2.54."""

    def sense(self, procedure: str) -> Future[SenseResult]:
        result = self.sense_now(procedure)
        inches = {f.name for p in PROFILE.sensing for f in p.features if f.unit == "in"}
        values = {k: (v * 2.54 if k in inches and v is not None else v) for k, v in result.values.items()}
        return _settled(dataclasses.replace(result, values=values))

    def sense_now(self, procedure: str) -> SenseResult:
        return super().sense(procedure).result()


class StuckHeld(RealRobot):
    """A finger sensor stuck at "held": every grasp reports success."""

    def grasp(self, procedure: str) -> Future[GraspResult]:
        result = super().grasp(procedure).result()
        return _settled(dataclasses.replace(result, success=True))


class Stale(RealRobot):
    """Each procedure repeats the values of its first reading."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)
        self.first: dict[str, SenseResult] = {}

    def sense(self, procedure: str) -> Future[SenseResult]:
        result = super().sense(procedure).result()
        first = self.first.setdefault(procedure, result)
        return _settled(dataclasses.replace(result, values=first.values))


class YawReversed(RealRobot):
    """The camera draws each object turned the other way round (-yaw) from where the
    sonar and the hand meet it."""

    def camera(self) -> Future:
        sim = self.world
        floor = [(o.entry.footprint, o.x_in, o.y_in, -o.yaw_deg) for o in sim.physics.objects if o.status == "floor"]
        return _settled(sim_camera.render(sim.spec, floor, sim.pose, PROFILE.robot.geometry.base_radius_in, sim.noise,
                                          sim.rng, sim.clock_s, preset=sim.camera_preset,
                                          movers=sim.physics.movers.outlines()))


class DrawsLifted(RealRobot):
    """Draws its floor from a world model that never takes a lifted object away."""

    def camera(self) -> Future:
        sim = self.world
        floor = [(o.entry.footprint, o.x_in, o.y_in, o.yaw_deg) for o in sim.physics.objects]
        return _settled(sim_camera.render(sim.spec, floor, sim.pose, PROFILE.robot.geometry.base_radius_in, sim.noise,
                                          sim.rng, sim.clock_s, preset=sim.camera_preset,
                                          movers=sim.physics.movers.outlines()))


class FrozenCamera(RealRobot):
    """Sends the first image it took, whatever changed on the floor since."""

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)
        self.first: Future | None = None

    def camera(self) -> Future:
        if self.first is None:
            self.first = super().camera()
        return self.first


def _settled(value: object) -> Future:
    future: Future = Future()
    future.set_result(value)
    return future


def _failed(error: Exception) -> Future:
    future: Future = Future()
    future.set_exception(error)
    return future


@pytest.fixture
def client(endpoint: str, server: zenoh.Session) -> Iterator[zenoh.Session]:
    with open_session(connect=[endpoint]) as session:
        yield session


def reference() -> Reference:
    return Reference(reference_objects(DEFAULT_OBJECTS, PROFILE), PROFILE)


def check_reference(driver: SimulatedHero, server: zenoh.Session, client: zenoh.Session) -> dict[str, CheckResult]:
    """The reference checks alone against ``driver`` served in-process, by name."""
    with DriverNode(driver, server):
        probe = Probe(client, driver.robot, 5.0)
        try:
            assert probe.rpc.wait_alive(5.0)  # the suite's first check, before which nothing is asked
            results = reference_checks(probe, reference())
        finally:
            probe.close()
    return {r.name: r for r in results}


def failed(results: dict[str, CheckResult]) -> set[str]:
    return {name for name, result in results.items() if not result.passed}


def test_a_real_robot_passes_on_the_reference(server: zenoh.Session, client: zenoh.Session) -> None:
    results = check_reference(RealRobot("real", world=WORLD), server, client)
    assert set(results) == REFERENCE_CHECKS
    assert failed(results) == set(), results
    assert results["reference-objects"].detail.startswith(
        f"{BOX} seen at (150.0, 100.0) over ")
    assert f"; {CAN} seen at (70.0, 110.0) over " in results["reference-objects"].detail
    # the box: four sides at 6 in, three at 15 in, one at 39; the can: 6, 15 and 39 in on one side
    assert results["reference-objects"].detail.endswith("; 11 training positions reachable")
    assert results["reference-grasp"].detail == f"Front-Wrap held {CAN}, which left the floor; released"
    # the box's grasp is No-Grab: Front-Pinch, the cheapest grasp the fingers confirm, cannot lift it
    assert results["reference-wrong-grasp"].detail == (f"Front-Pinch on {BOX}, a grasp that cannot lift it, "
                                                       "reported not held")
    # the box's Width-Degree-5° is 85 at 6 in on its long side and 15 at 39 in: 14 expected errors apart
    assert results["reference-stale"].detail.startswith("Width-Degree-5° read ")
    assert results["reference-stale"].detail.endswith("(library 85, 15)")


def test_a_real_looking_camera_is_read_through_its_calibration(server: zenoh.Session, client: zenoh.Session,
                                                               tmp_path: Path) -> None:
    """The realistic camera, calibrated on the same room with nothing on the floor (the
    board of the lab, which the world names): the executive's vision finds both objects."""
    empty = tmp_path / "empty.json"
    empty.write_text(json.dumps({**json.loads(WORLD.read_text(encoding="utf-8")), "objects": []}), encoding="utf-8")
    floor = SimulatedHero("empty", world=empty, camera="realistic").camera().result().pixels
    camera = calibrated_camera(floor, load_board(board_path("lab")))
    with DriverNode(RealRobot("seen", world=WORLD, camera="realistic"), server):
        probe = Probe(client, "seen", 5.0)
        try:
            assert probe.rpc.wait_alive(5.0)
            results = {r.name: r for r in reference_checks(probe, dataclasses.replace(reference(), camera=camera))}
        finally:
            probe.close()
    assert failed(results) == set(), results
    assert results["reference-objects"].detail.startswith(f"{BOX} seen at (")


def test_objects_placed_too_close_stop_the_checks_before_the_robot_moves(server: zenoh.Session,
                                                                        client: zenoh.Session, tmp_path: Path) -> None:
    """The can 28 in from the box's centre along its long axis (turned 30 deg): the
    library has positions at 6 in off both ends and 15 in off one, where the base
    (9 in round, its centre 11 in behind the sonar) would stand on the can."""
    world = json.loads(WORLD.read_text(encoding="utf-8"))
    world["objects"][1].update(x_in=round(150 - 28 * math.cos(math.radians(30)), 1),
                               y_in=round(100 - 28 * math.sin(math.radians(30)), 1))
    path = tmp_path / "close.json"
    path.write_text(json.dumps(world), encoding="utf-8")
    driver = RealRobot("close", world=path)
    results = check_reference(driver, server, client)
    assert not results["reference-objects"].passed
    assert results["reference-objects"].detail.endswith("place the objects farther apart")
    assert all(results[name].detail == "needs reference-objects to pass" for name in REFERENCE_CHECKS - {
        "reference-objects"})
    assert driver.state().clock_s == 0  # not one move, sense or grasp


def test_sonar_lengths_in_centimetres_fail_sensing(server: zenoh.Session,
                                                   client: zenoh.Session) -> None:
    results = check_reference(Centimetres("cm", world=WORLD), server, client)
    assert failed(results) == {"reference-sensing"}
    # the can's D-Scan at 6 in: Depth 2.7 in by the library (± 3 x 0.5), read 2.54 times too long, twice (or
    # once, and once not at all: the simulator drops a value now and then, as a sonar does)
    READ = r"(?:[\d.]+|nothing)"
    assert re.fullmatch(rf"D-Scan-0\.3 at {re.escape(CAN)} at \(6 in, \d+ deg\): Depth read {READ}, {READ}; "
                        r"the library has 2\.7 in within 1\.5 \(3 x its expected error 0\.5\)",
                        results["reference-sensing"].detail), results["reference-sensing"].detail


def test_a_finger_sensor_stuck_at_held_fails_the_wrong_grasp(server: zenoh.Session,
                                                            client: zenoh.Session) -> None:
    results = check_reference(StuckHeld("stuck", world=WORLD), server, client)
    assert failed(results) == {"reference-wrong-grasp"}
    assert results["reference-wrong-grasp"].detail == (
        f"Front-Pinch on {BOX}, a grasp that cannot lift it, reported held, and the camera still sees it on the "
        "floor (a finger sensor stuck at held?)")


def test_a_stale_sensor_fails(server: zenoh.Session, client: zenoh.Session) -> None:
    results = check_reference(Stale("stale", world=WORLD), server, client)
    assert {"reference-sensing", "reference-stale"} <= failed(results)
    stale = results["reference-stale"].detail
    assert stale.startswith("Width-Degree-5° read ") and stale.endswith(
        "the library has 85 and 15 there, so the readings must differ by at least 35 (a stale or stuck reading?)")
    first, second = re.findall(r"read (\S+) at .* and then (\S+) at ", stale)[0]
    assert first == second


def test_objects_yaw_drawn_the_other_way_round_fails_sensing(server: zenoh.Session,
                                                             client: zenoh.Session) -> None:
    """The camera shows the box at -30 deg, the sonar meets it at +30: standing 6 in off
    the face the camera shows, the sonar is against (or inside) a corner of the real box."""
    results = check_reference(YawReversed("yaw", world=WORLD), server, client)
    assert "reference-sensing" in failed(results)
    assert f"at {BOX} at (" in results["reference-sensing"].detail
    assert results["reference-grasp"].passed  # the can is round: its yaw does not matter


def test_a_camera_that_still_draws_a_lifted_object_fails_the_grasp(server: zenoh.Session,
                                                                  client: zenoh.Session) -> None:
    """The can was lifted (the fingers say so), yet the image still shows it where it stood."""
    results = check_reference(DrawsLifted("lifted", world=WORLD), server, client)
    assert failed(results) == {"reference-grasp"}
    assert results["reference-grasp"].detail == (f"Front-Wrap on {CAN} reported held, but the camera still sees it "
                                                 "on the floor at (70.0, 110.0)")


def test_a_camera_that_keeps_sending_its_first_image_stops_the_robot(server: zenoh.Session,
                                                                    client: zenoh.Session) -> None:
    """Moved by the driver, the robot stays at its start in the image: the drift the
    executive corrects would be the whole drive, so the checks stop before the robot is
    sent by it (into an object)."""
    driver = FrozenCamera("frozen", world=WORLD)
    results = check_reference(driver, server, client)
    assert failed(results) == REFERENCE_CHECKS - {"reference-objects"}
    assert re.fullmatch(r"the camera sees the robot at \(30\.0, 30\.0\), [\d.]+ in from where the driver says it "
                        r"is \([\d.]+, [\d.]+\); at most 4 in \(a stale image, or a pose that is not the robot's\?\)",
                        results["reference-sensing"].detail), results["reference-sensing"].detail
    assert driver.contacts == 0


@pytest.mark.parametrize("ids, problem", [
    (["no-such-thing/upright", CAN], "no-such-thing/upright: not in the object catalogue"),
    (["closed-box-10x10x10/upright", CAN], "closed-box-10x10x10/upright: the library hero2000-library.json has no "
                                           "description of it"),
    ([CAN, "cup-8oz/upright"], f"{CAN} and cup-8oz/upright cannot be told apart by the camera"),
    ([CAN], "expected at least two different catalogue ids"),
    # 99 and 45 sq in: a region of 66 sq in would fit both
    ([BOX, "open-box-9x4x5/lying-facing-down"], f"{BOX} and open-box-9x4x5/lying-facing-down cannot be told apart"),
])
def test_reference_objects_are_refused_in_one_line(ids: Sequence[str], problem: str) -> None:
    with pytest.raises(ValueError, match=re.escape(problem)):
        reference_objects(ids, PROFILE)


def test_a_reference_with_nothing_to_lift_is_refused(tmp_path: Path) -> None:
    """The grasp check needs an object the finger sensor can confirm held."""
    document = json.loads(LIBRARY.read_text(encoding="utf-8"))
    for description in document["descriptions"]:
        if description["id"] == CAN:
            description["grasp"] = "No-Grab"
    library = tmp_path / "library.json"
    library.write_text(json.dumps(document), encoding="utf-8")
    with pytest.raises(ValueError, match=re.escape(f"none of {BOX}, {CAN} can be lifted")):
        reference_objects(DEFAULT_OBJECTS, PROFILE, library)


def test_an_operator_who_does_not_place_the_objects_leaves_them_not_checked(server: zenoh.Session,
                                                                          client: zenoh.Session) -> None:
    asked: list[str] = []

    def decline(text: str) -> bool:
        asked.append(text)
        return False

    with DriverNode(RealRobot("asked", world=WORLD), server):
        probe = Probe(client, "asked", 5.0)
        try:
            assert probe.rpc.wait_alive(5.0)
            results = reference_checks(probe, dataclasses.replace(reference(), ask=decline))
        finally:
            probe.close()
    assert results == [CheckResult("reference", False, NOT_PLACED)]
    (text,) = asked
    assert f"  - {BOX}\n  - {CAN}\n" in text
    assert "grasp soda-can-12oz/upright with Front-Wrap" in text and "Press Enter" in text


def run_cli(driver: SimulatedHero, server: zenoh.Session, endpoint: str, capsys: pytest.CaptureFixture[str],
            *extra: str) -> tuple[int, dict[str, str], dict[str, str]]:
    """``csl driver check`` against ``driver`` served in-process: the exit status, each
    check's PASS/FAIL and its detail."""
    with DriverNode(driver, server):
        status = main(["driver", "check", "--robot", driver.robot, "--connect", endpoint, "--timeout", "10", *extra])
    rows = re.findall(r"^(\S+)\s+(PASS|FAIL)\s+(.*)$", capsys.readouterr().out, re.MULTILINE)
    return status, {name: verdict for name, verdict, _ in rows}, {name: detail for name, _, detail in rows}


@pytest.mark.slow
@pytest.mark.parametrize("flags", [("--reference", "--placed"), ("--placed",)], ids=["reference", "placed-only"])
def test_a_real_robot_passes_the_suite_with_a_reference(server: zenoh.Session, endpoint: str,
                                                       capsys: pytest.CaptureFixture[str], flags: Sequence[str]) -> None:
    """With ``--placed`` alone, the default objects are taken as placed."""
    status, verdicts, details = run_cli(RealRobot("real", world=WORLD), server, endpoint, capsys, *flags)
    assert {name for name, verdict in verdicts.items() if verdict == "FAIL"} == set()
    assert REFERENCE_CHECKS <= set(verdicts) and "reference" not in verdicts
    assert details["reset-objects"] == "not checked: the driver cannot restore world 'lab' (a real robot cannot " \
                                       "restore a world)"
    assert status == 0


@pytest.mark.slow
def test_a_real_robot_without_a_reference_fails_not_checked(server: zenoh.Session, endpoint: str,
                                                            capsys: pytest.CaptureFixture[str]) -> None:
    """Its sense and grasp checks pass on no_target, so the suite must not."""
    status, verdicts, details = run_cli(RealRobot("bare", world=WORLD), server, endpoint, capsys)
    assert {name for name, verdict in verdicts.items() if verdict == "FAIL"} == {"reference"}
    assert details["reference"] == NOT_CHECKED
    assert not REFERENCE_CHECKS & set(verdicts)
    assert status == 1


@pytest.mark.slow
def test_an_operator_asked_on_standard_error_may_skip(server: zenoh.Session, endpoint: str,
                                                      capsys: pytest.CaptureFixture[str],
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr("sys.stdin", io.StringIO("skip\n"))
    with DriverNode(RealRobot("ask", world=WORLD), server):
        status = main(["driver", "check", "--robot", "ask", "--connect", endpoint, "--timeout", "10", "--reference"])
    out, err = capsys.readouterr()
    assert re.search(rf"^reference +FAIL +{NOT_PLACED}$", out, re.MULTILINE), out
    assert err.startswith("reference check: place these objects anywhere on the floor") and "Press Enter" in err
    assert status == 1


@pytest.mark.slow
def test_the_simulator_passes_with_a_reference(server: zenoh.Session, endpoint: str,
                                               capsys: pytest.CaptureFixture[str]) -> None:
    """A simulator restores the lab for the other checks and the shipped world
    'reference' for these: nobody is asked to place anything."""
    status, verdicts, details = run_cli(SimulatedHero("sim"), server, endpoint, capsys, "--reference")
    assert {name for name, verdict in verdicts.items() if verdict == "FAIL"} == set()
    assert details["reset-objects"].startswith("world 'lab': 7 objects drawn where reset placed them")
    assert REFERENCE_CHECKS <= set(verdicts)
    assert status == 0


@pytest.mark.parametrize("ids, problem", [
    ("no-such-thing/upright,soda-can-12oz/upright", "no-such-thing/upright: not in the object catalogue"),
    ("closed-box-10x10x10/upright,soda-can-12oz/upright", "closed-box-10x10x10/upright: the library"),
])
def test_bad_reference_ids_exit_2_with_one_line(ids: str, problem: str, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["driver", "check", "--reference", ids, "--timeout", "1"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"csl: error: --reference: {problem}") and err.count("\n") == 1, err


def test_an_extra_field_in_the_sense_reply_fails_sensing(server: zenoh.Session, client: zenoh.Session,
                                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """The mistake the lab's checks never saw (from the reset pose nothing is in range,
    so no sense result is ever decoded there): on the reference every reply is read as
    strictly as the executive reads it."""
    sense = verbs.BY_NAME["sense"]

    def chatty_out(result: SenseResult) -> dict[str, object]:
        return {**sense.reply.write(result), "gain_db": 12}

    monkeypatch.setitem(verbs.BY_NAME, "sense", dataclasses.replace(
        sense, reply=dataclasses.replace(sense.reply, write=chatty_out)))  # the node's wire
    results = check_reference(RealRobot("chatty", world=WORLD), server, client)
    assert "reference-sensing" in failed(results)
    assert "gain_db: unknown field" in results["reference-sensing"].detail
