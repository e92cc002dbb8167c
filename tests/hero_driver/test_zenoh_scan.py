"""The ``scan`` feature over the real zenoh link on 127.0.0.1: the node serves the
simulator's scans and lists the feature, the client asks for them (and refuses them in
one line of a driver without it), the wire format keeps its schema and refuses what a
scan cannot be, and ``csl driver check``'s scan checks pass the simulator and fail the
mutants that decode perfectly and still mislead a map: ranges in centimetres, a scan in
the world's frame, a clock in milliseconds."""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Iterator
from concurrent.futures import Future
from pathlib import Path

import pytest
import zenoh
from jsonschema import Draft202012Validator

from hero_driver.interface import UNKNOWN_VERB, DriverError, Pose, RangeScan
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim_driver import SimulatedHero
from hero_driver.zenoh_link.checking import CheckResult, Probe, message, run_check
from hero_driver.zenoh_link.client import ZenohDriver
from hero_driver.zenoh_link.codec import CodecError
from hero_driver.zenoh_link.conformance import Procedures, run_checks
from hero_driver.zenoh_link.node import DriverNode
from hero_driver.zenoh_link.scan_check import ScanChecks, square_wall, toward
from hero_driver.zenoh_link.verbs import BY_NAME
from tests.hero_driver.test_zenoh_motion_checks import failed
from robot_profile import SCANNER_DEFAULTS, ScannerSpec, load_profile
from tests.hero_driver.test_sim_scan import world
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

SCHEMA = json.loads((Path(__file__).resolve().parents[2] / "docs" / "schemas" / "scan.reply.json").read_text())
SCAN = BY_NAME["scan"]


def _done(scan: RangeScan) -> Future[RangeScan]:
    future: Future[RangeScan] = Future()
    future.set_result(scan)
    return future


class RangesInCentimetres(SimulatedHero):
    """Reports every range, and the limits, in centimetres: a consistent scan of a room
    2.54 times too large."""

    def scan(self) -> Future[RangeScan]:
        s = super().scan().result()
        return _done(dataclasses.replace(s, ranges_in=tuple(r * 2.54 for r in s.ranges_in),
                                         range_min_in=s.range_min_in * 2.54, range_max_in=s.range_max_in * 2.54))


class ScanInTheWorldFrame(SimulatedHero):
    """Reports each beam's world heading instead of its angle from the robot's heading."""

    def scan(self) -> Future[RangeScan]:
        s = super().scan().result()
        beams = sorted(((a + s.pose.heading_deg + 180.0) % 360.0 - 180.0, r)
                       for a, r in zip(s.angles_deg, s.ranges_in, strict=True))
        return _done(dataclasses.replace(s, angles_deg=tuple(a for a, _ in beams),
                                         ranges_in=tuple(r for _, r in beams)))


class AnglesInRadians(SimulatedHero):
    def scan(self) -> Future[RangeScan]:
        s = super().scan().result()
        return _done(dataclasses.replace(s, angles_deg=tuple(math.radians(a) for a in s.angles_deg)))


class ClockInMilliseconds(SimulatedHero):
    def scan(self) -> Future[RangeScan]:
        s = super().scan().result()
        return _done(dataclasses.replace(s, clock_s=s.clock_s * 1000.0))


class NoScanner(SimulatedHero):
    """A driver from before the feature: no ``scan`` method."""

    scan = None  # type: ignore[assignment]


def profile(model: str):  # noqa: ANN201 (a RobotProfile)
    scanner = ScannerSpec(model=model, **SCANNER_DEFAULTS[model])  # type: ignore[arg-type]
    return dataclasses.replace(load_profile(), scanner=scanner)


@pytest.fixture
def client_session(server: zenoh.Session, endpoint: str) -> Iterator[zenoh.Session]:
    with open_session(connect=[endpoint]) as session:
        yield session


def scan_checks(driver: SimulatedHero, server: zenoh.Session, session: zenoh.Session) -> dict[str, CheckResult]:
    """The scan checks alone, against ``driver`` served on ``server``."""
    results = {}
    with DriverNode(driver, server):
        probe = Probe(session, driver.robot, 10.0)
        try:
            assert probe.rpc.wait_alive(5.0)
            checks = ScanChecks(probe, lambda: ("scan",) if driver.scan is not None else ())
            results.update((name, run_check(name, check)) for name, check in checks.checks())
        finally:
            probe.close()
    return results


# -- the round trip ----------------------------------------------------------------------

def test_a_scan_crosses_the_link_as_the_simulator_took_it(server: zenoh.Session, endpoint: str) -> None:
    """Under the paper preset some beams hear nothing: ``inf`` goes as ``null`` and
    comes back ``inf``; every other number arrives exactly."""
    here = SimulatedHero("there", world="lab", seed=2, noise=NoiseConfig.preset("paper"))
    served = SimulatedHero("scan1", world="lab", seed=2, noise=NoiseConfig.preset("paper"))
    with DriverNode(served, server), ZenohDriver("scan1", connect=[endpoint], discover_s=5.0) as client:
        assert client.wait_ready(5.0)
        assert "scan" in client.hello().result(5.0).served.features
        assert "scan" in client.agreement.features
        got = client.scan().result(10.0)
    expected = here.scan().result()
    assert got == expected
    assert any(math.isinf(r) for r in got.ranges_in)  # a dropout or a mirror, carried as null


def test_a_driver_without_the_feature_is_refused_in_one_line(server: zenoh.Session, endpoint: str,
                                                              client_session: zenoh.Session) -> None:
    with DriverNode(NoScanner("plain", world="lab"), server):
        with ZenohDriver("plain", connect=[endpoint], discover_s=5.0) as client:
            assert client.wait_ready(5.0)
            assert "scan" not in client.hello().result(5.0).served.features
            with pytest.raises(DriverError) as info:
                client.scan().result(5.0)
        assert (info.value.code, info.value.message) == (UNKNOWN_VERB, "scan: this driver has no scan feature "
                                                                       "(see its hello)")
        # and the node answers a client that asks anyway the same
        probe = Probe(client_session, "plain", 5.0)
        try:
            assert probe.refusal("scan", message({}), (UNKNOWN_VERB,)) == \
                "unknown_verb: scan: this driver has no scan feature (see its hello)"
        finally:
            probe.close()


# -- the wire format -----------------------------------------------------------------------

EXAMPLE = RangeScan(Pose(30.0, 30.0, 90.0), 12.5, (-90.0, 0.0, 90.0), (30.0, math.inf, 131.0), 0.5, 480.0)


def test_a_payload_validates_against_the_published_schema() -> None:
    body = json.loads(SCAN.encode_result(EXAMPLE))
    assert body == {"v": 1, "pose": {"x_in": 30.0, "y_in": 30.0, "heading_deg": 90.0}, "clock_s": 12.5,
                    "angles_deg": [-90.0, 0.0, 90.0], "ranges_in": [30.0, None, 131.0],
                    "range_min_in": 0.5, "range_max_in": 480.0}
    assert Draft202012Validator(SCHEMA).is_valid(body)
    assert SCAN.decode_result(json.dumps(body).encode()) == EXAMPLE
    assert not Draft202012Validator(SCHEMA).is_valid({**body, "ranges_in": [30.0, "far", 131.0]})


@pytest.mark.parametrize("change, error", [
    ({"angles_deg": [-90.0, 90.0, 0.0]}, "angles_deg[2]: 0.0 does not increase on the beam before it (90.0)"),
    ({"angles_deg": [-90.0, 0.0, 180.0]}, "angles_deg[2]: 180.0 outside [-180, 180) degrees"),
    ({"ranges_in": [30.0, None]}, "ranges_in: expected 3 items, got 2"),
    ({"ranges_in": [30.0, None, 500.0]}, "ranges_in[2]: 500.0 outside [0.5, 480.0]"),
    ({"ranges_in": [0.1, None, 131.0]}, "ranges_in[0]: 0.1 outside [0.5, 480.0]"),
    ({"range_max_in": 0.5}, "range_max_in: 0.5 is not above range_min_in 0.5"),
    ({"angles_deg": [], "ranges_in": []}, "angles_deg: expected 1 to 3600 beams, got 0"),
])
def test_the_codec_refuses_what_a_scan_cannot_be_naming_the_field(change: dict[str, object], error: str) -> None:
    body = {**json.loads(SCAN.encode_result(EXAMPLE)), **change}
    with pytest.raises(CodecError) as info:
        SCAN.decode_result(json.dumps(body).encode())
    assert str(info.value) == error


def test_a_driver_cannot_send_a_range_beyond_its_limits() -> None:
    with pytest.raises(CodecError, match=r"^ranges_in\[1\]: 600.0 outside \[0.5, 480.0\]$"):
        SCAN.encode_result(dataclasses.replace(EXAMPLE, ranges_in=(30.0, 600.0, 131.0)))


# -- conformance ------------------------------------------------------------------------------

@pytest.mark.parametrize("model", ["lidar", "sonar"])
@pytest.mark.parametrize("preset", ["paper", "harsh"])
def test_the_simulator_passes_the_scan_checks(model: str, preset: str, server: zenoh.Session,
                                              client_session: zenoh.Session) -> None:
    hero = SimulatedHero("sc", world="lab", seed=1, noise=NoiseConfig.preset(preset), profile=profile(model))
    results = scan_checks(hero, server, client_session)
    assert failed(results) == set(), results
    assert results["scan-repeat"].detail.startswith("standing still, ")
    assert results["scan-turn"].detail.startswith("after a ")


@pytest.mark.parametrize("preset", ["clean", "paper"])
def test_the_swept_sonar_drives_at_a_wall_in_an_empty_room(preset: str, server: zenoh.Session,
                                                             client_session: zenoh.Session) -> None:
    """In the lab's clutter the sonar's 15 deg beams cannot tell a wall from an object, so
    scan-drive is "not checked" there; in an empty room 240 x 180 from (120, 90), after the
    turn check faces +y, the walls 90 in ahead and behind are met square on within its
    127 in reach and the drive is checked."""
    spec = world(240, 180, (120, 90, 0)).spec
    hero = SimulatedHero("es", world=spec, seed=3, noise=NoiseConfig.preset(preset), profile=profile("sonar"))
    results = scan_checks(hero, server, client_session)
    assert failed(results) == set(), results
    assert results["scan-drive"].detail.startswith("driving "), results["scan-drive"].detail


def test_a_driver_without_the_feature_is_not_checked(server: zenoh.Session, client_session: zenoh.Session) -> None:
    results = scan_checks(NoScanner("ns", world="lab"), server, client_session)
    assert failed(results) == set()
    assert {r.detail for r in results.values()} == {"not checked: the driver does not offer the scan feature"}


def test_ranges_in_centimetres_fail_the_drive(server: zenoh.Session, client_session: zenoh.Session) -> None:
    """The room read 2.54 times too large is self-consistent standing or turning; a
    36 in drive at a wall shortens the range ahead by 91 "inches"."""
    results = scan_checks(RangesInCentimetres("cm", world="lab", noise=NoiseConfig.off()), server, client_session)
    assert failed(results) == {"scan-drive"}
    detail = results["scan-drive"].detail
    assert "\n" not in detail
    assert detail.startswith("driving 36.0 in straight at a wall took the range ahead from ")
    assert "(by 91.4, expected 36.0 within " in detail and detail.endswith("ranges are inches from the base centre")


def test_a_scan_in_the_world_frame_fails_the_turn(server: zenoh.Session, client_session: zenoh.Session) -> None:
    results = scan_checks(ScanInTheWorldFrame("world", world="lab", noise=NoiseConfig.off()), server, client_session)
    assert "scan-turn" in failed(results)
    detail = results["scan-turn"].detail
    assert "\n" not in detail and detail.startswith("after a 90 deg turn in place, ")
    assert detail.endswith("angles are counter-clockwise from the robot's heading, in degrees")


def test_angles_in_radians_fail_the_scan(server: zenoh.Session, client_session: zenoh.Session) -> None:
    results = scan_checks(AnglesInRadians("rad", world="lab", noise=NoiseConfig.off()), server, client_session)
    assert failed(results) == {"scan", "scan-repeat", "scan-turn", "scan-drive"}
    assert results["scan"].detail == ("the beams span 6.26573 deg, from -3.14159 to 3.12414: a scan covers at least "
                                      "180 deg, its angles in degrees (not radians)")


def test_a_clock_in_milliseconds_fails_the_scan(server: zenoh.Session, client_session: zenoh.Session) -> None:
    results = scan_checks(ClockInMilliseconds("ms", world="lab", noise=NoiseConfig.off()), server, client_session)
    assert failed(results) == {"scan", "scan-repeat", "scan-turn", "scan-drive"}  # the others need the first
    assert results["scan"].detail.startswith("the scan's clock_s 200 is not between the clocks published before")
    assert results["scan-repeat"].detail == "needs the scan check to pass"


def test_the_whole_suite_names_only_the_scan_check_a_mutant_breaks(server: zenoh.Session, endpoint: str) -> None:
    with DriverNode(RangesInCentimetres("cmx", world="lab"), server):
        results = {r.name: r for r in run_checks("cmx", [endpoint], timeout_s=5.0,
                                                 procedures=Procedures.from_profile())}
    assert failed(results) == {"scan-drive"}
    assert results["scan"].passed and results["scan"].detail.endswith("at the published pose")


@pytest.mark.parametrize("model", ["lidar", "sonar"])
def test_a_wall_is_chosen_where_it_is_met_square_on(model: str) -> None:
    """Room 200 x 100, robot at (50, 40) facing +y: the walls are met square on 60 ahead,
    150 to the right (-90; beyond the sonar's 127 in reach), 50 behind and 40 to the
    left; the farthest with the room asked for is chosen, and the range ahead is the wall
    60 away. The sonar's beams at -15, 0 and 15 all hold the wall's normal in their
    30 deg cones, so all three read it square on: the middle one, whose neighbours read
    alike, is taken."""
    scan = world(200, 100, (50, 40, 90), model=model).scan()
    assert square_wall(scan, 55.0) == (-90.0 if model == "lidar" else 0.0)
    assert square_wall(scan, 76.0) == (-90.0 if model == "lidar" else None)
    assert square_wall(scan, 160.0) is None
    assert toward(scan, 90.0) == pytest.approx(60.0)  # the wall ahead, at world heading 90
    assert toward(scan, 0.0) == (pytest.approx(150.0) if model == "lidar" else math.inf)
