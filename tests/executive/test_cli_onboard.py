"""``--perception onboard`` through the real command line: the
tree with its exploration branch, the small home to try it in, the one-line refusals
(a home with the ceiling camera's perception, the camera's options with onboard, a
driver without scans), an episode that writes the built map beside the true one and
says what the exploration cost, and an exit status that counts the objects of the home
the robot never found."""

from __future__ import annotations

import json
import math
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from csl_cli import args as cli_args
from csl_cli.demo_library import training_key
from csl_cli.main import main
from csl_cli.onboard import Exploration, exploration, judged, never_found, still_there, still_there_line
from executive import executive
from executive.exit_status import ALL_HANDLED, LOST, SOME_FAILED
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.truth_map import truth_map
from hero_driver.sim.worldfile import load_world
from hero_driver.sim_driver import SimulatedHero
from mapping import OccupancyGrid, PlanarScan
from reporting.built_map import plot_built_map
from reporting.report import Truth
from robot_profile import load_profile, profile_stamp
from tests.hero_driver.test_sim_apartment import reachable_cells

PROFILE, CATALOGUE = profile_and_catalogue(None)
ESCAPE = re.compile(r"\x1b\[[0-9;]*m")
EXPLORATION_BRANCH = ["-^- explore the home", "    {-} look further", "        --> LookAround",
                      "        --> MoreToSee?", "        --> GoToView"]

# Two rooms with no door between them: the robot maps its own room and handles the
# tumbler there; the box beyond the wall is never seen.
CLOSED = {"name": "closed", "room": {"width_in": 160, "depth_in": 72}, "ceiling_camera": False,
          "walls": [{"from": [100, 0], "to": [100, 72], "thickness_in": 4}],
          "robot": {"x_in": 25, "y_in": 36, "heading_deg": 0},
          "objects": [{"id": "tumbler-20oz/lying", "x_in": 70, "y_in": 36, "yaw_deg": 90},
                      {"id": "closed-box-10x10x10/upright", "x_in": 135, "y_in": 36, "yaw_deg": 0}]}


def _closed_world(tmp_path: Path) -> Path:
    path = tmp_path / "closed.json"
    path.write_text(json.dumps(CLOSED), encoding="utf-8")
    return path


def _lines(text: str) -> list[str]:
    return [line for line in ESCAPE.sub("", text).splitlines() if line.strip()]


# ---------------------------------------------------------------- the tree


def test_the_perception_choices_are_the_executives() -> None:
    assert cli_args.PERCEPTIONS == executive.PERCEPTIONS
    assert (cli_args.CEILING, cli_args.ONBOARD) == (executive.CEILING, executive.ONBOARD)


def test_onboard_tree_shape(csl_snapshot, capsys: pytest.CaptureFixture[str]) -> None:  # noqa: ANN001
    assert main(["bt", "--perception", "onboard"]) == 0
    assert ESCAPE.sub("", capsys.readouterr().out) == csl_snapshot


def test_the_onboard_tree_is_the_ceiling_tree_with_the_exploration_branch_before_locating(
        capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["bt"]) == 0
    ceiling = _lines(capsys.readouterr().out)
    assert main(["bt", "--perception", "onboard"]) == 0
    onboard = _lines(capsys.readouterr().out)
    at = next(i for i, line in enumerate(onboard) if line.strip() == "-^- explore the home")
    indent = onboard[at][:len(onboard[at]) - len(onboard[at].lstrip())]
    assert onboard[at:at + 5] == [indent + line for line in EXPLORATION_BRANCH]
    assert onboard[at + 5].strip() == "--> LocateObjects"
    assert onboard[:at] + onboard[at + 5:] == ceiling


# ---------------------------------------------------------------- the small home


def test_the_small_home_has_two_rooms_no_camera_and_objects_the_robot_can_reach() -> None:
    home = load_world("two-rooms", CATALOGUE)
    assert [r.name for r in home.home.rooms] == ["front room", "back room"]
    assert not home.home.ceiling_camera and 3 <= len(home.objects) <= 4
    assert {home.home.room_at(p.x_in, p.y_in) for p in home.objects} == {"front room", "back room"}
    assert [len(w.doors) for w in home.home.walls] == [1]
    reach, grid = reachable_cells(home)
    for p in home.objects:  # a base centre within 30 in of each object can get there
        near = [grid.cell_of(p.x_in + 30 * math.cos(a), p.y_in + 30 * math.sin(a))
                for a in np.radians(np.arange(0, 360, 15))]
        assert any(0 <= r < reach.shape[0] and 0 <= c < reach.shape[1] and reach[r, c] for r, c in near), p.entry_id


# ---------------------------------------------------------------- refusals, each one line


def test_a_home_with_the_ceiling_cameras_perception_is_refused_before_training(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    assert main(["demo", "--world", "two-rooms", "--out", str(out)]) == 2
    captured = capsys.readouterr()
    assert _lines(captured.err) == ["csl: error: world 'two-rooms' has no ceiling camera: add --perception onboard "
                                    "(the robot explores it with its own range scans)"]
    assert "training" not in captured.err and not out.exists()  # nothing trained, nothing left behind


@pytest.mark.parametrize(("given", "flag"), [(["--appearance"], "--appearance"),
                                             (["--camera", "realistic"], "--camera"),
                                             (["--camera-calibration", "cal.json"], "--camera-calibration")])
def test_the_overhead_cameras_options_are_refused_with_onboard(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                               given: list[str], flag: str) -> None:
    assert main(["run", "--perception", "onboard", *given, "--out", str(tmp_path / "out"),
                 "--library", str(tmp_path / "lib.sqlite")]) == 2
    err = _lines(capsys.readouterr().err)
    assert len(err) == 1 and err[0].startswith(f"csl: error: {flag} is the overhead camera's and goes with "
                                               "--perception ceiling")
    assert not (tmp_path / "out").exists() and not (tmp_path / "lib.sqlite").exists()


# ---------------------------------------------------------------- what a run says and writes


def test_an_object_of_the_home_never_found_fails_the_run_in_one_line(tmp_path: Path,
                                                                      capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "out"
    status = main(["run", "--world", str(_closed_world(tmp_path)), "--noise", "clean", "--perception", "onboard",
                   "--out", str(out), "--library", str(tmp_path / "lib.sqlite")])
    captured = capsys.readouterr()
    assert status == SOME_FAILED
    err, lines = _lines(captured.err), _lines(captured.out)
    assert "csl: 1 of 2 objects the simulator placed was never found: closed-box-10x10x10/upright at (135, 36)" in err
    assert lines[-1] == "exit status 1: 1 of 2 objects the simulator placed was never found"
    assert re.fullmatch(r"exploration: the home is mapped after \d+ views?, \d+\.\d robot min; 1 object candidate "
                        r"found", next(line for line in lines if line.startswith("exploration:")))
    events = [json.loads(line) for line in (out / "episode.jsonl").read_text().splitlines()]
    mapped = [e for e in events if e["event"] == "mapped"]
    assert len(mapped) == 1 and mapped[0]["reason"] == "the home is mapped"
    assert [e["object"] for e in events if e["event"] == "object"] == [0]
    built = cv2.imread(str(out / "map.png"))
    assert built is not None and built.shape[1] > 2 * built.shape[0]  # two panels: built beside true
    assert (out / "behaviour-tree.png").exists() and (out / "tree-0.png").exists()


@pytest.mark.slow
def test_csl_demo_in_the_small_home_finds_every_object_and_exits_by_their_outcomes(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "home"
    status = main(["demo", "--world", "two-rooms", "--perception", "onboard", "--noise", "clean", "--out", str(out),
                   "--json"])
    document = json.loads(capsys.readouterr().out)
    assert document["never_found"] == []  # every object the world holds was found...
    names = sorted(o["object"] for o in document["objects"])
    assert names == sorted(p.entry_id for p in load_world("two-rooms", CATALOGUE).objects)  # ...once each
    handled = all(o["outcome"] in ("grasped", "left", "gone") for o in document["objects"])
    assert status == document["exit_status"] == (ALL_HANDLED if handled else SOME_FAILED)
    assert document["exploration"]["reason"] == "the home is mapped"
    assert document["exploration"]["candidates"] >= 4 and document["exploration"]["robot_s"] > 0
    assert (out / "map.png").exists() and (out / "episode.jsonl").exists() and (out / "library.sqlite").exists()


# ---------------------------------------------------------------- over zenoh


class NoScanner(SimulatedHero):
    """A driver from before the scan feature."""

    scan = None  # type: ignore[assignment]


@contextmanager
def served(driver: SimulatedHero) -> Iterator[str]:
    """``driver`` served over zenoh on a free loopback endpoint, for ``csl run --connect``."""
    from hero_driver.zenoh_link.node import DriverNode
    from tests.zenoh_rpc.support import free_endpoint
    from zenoh_rpc.config import open_session

    endpoint = free_endpoint()
    with open_session(listen=[endpoint]) as session, \
            DriverNode(driver, session, profile=profile_stamp(load_profile())):
        yield endpoint


@pytest.mark.zenoh
def test_run_onboard_refuses_a_driver_without_scans_in_one_line(tmp_path: Path,
                                                                capsys: pytest.CaptureFixture[str]) -> None:
    with served(NoScanner("plain", world="lab")) as endpoint:
        status = main(["run", "--driver", "zenoh", "--robot", "plain", "--connect", endpoint, "--perception",
                       "onboard", "--out", str(tmp_path / "out"), "--library", str(tmp_path / "lib.sqlite")])
    assert status == 2
    assert _lines(capsys.readouterr().err)[-1] == (
        "csl: error: --perception onboard: driver plain offers no range scans (no scan feature in its hello; "
        "docs/driver-protocol.md, Scans): run it with --perception ceiling, or drive a robot that scans")
    assert not (tmp_path / "out").exists()


@pytest.mark.zenoh
def test_run_with_the_ceiling_camera_against_a_home_says_to_add_onboard(tmp_path: Path,
                                                                         capsys: pytest.CaptureFixture[str]) -> None:
    with served(SimulatedHero("home", world="two-rooms")) as endpoint:
        status = main(["run", "--driver", "zenoh", "--robot", "home", "--connect", endpoint,
                       "--out", str(tmp_path / "out"), "--library", str(tmp_path / "lib.sqlite")])
    assert status == 2
    assert _lines(capsys.readouterr().err)[-1] == ("csl: error: driver home's robot has no ceiling camera: add "
                                                   "--perception onboard (the robot explores it with its own range "
                                                   "scans)")


@pytest.mark.zenoh
def test_run_onboard_drives_a_driver_that_offers_scans(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """Over zenoh the run knows no truth: the built map is drawn alone, and what it
    found is all it can judge (the tumbler, handled: exit 0)."""
    from hero_driver.zenoh_link.node import DriverNode
    from tests.zenoh_rpc.support import free_endpoint
    from zenoh_rpc.config import open_session

    endpoint, out = free_endpoint(), tmp_path / "out"
    hero = SimulatedHero("scanner", world=_closed_world(tmp_path), noise=NoiseConfig.off())
    with open_session(listen=[endpoint]) as session, DriverNode(hero, session, profile=profile_stamp(load_profile())):
        status = main(["run", "--driver", "zenoh", "--robot", "scanner", "--connect", endpoint, "--perception",
                       "onboard", "--out", str(out), "--library", str(tmp_path / "lib.sqlite")])
    captured = capsys.readouterr()
    assert status == ALL_HANDLED, captured.err
    assert "never found" not in captured.err
    assert any(line.startswith("exploration: the home is mapped") for line in _lines(captured.out))
    built = cv2.imread(str(out / "map.png"))
    assert built is not None and built.shape[1] < 2 * built.shape[0]  # one panel: no true map to set beside it


# ---------------------------------------------------------------- the pieces, by hand


def test_the_exploration_is_read_from_the_mapped_event() -> None:
    events = [{"event": "view", "candidates": 1}, {"event": "explore_move"}, {"event": "view", "candidates": 3},
              {"event": "mapped", "views": 2, "seconds": 150.0, "candidates": 3, "reason": "the home is mapped"},
              {"event": "object", "object": 0}]
    found = exploration(events)
    assert found == Exploration(views=2, robot_s=150.0, reason="the home is mapped", candidates=3)
    assert found.line() == "exploration: the home is mapped after 2 views, 2.5 robot min; 3 object candidates found"
    assert exploration(events[:3]) is None  # never ended


def _record(x: float, y: float) -> SimpleNamespace:
    return SimpleNamespace(first_region=SimpleNamespace(centroid=(x, y)), region=None)


def test_an_object_counts_as_found_only_when_a_located_one_is_nearest_and_near_it() -> None:
    cup, box, can = (Truth("cup", ("Top-Pinch",), 10.0, 10.0), Truth("box", ("No-Grab",), 100.0, 10.0),
                     Truth("can", ("Front-Pinch",), 100.0, 60.0))
    # one at the cup, two at the box (a candidate split in two), one 30 in from the can
    records = [_record(11.0, 9.0), _record(100.0, 12.0), _record(102.0, 10.0), _record(100.0, 30.0)]
    assert never_found(records, [cup, box, can]) == [can]  # (100, 30) is nearest the box (20 in) but not near it
    assert never_found([], [cup]) == [cup] and never_found(records, []) == []
    assert judged(ALL_HANDLED, "all 4 objects were handled", [can], [cup, box, can]) == (
        SOME_FAILED, "1 of 3 objects the simulator placed was never found")
    assert judged(SOME_FAILED, "1 of 4 objects were not handled", [can, box], [cup, box, can]) == (
        SOME_FAILED, "1 of 4 objects were not handled; 2 of 3 objects the simulator placed were never found")
    assert judged(LOST, "2 driver faults", [], [cup]) == (LOST, "2 driver faults")


def test_an_object_reported_gone_that_never_left_the_floor_fails_the_run() -> None:
    """Three records reported ``gone``: the cup's is still where the robot last saw it
    (2 in away): the scans saw past it, and the run fails (exit 1) with one line naming
    it. The box was really taken (now 200 in away), the can left the floor (held or put
    away: None); neither is held against the run, nor is a record not reported gone."""
    cup, box, can = (Truth("cup", ("Top-Pinch",), 10.0, 10.0), Truth("box", ("No-Grab",), 100.0, 10.0),
                     Truth("can", ("Front-Pinch",), 100.0, 60.0))

    def gone(x: float, y: float, outcome: str = "gone") -> SimpleNamespace:
        seen = SimpleNamespace(centroid=(x, y))
        return SimpleNamespace(first_region=seen, region=seen, outcome=outcome)

    records = [gone(11.0, 9.0), gone(100.0, 12.0), gone(100.0, 61.0), gone(12.0, 10.0, "grasped")]
    on_floor = [(12.0, 10.0), (300.0, 10.0), None]
    assert still_there(records, [cup, box, can], on_floor) == [cup]
    assert still_there(records, [cup, box, can], []) == []  # not the simulator: nothing to check against
    assert judged(ALL_HANDLED, "all 4 objects were handled", [], [cup, box, can], [cup]) == (
        SOME_FAILED, "1 reported gone was still on the floor")
    assert judged(ALL_HANDLED, "w", [can], [cup, box, can], [cup]) == (
        SOME_FAILED, "1 of 3 objects the simulator placed was never found; 1 reported gone was still on the floor")
    assert still_there_line([cup]) == ("csl: 1 object reported gone was still on the floor where the robot last "
                                       "saw them (its scans saw past them): cup at (10, 10)")


def test_the_built_map_is_drawn_beside_the_truth_or_alone(tmp_path: Path) -> None:
    home = load_world("two-rooms", CATALOGUE)
    truth = truth_map(home, CATALOGUE, 2.0)
    grid = OccupancyGrid(-20.0, -20.0, 260.0, 140.0, 2.0)
    angles = np.radians(np.arange(-180.0, 180.0, 2.0))
    grid.integrate(PlanarScan(angles, np.full(angles.shape, 25.0), 30.0, 60.0, 0.0, 0.0, 400.0))
    plot_built_map(tmp_path / "both.png", grid, truth, route=[(30.0, 60.0)])
    plot_built_map(tmp_path / "alone.png", grid)
    both, alone = cv2.imread(str(tmp_path / "both.png")), cv2.imread(str(tmp_path / "alone.png"))
    assert both.shape[1] > alone.shape[1] + 400  # a second panel, 6.5 in at 110 dpi
    assert (both.shape[1] - alone.shape[1]) == pytest.approx(6.5 * 110, abs=2)


def test_an_onboard_demos_training_is_kept_apart_and_a_ceiling_demos_is_unchanged() -> None:
    profile = load_profile()
    ceiling = training_key(profile, "two-rooms", 0)
    assert training_key(profile, "two-rooms", 0, perception="ceiling") == ceiling
    assert training_key(profile, "two-rooms", 0, perception="onboard") != ceiling
