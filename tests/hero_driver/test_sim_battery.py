"""The simulated battery (hero_driver.sim.battery): drained by robot time at the
documented rates, empty refuses the robot's verbs, charged only at the dock; the world
file's ``dock`` and ``battery`` keys."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from hero_driver.interface import BATTERY_EMPTY, OUT_OF_RANGE, DriverError, Pose
from hero_driver.sim.battery import (CHARGING_PER_S, GRASPING_PER_S, MOVING_PER_S, SENSING_PER_S, Battery, Dock)
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.odometry import Drift
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.world import SimWorld
from hero_driver.sim.worldfile import load_world, parse_world

ROOM = {"width_in": 120, "depth_in": 100}


def world(tmp_path: Path, **extra: object) -> SimWorld:
    data = {"name": "battery", "room": ROOM, "robot": {"x_in": 20, "y_in": 20, "heading_deg": 0},
            "objects": [{"id": "closed-box-10x10x10/upright", "x_in": 80, "y_in": 20}], **extra}
    path = tmp_path / "battery.json"
    path.write_text(json.dumps(data), encoding="utf-8")
    return SimWorld(path, seed=0, noise=NoiseConfig.preset("clean"))


def test_the_documented_rates() -> None:
    # docs/simulator.md, Battery: 5 h of driving, 10 h of sensing, 3 h 20 min of grasping,
    # 30 min from empty to full at the dock
    assert (1 / MOVING_PER_S, 1 / SENSING_PER_S, 1 / GRASPING_PER_S, 1 / CHARGING_PER_S) == \
        pytest.approx((5 * 3600, 10 * 3600, 3 * 3600 + 20 * 60, 30 * 60))


def test_a_move_drains_its_seconds_at_the_moving_rate(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.5)
    # 20 in straight ahead at 0.5 in/s, no turn, plus 5 s of vision: 45 s
    result = sim.move([Pose(40.0, 20.0, 0.0)], None)
    assert result.duration_s == pytest.approx(45.0)
    assert sim.state().battery == pytest.approx(0.5 - 45.0 / 18000.0)


def test_sensing_and_grasping_drain_at_their_rates(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.5)
    sim.move([Pose(58.0, 20.0, 0.0)], (80.0, 20.0))  # the sonar 6 in from the box
    after_move = sim.state().battery
    sensed = sim.sense("H-Sweep-5°")
    assert sim.state().battery == pytest.approx(after_move - sensed.duration_s / 36000.0)
    before = sim.state().battery
    grasped = sim.grasp("Front-Pinch")
    assert sim.state().battery == pytest.approx(before - grasped.duration_s / 12000.0)


def test_an_empty_battery_refuses_moving_sensing_and_grasping_but_not_the_camera(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.0)
    for verb, call in (("move", lambda: sim.move([Pose(40.0, 20.0, 0.0)], None)),
                       ("sense", lambda: sim.sense("H-Sweep-5°")), ("grasp", lambda: sim.grasp("Front-Pinch"))):
        with pytest.raises(DriverError, match=f"{verb}: the battery is empty") as caught:
            call()
        assert caught.value.code == BATTERY_EMPTY
    assert sim.state().clock_s == 0.0
    sim.camera()


def test_the_verb_that_empties_the_battery_finishes_and_the_next_is_refused(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.001)  # 18 s of driving left; the move takes 45 s
    sim.move([Pose(40.0, 20.0, 0.0)], None)
    assert sim.state().battery == 0.0 and sim.state().pose.x_in == pytest.approx(40.0)
    with pytest.raises(DriverError) as caught:
        sim.move([Pose(20.0, 20.0, 0.0)], None)
    assert caught.value.code == BATTERY_EMPTY


def test_charging_at_the_dock_fills_the_battery_in_robot_time(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.5, dock={"x_in": 20, "y_in": 70, "heading_deg": 180})
    assert sim.dock() == Pose(20.0, 70.0, 180.0)
    with pytest.raises(DriverError, match=r"charge: the base is 50.0 in from the dock; the beacon guides it "
                                          r"in from 24 in") as caught:
        sim.charge()
    assert caught.value.code == OUT_OF_RANGE
    sim.move([Pose(20.0, 60.0, 180.0)], None)  # turn 90° (18 s), 40 in (80 s), turn 90° (18 s), vision 5 s
    level = 0.5 - 121.0 / 18000.0
    assert sim.state().battery == pytest.approx(level)
    state = sim.charge()  # the beacon: 10 in onto the contacts (20 s), then 1 - level at 1/1800 per second
    level -= 20.0 / 18000.0
    assert state.battery == 1.0 and state.pose == Pose(20.0, 70.0, 180.0)
    assert state.clock_s == pytest.approx(121.0 + 20.0 + (1.0 - level) * 1800.0)


def test_docking_removes_the_drift(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.5, dock={"x_in": 20, "y_in": 70, "heading_deg": 180})
    sim.pose = Pose(25.0, 72.0, 180.0)
    sim.drift = Drift(3.0, -2.0)  # the robot believes it stands at (22, 74) and the dock at (17, 72)
    assert sim.dock() == Pose(17.0, 72.0, 180.0)
    state = sim.charge()
    assert state.pose == Pose(20.0, 70.0, 180.0) and sim.dock() == Pose(20.0, 70.0, 180.0)


def test_a_world_without_a_dock_cannot_charge(tmp_path: Path) -> None:
    sim = world(tmp_path, battery=0.5)
    assert sim.dock() is None
    with pytest.raises(DriverError, match="no charging dock") as caught:
        sim.charge()
    assert caught.value.code == OUT_OF_RANGE


def test_a_world_with_neither_key_runs_tethered(tmp_path: Path) -> None:
    sim = world(tmp_path)
    sim.move([Pose(40.0, 20.0, 0.0)], None)
    assert sim.state().battery == 1.0 and sim.dock() is None


def test_the_lab_has_a_dock() -> None:
    _, catalogue = profile_and_catalogue()
    assert load_world("lab", catalogue).dock == Dock(24.0, 85.0, 180.0)


@pytest.mark.parametrize(("extra", "message"), [
    ({"battery": 1.5}, "world: field 'battery' must be a level from 0 to 1, got 1.5"),
    ({"battery": -0.1}, "world: field 'battery' must be a number >= 0.0"),
    ({"battery": "full"}, "world: field 'battery' must be a number"),
    ({"dock": {"x_in": 200, "y_in": 10}}, "dock: field 'x_in' puts the dock outside the 120x100 in room"),
    ({"dock": {"x_in": 20, "y_in": 10, "z_in": 3}}, "dock: field 'z_in' is unknown"),
    ({"dock": [20, 10]}, "dock: must be an object"),
])
def test_bad_dock_and_battery_keys_are_one_line_errors_naming_the_field(extra: dict[str, object], message: str) -> None:
    _, catalogue = profile_and_catalogue()
    data = {"room": ROOM, "robot": {"x_in": 20, "y_in": 20}, **extra}
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")) as caught:
        parse_world(data, "w.json", catalogue)
    assert "\n" not in str(caught.value) and str(caught.value).startswith("w.json: ")


@given(start=st.floats(0.0, 1.0), spends=st.lists(st.tuples(st.floats(0.0, 1e5), st.sampled_from(
    [MOVING_PER_S, SENSING_PER_S, GRASPING_PER_S])), max_size=20))
def test_draining_never_raises_the_level_nor_goes_below_empty(start: float, spends: list[tuple[float, float]]) -> None:
    battery = Battery(start)
    for seconds, rate in spends:
        before = battery.level
        battery.drain(seconds, rate)
        assert 0.0 <= battery.level <= before
        assert battery.level == pytest.approx(max(0.0, before - seconds * rate))


@given(level=st.floats(0.0, 1.0))
def test_charging_takes_the_missing_charge_over_the_rate(level: float) -> None:
    battery = Battery(level)
    seconds = battery.charge()
    assert battery.level == 1.0 and seconds == pytest.approx((1.0 - level) * 1800.0)


def test_a_tethered_battery_never_drains() -> None:
    battery = Battery(1.0, metered=False)
    battery.drain(1e9, MOVING_PER_S)
    assert battery.level == 1.0
