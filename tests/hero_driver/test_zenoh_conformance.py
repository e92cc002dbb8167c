"""``csl driver check``: passes against the simulated HERO, and against broken driver
processes fails exactly the checks that name what they break."""

from __future__ import annotations

import re
from collections.abc import Sequence

import pytest

from csl_cli.main import main
from hero_driver.zenoh_link import conformance
from hero_driver.zenoh_link.checking import CheckResult
from hero_driver.zenoh_link.conformance import Procedures, known_world
from hero_driver.zenoh_link.verbs import NAMES
from robot_profile import DEFAULT_PROFILE, load_profile, profile_stamp
from tests.hero_driver.test_zenoh_support import REPO, DriverProcess
from tests.zenoh_rpc.support import free_endpoint
from zenoh_rpc.config import open_session

pytestmark = pytest.mark.zenoh

ALL_CHECKS = {
    "liveliness", "state-published", "noop", "hello", "profile", "reset", "reset-objects", "camera",
    "camera-mapping", "move", "state-after-move", "busy", "turns", "durations", "busy-release", "sense", "grasp", "release", "charge", "blocked-moves",
    "scan", "scan-repeat", "scan-turn", "scan-drive", "out-of-range-target",
    "unknown-verb",
    "unknown-procedure", "malformed-json", "not-utf8", "not-an-object", "every-verb", "wildcard-silence", "wrong-types",
    "missing-field", "unknown-field", "non-finite-number", "wrong-version", "keeps-serving",
}
ROVER = REPO / "hero_driver" / "profiles" / "rover.toml"
# The busy check turns from the move check's pose, which turns from a published state.
BUSY_CHECKS = ("state-published", "move", "busy")


def run_named_checks(robot: str, endpoint: str, names: Sequence[str], **options: object) -> dict[str, CheckResult]:
    """The ``names`` checks of ``run_checks``, in the suite's order, the others left out.

    Why: a driver whose moves take real time (a slow turn, the template's toy robot)
    spends them on every move of the whole suite, while a test of one check needs only
    it and the checks it builds on. Going through ``run_checks`` keeps its own steps (the
    token awaited, the profile compared), and every name must be one the suite has, so
    a renamed check fails here instead of leaving nothing checked."""
    whole = conformance._Suite.checks
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(conformance._Suite, "checks",
                      lambda suite: [(name, check) for name, check in whole(suite) if name in names])
        results = conformance.run_checks(robot, [endpoint], **options)  # type: ignore[arg-type]
    assert [r.name for r in results] == list(names), [(r.name, r.detail) for r in results]
    return {r.name: r for r in results}


def run_check(endpoint: str, robot: str, capsys: pytest.CaptureFixture[str],
              timeout_s: float = 10.0, *extra: str) -> tuple[int, dict[str, str]]:
    """Exit status and each named check's PASS/FAIL from the printed table."""
    status, verdicts, _details = run_check_detailed(endpoint, robot, capsys, timeout_s, *extra)
    return status, verdicts


def run_check_detailed(endpoint: str, robot: str, capsys: pytest.CaptureFixture[str], timeout_s: float = 10.0,
                       *extra: str) -> tuple[int, dict[str, str], dict[str, str]]:
    """Exit status, each named check's PASS/FAIL and its detail, from the printed table."""
    status = main(["driver", "check", "--robot", robot, "--connect", endpoint,
                   "--timeout", str(timeout_s), *extra])
    table = capsys.readouterr().out
    rows = re.findall(r"^(\S+)\s+(PASS|FAIL)\s+(.*)$", table, re.MULTILINE)
    return status, {name: verdict for name, verdict, _ in rows}, {name: detail for name, _, detail in rows}


def failed(verdicts: dict[str, str]) -> set[str]:
    return {name for name, verdict in verdicts.items() if verdict == "FAIL"}


@pytest.mark.slow
def test_the_simulated_hero_passes_every_check(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="conf") as process:
        process.ready()
        status, verdicts, details = run_check_detailed(endpoint, "conf", capsys)
    assert set(verdicts) == ALL_CHECKS
    assert failed(verdicts) == set()
    assert status == 0
    hero = profile_stamp(load_profile(DEFAULT_PROFILE))
    assert details["profile"] == f"serves hero2000 (sha256 {hero.sha256[:12]}), as given"
    # the lab's seven objects, each drawn within a pixel or so of its place
    assert details["reset-objects"].startswith("world 'lab': 7 objects drawn where reset placed them")
    # the lab's dock is at (24, 85), 55 in from the reset pose (30, 30): out of the beacon's 24 in reach
    assert details["charge"].startswith("out_of_range away from the dock: charge: the base is 55.3 in from the dock")
    # the node reads a request before it looks at features: every verb of the table refuses the array
    assert details["every-verb"] == f"{len(NAMES)} verbs refuse a JSON array bad_request: {', '.join(NAMES)}"


@pytest.mark.slow
def test_a_broken_driver_fails_the_checks_it_breaks(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("broken", endpoint, robot="broken") as process:
        process.ready()
        status, verdicts = run_check(endpoint, "broken", capsys)
    # Text feature values (from a sonar that never refuses, so nothing is out of
    # range either), a crash on an unknown procedure, a clock that survives reset,
    # and (as every FakeHero) an image without the robot in it.
    # and a reset that accepts the world 'lab' but restores none of it; the robot not
    # drawn, the turns cannot be seen either, and the durations check's sense meets the
    # same text values.
    assert failed(verdicts) == {"sense", "out-of-range-target", "unknown-procedure", "reset", "camera-mapping",
                                "reset-objects", "turns", "durations"}
    assert status == 1


@pytest.mark.slow
def test_a_driver_without_token_or_state_fails_those_checks(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.fake("tokenless", endpoint, robot="bare") as process:
        process.ready()
        status, verdicts = run_check(endpoint, "bare", capsys, timeout_s=2.0)
    assert {"liveliness", "state-published", "reset", "unknown-verb"} <= failed(verdicts)
    assert verdicts["noop"] == "PASS"
    assert status == 1


def test_a_driver_of_another_robot_profile_stops_the_suite_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with DriverProcess.sim(endpoint, robot="hero") as process:
        process.ready()
        status, verdicts, details = run_check_detailed(endpoint, "hero", capsys, 10.0, "--profile", str(ROVER))
    hero, rover = (profile_stamp(load_profile(path)) for path in (DEFAULT_PROFILE, ROVER))
    assert verdicts == {"profile": "FAIL"}
    assert details["profile"] == (f"the driver serves robot profile hero2000 (sha256 {hero.sha256[:12]}), not rover "
                                  f"(sha256 {rover.sha256[:12]}) as given: check it with its own profile "
                                  "(--profile FILE)")
    assert status == 1


@pytest.mark.slow
def test_a_driver_of_the_given_profile_passes_with_its_procedures(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    argv = ["-m", "csl_cli", "driver", "sim", "--robot", "rover", "--listen", endpoint, "--profile", str(ROVER)]
    with DriverProcess(argv) as process:
        process.ready()
        status, verdicts, details = run_check_detailed(endpoint, "rover", capsys, 10.0, "--profile", str(ROVER))
    assert failed(verdicts) == set()
    assert details["profile"].startswith("serves rover (sha256 ")
    assert status == 0


def test_the_known_world_is_read_from_the_shipped_lab_file() -> None:
    start, placed = known_world()
    assert (start.x_in, start.y_in, start.heading_deg) == (30.0, 30.0, 0.0)  # hero_driver/worlds/lab.json
    assert len(placed) == 7
    box = placed[0]
    assert (box.name, box.x_in, box.y_in, box.area_in2) == ("closed-box-2x2x2/upright", 70.0, 60.0, 4.0)
    assert placed[1].area_in2 == pytest.approx(3.14159 * 1.35**2, rel=1e-4)  # an upright bottle, r 1.35 in


def test_procedures_come_from_the_knowledge_profile() -> None:
    chosen = Procedures.from_profile()
    assert chosen.sense == "V-Sweep-5°"  # the cheapest of the long-range sweeps
    assert chosen.near in {"S-Sweep-1°", "H-Scan-0.3", "D-Scan-0.3"}
    assert chosen.grasp == "Front-Pinch"


@pytest.mark.parametrize("argv", [
    ["driver", "check", "--timeout", "0"],
    ["driver", "check", "--robot", "r/1"],
    ["driver", "check", "--connect", "localhost"],
    ["driver", "sim", "--robot", "r*"],
    ["driver", "sim", "--listen", "nowhere"],
    ["driver", "sim", "--listen", "udpx/127.0.0.1:1"],
    ["driver", "sim", "--world", "no-such-world", "--listen", "udpx/127.0.0.1:1"],
])
def test_bad_arguments_exit_2_with_one_line(argv: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    assert main(argv) == 2
    err = capsys.readouterr().err
    # "csl: error: ..." from the command, or argparse's "csl driver sim: error: argument ...": one line either way
    assert re.match(r"csl( driver \w+)?: error: ", err) and err.count("\n") == 1, err


def test_a_taken_port_exits_2(capsys: pytest.CaptureFixture[str]) -> None:
    endpoint = free_endpoint()
    with open_session(listen=[endpoint]):
        assert main(["driver", "sim", "--listen", endpoint]) == 2
    assert "Address already in use" in capsys.readouterr().err


def _documented_bands() -> dict[str, tuple[int, int, int]]:
    """docs/driver-protocol.md's grey-level table: what -> (level rendered, band lo, band hi)."""
    text = (REPO / "docs" / "driver-protocol.md").read_text(encoding="utf-8")
    rows = re.findall(r"^\| ([^|]+?) \| (\d+) \| (\d+)-(\d+) \|$", text, re.MULTILINE)
    keys = {"floor": "floor", "walls": "walls", "robot's base": "base", "heading marker": "marker",
            "object's footprint": "object"}
    table = {}
    for what, level, lo, hi in rows:
        (key,) = [name for word, name in keys.items() if word in what]
        table[key] = (int(level), int(lo), int(hi))
    assert set(table) == set(keys.values())
    return table


def test_the_published_grey_bands_are_the_protocol_pages() -> None:
    """One leaf module holds the bands the simulator draws, the suite checks and the
    vision reads (camera_model.bands); it says what the protocol page says."""
    from camera_model import bands

    table = _documented_bands()
    assert {"floor": bands.FLOOR_BAND, "walls": bands.WALL_BAND, "base": bands.ROBOT_BAND,
            "marker": bands.MARKER_BAND, "object": bands.OBJECT_BAND} == {k: v[1:] for k, v in table.items()}
    rendered = (bands.FLOOR, bands.WALL, bands.BASE, bands.MARKER, bands.OBJECT)
    assert rendered == tuple(table[key][0] for key in ("floor", "walls", "base", "marker", "object"))
    # the bands tile 0-255 in order, each rendered level inside its own band
    ordered = sorted(table.values(), key=lambda row: row[1])
    assert [row[1] for row in ordered] == [0] + [row[2] + 1 for row in ordered[:-1]]
    assert ordered[-1][2] == 255
    assert all(lo <= level <= hi for level, lo, hi in ordered)
    # the protocol's pixel noise never moves a level out of its band
    noise = bands.PIXEL_NOISE_MAX
    assert all(lo <= level - noise and min(level + noise, 255) <= hi for level, lo, hi in ordered)


@pytest.mark.slow
def test_a_realistic_camera_is_checked_through_its_calibration(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    """A real-looking camera (no grey bands) passes with its calibration, read by the
    executive's vision; without one its image checks say why they were not run."""
    endpoint = free_endpoint()
    calibration = tmp_path / "rz.json"
    argv = ["-m", "csl_cli", "driver", "sim", "--camera", "realistic", "--robot", "rz", "--listen", endpoint]
    with DriverProcess(argv) as process:
        process.ready()
        status, verdicts, details = run_check_detailed(endpoint, "rz", capsys)
        assert (status, failed(verdicts)) == (0, set())
        needs = ("not checked: the image is not drawn in the grey bands (a real camera's?): needs "
                 "--camera-calibration FILE (csl camera calibrate, docs/camera.md)")
        assert details["camera-mapping"] == details["reset-objects"] == needs
        assert main(["camera", "calibrate", "--robot", "rz", "--connect", endpoint, "--out", str(calibration)]) == 0
        capsys.readouterr()
        status, verdicts, details = run_check_detailed(endpoint, "rz", capsys, 10.0,
                                                       "--camera-calibration", str(calibration))
    assert set(verdicts) == ALL_CHECKS
    assert (status, failed(verdicts)) == (0, set())
    # the reset pose (30, 30, 0) and the lab's seven objects, each within the half inch
    # the vision is measured to on this preset (BENCHMARKS.md)
    mapping = re.fullmatch(r"robot seen through the calibration at \((\S+), (\S+)\) heading (-?\d+) deg, (\S+) in "
                           r"from the published pose", details["camera-mapping"])
    assert mapping is not None, details["camera-mapping"]
    assert float(mapping[4]) <= 0.5 and abs(int(mapping[3])) <= 3
    objects = re.fullmatch(r"world 'lab': 7 objects seen through the calibration where reset placed them, the "
                           r"farthest (\S+) in off", details["reset-objects"])
    assert objects is not None, details["reset-objects"]
    assert float(objects[1]) <= 0.5


def test_a_bad_calibration_file_is_one_line_exit_2(tmp_path, capsys: pytest.CaptureFixture[str]) -> None:
    (tmp_path / "cam.json").write_text('{"format": 1}')
    status = main(["driver", "check", "--connect", free_endpoint(), "--camera-calibration", str(tmp_path / "cam.json")])
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert err == f"csl: error: --camera-calibration: {tmp_path / 'cam.json'}: floor: expected an object"
