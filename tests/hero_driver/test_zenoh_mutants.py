"""Drivers that decode perfectly and still ruin every episode must fail ``csl driver
check``: each mutant here is the simulated HERO with one thing wrong,
served in-process by the real node, and the suite must name the check it breaks."""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Sequence
from concurrent.futures import Future
from pathlib import Path

import numpy as np
import pytest
import zenoh

from camera_model.board import load_board
from camera_model.image import CameraImage
from hero_driver.interface import MoveResult, Pose
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.render_board import board_path
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link import verbs
from hero_driver.zenoh_link.camera_check import Vision, calibrated_reader
from hero_driver.zenoh_link.conformance import CheckResult, Procedures, run_checks, shutdown_order
from hero_driver.zenoh_link.node import DriverNode
from planner.segmentation import calibrated_camera, save_camera
from tests.hero_driver.test_zenoh_conformance import BUSY_CHECKS, run_named_checks
from zenoh_rpc.server import RpcServer

pytestmark = pytest.mark.zenoh

SLOW_TURN_S = 0.5
SHIFT_PX = 10  # 8 in at the simulator's 0.8 in per pixel
PARKING_S = 1.0  # what a driver that parks its arm between queryables and token leaves open


class RowsFromBottom(SimulatedHero):
    """Sends the overhead image with row 0 at the room's low-y edge."""

    def camera(self) -> Future[CameraImage]:
        image = super().camera().result()
        return _done(dataclasses.replace(image, pixels=image.pixels[::-1].copy()))


class ObjectsAt180(SimulatedHero):
    """Draws objects at grey level 180 (the robot's band) instead of 220."""

    def camera(self) -> Future[CameraImage]:
        image = super().camera().result()
        pixels = image.pixels.copy()
        objects = (pixels >= 195) & (pixels <= 234)
        pixels[objects] -= 40
        return _done(dataclasses.replace(image, pixels=pixels))


class ObjectsShifted(SimulatedHero):
    """Draws every object 8 in along +x of where it is (a camera calibrated off by 10 px)."""

    def camera(self) -> Future[CameraImage]:
        image = super().camera().result()
        pixels = image.pixels.copy()
        objects = (pixels >= 195) & (pixels <= 234)
        pixels[objects] = 30
        pixels[np.roll(objects, SHIFT_PX, axis=1)] = 220
        return _done(dataclasses.replace(image, pixels=pixels))


class SlowTurns(SimulatedHero):
    """Moves take real time, finishing on a timer as a hardware driver's would."""

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        done = super().move(waypoints, face)
        later: Future[MoveResult] = Future()
        threading.Timer(SLOW_TURN_S, lambda: later.set_result(done.result())).start()
        return later


class MirroredCamera(SimulatedHero):
    """A real-looking camera turned round after it was calibrated: its image shows the
    room left to right the other way (columns reversed)."""

    def camera(self) -> Future[CameraImage]:
        image = super().camera().result()
        return _done(dataclasses.replace(image, pixels=image.pixels[:, ::-1].copy()))


def _done(value: CameraImage) -> Future[CameraImage]:
    future: Future[CameraImage] = Future()
    future.set_result(value)
    return future


def check(driver: SimulatedHero, server: zenoh.Session, endpoint: str,
          vision: Vision | None = None) -> dict[str, CheckResult]:
    with DriverNode(driver, server):
        results = run_checks(driver.robot, [endpoint], timeout_s=5.0, procedures=Procedures.from_profile(),
                             vision=vision)
    return {result.name: result for result in results}


def failed(results: dict[str, CheckResult]) -> set[str]:
    return {name for name, result in results.items() if not result.passed}


def test_rows_counted_from_the_bottom_fail_the_camera_mapping(server: zenoh.Session, endpoint: str) -> None:
    results = check(RowsFromBottom("flip"), server, endpoint)
    assert failed(results) == {"camera-mapping", "reset-objects", "turns"}  # no robot seen: no turn seen
    assert "row-mirrored place" in results["camera-mapping"].detail
    assert "row-mirrored place" in results["turns"].detail
    assert "one is at the row-mirrored place" in results["reset-objects"].detail


@pytest.mark.slow
def test_objects_at_grey_180_fail_the_camera_mapping(server: zenoh.Session, endpoint: str) -> None:
    results = check(ObjectsAt180("grey"), server, endpoint)
    assert failed(results) == {"camera-mapping", "reset-objects"}
    assert "objects belong at 195-234" in results["camera-mapping"].detail
    assert "nothing drawn in the object levels 195-234" in results["reset-objects"].detail


@pytest.mark.slow
def test_objects_drawn_off_their_place_fail_reset_objects(server: zenoh.Session, endpoint: str) -> None:
    results = check(ObjectsShifted("shift"), server, endpoint)
    assert failed(results) == {"reset-objects"}
    # the lab's first object, a 2 x 2 in box at (70, 60), drawn 10 px = 8 in along +x
    assert results["reset-objects"].detail == ("world 'lab': closed-box-2x2x2/upright: drawn at (78.0, 60.0), 8.0 in "
                                               "from (70, 60) where reset placed it; at most 3 in")


@pytest.mark.slow
def test_a_band_camera_through_a_fisheye_lens_passes(server: zenoh.Session, endpoint: str) -> None:
    """The control for the camera mutants: band images sent with their fish-eye lens
    (the harsh noise preset: lens, pixel noise 10, odometry noise) are undistorted by
    the suite as the protocol says and pass both image checks."""
    results = check(SimulatedHero("fish", noise=NoiseConfig.preset("harsh")), server, endpoint)
    assert failed(results) == set()
    assert results["camera-mapping"].detail.startswith("robot drawn at (")
    assert results["reset-objects"].detail.startswith("world 'lab': 7 objects drawn where reset placed them")


@pytest.mark.slow
def test_a_camera_turned_after_calibration_fails_through_the_calibration(server: zenoh.Session, endpoint: str,
                                                                         tmp_path: Path) -> None:
    """Read through the calibration of the camera as it was, the turned camera's floor
    no longer matches the calibration's empty floor: both image checks fail with the
    scene-change line of the executive's vision (planner/scene_check.py)."""
    calibration = tmp_path / "cam.json"
    good = SimulatedHero("cal", camera="realistic")
    pixels = good.camera().result().pixels
    camera = calibrated_camera(pixels, load_board(board_path("lab")))
    save_camera(camera.calibration, camera.calibration.rectify(pixels), calibration)
    good.close()
    results = check(MirroredCamera("turned", camera="realistic"), server, endpoint, calibrated_reader(calibration))
    # a mirrored image shows every turn the other way round
    assert failed(results) == {"camera-mapping", "reset-objects", "turns"}
    assert results["camera-mapping"].detail.startswith("the calibrated vision")
    assert results["reset-objects"].detail.startswith(
        "world 'lab': the calibrated vision: the floor no longer matches the calibration: ")


def test_a_driver_that_drops_its_token_first_passes_shutdown_order(server: zenoh.Session, endpoint: str) -> None:
    node = DriverNode(SimulatedHero("down"), server)
    result = shutdown_order("down", [endpoint], node.close, timeout_s=5.0)
    assert result.passed, result.detail
    assert int(result.detail.split()[3]) >= 5  # "token went first: N of M noops answered": pinged while it stopped


def test_queryables_gone_before_the_token_fail_shutdown_order(server: zenoh.Session, endpoint: str,
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    """A node that undeclares its queryables, parks the arm for a second, and only
    then drops its token: clients see it alive and get no answers meanwhile."""
    def queryables_first(self: RpcServer) -> None:
        for queryable in self._queryables:
            queryable.undeclare()
        time.sleep(PARKING_S)
        self._token.undeclare()

    monkeypatch.setattr(RpcServer, "close", queryables_first)
    node = DriverNode(SimulatedHero("late"), server)
    result = shutdown_order("late", [endpoint], node.close, timeout_s=5.0)
    assert not result.passed
    assert "noop(s) sent while the token was still visible got no reply" in result.detail
    missed = int(result.detail.split()[0])
    assert missed >= 10  # about (PARKING_S - SHUTDOWN_RACE_S) / PING_PERIOD_S = 37 on an idle machine


def test_a_driver_that_never_stops_fails_shutdown_order(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(SimulatedHero("stays"), server):
        result = shutdown_order("stays", [endpoint], None, timeout_s=1.0)
    assert not result.passed
    assert result.detail == "the token on hero/stays/alive was still there 1 s later: the driver did not stop, " \
                            "or kept its token"


@pytest.mark.slow
@pytest.mark.parametrize("when", [lambda _result: True, lambda result: result.centred],
                         ids=["every-move", "centred-moves-only"])
def test_an_extra_field_in_move_replies_fails_the_move(server: zenoh.Session, endpoint: str,
                                                      monkeypatch: pytest.MonkeyPatch, when) -> None:  # noqa: ANN001
    move = verbs.BY_NAME["move"]

    def chatty_out(result: MoveResult) -> dict[str, object]:
        return {**move.reply.write(result), **({"speed_in_s": 0.5} if when(result) else {})}

    chatty = dataclasses.replace(move, reply=dataclasses.replace(move.reply, write=chatty_out))
    monkeypatch.setitem(verbs.BY_NAME, "move", chatty)  # the node's wire
    results = check(SimulatedHero("chatty"), server, endpoint)
    assert {"move", "state-after-move", "busy"} <= failed(results)
    assert "speed_in_s: unknown field" in results["move"].detail


class RunsAnything(verbs.Verb):
    """A verb that reads no request: whatever it is sent, it runs."""

    def decode_request(self, data: bytes) -> object:
        return self.request.value()


def test_a_verb_that_runs_whatever_it_is_sent_fails_every_verb(server: zenoh.Session, endpoint: str,
                                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """``release`` on a JSON array: a driver that releases anyway passes every check that
    sends release a proper request, and only the check of every verb sees it."""
    release = verbs.BY_NAME["release"]
    lax = RunsAnything(**{field.name: getattr(release, field.name) for field in dataclasses.fields(release)})
    monkeypatch.setitem(verbs.BY_NAME, "release", lax)
    results = check(SimulatedHero("lax"), server, endpoint)
    assert failed(results) == {"every-verb"}
    assert results["every-verb"].detail == "release: expected an error reply, got a result"


def test_verb_queryables_answering_wildcards_fail_wildcard_silence(server: zenoh.Session, endpoint: str,
                                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    def answer_any_key(self: RpcServer, verb: str):  # type: ignore[no-untyped-def]
        return lambda query: self._handle(verb, query)

    monkeypatch.setattr(RpcServer, "_exact", answer_any_key)
    results = check(SimulatedHero("greedy"), server, endpoint)
    assert failed(results) == {"wildcard-silence"}
    assert "replies to one query, expected exactly one" in results["wildcard-silence"].detail


def check_busy(driver: SimulatedHero, server: zenoh.Session, endpoint: str) -> dict[str, CheckResult]:
    """The busy check and those it builds on: with SlowTurns every move of the whole
    suite would take SLOW_TURN_S (the template's test runs a driver whose moves take
    real time through all of it)."""
    with DriverNode(driver, server):
        return run_named_checks(driver.robot, endpoint, BUSY_CHECKS, timeout_s=5.0,
                                procedures=Procedures.from_profile())


@pytest.mark.slow
def test_a_slow_turn_makes_a_second_verb_busy(server: zenoh.Session, endpoint: str) -> None:
    results = check_busy(SlowTurns("slow"), server, endpoint)
    assert failed(results) == set()
    assert "refused busy during a" in results["busy"].detail


@pytest.mark.slow
def test_a_driver_that_queues_fails_busy(server: zenoh.Session, endpoint: str,
                                         monkeypatch: pytest.MonkeyPatch) -> None:
    """A node that waits for the running verb instead of refusing the next one."""
    original = DriverNode._start

    def queue(self: DriverNode, verb: verbs.Verb, request: object) -> Future[object]:
        while verb.touches_robot and self._busy_verb is not None:
            time.sleep(0.01)
        return original(self, verb, request)

    monkeypatch.setattr(DriverNode, "_start", queue)
    results = check_busy(SlowTurns("queue"), server, endpoint)
    assert failed(results) == {"busy"}
    assert "held until it ended" in results["busy"].detail
