"""The dock detour in move prices (executive.battery_cost), values worked out by hand
from the documented drain rates (docs/simulator.md, "Battery") and the move formula
(vision 5 s + length / 0.5 in/s + turning / 5 deg/s + centring 15 s)."""

from __future__ import annotations

from dataclasses import replace

import math

import pytest
from hypothesis import given, strategies as st

from behaviours.services import Params
from executive.battery_cost import (
    HERO_DRAIN, BatteryView, DockDetourNavigator, detour_s, lasts, navigator_for, priced_move_s,
)
from hero_driver.sim import battery as sim_battery
from planner import Navigator, Pose
from robot_profile import Robot, load_profile
from tests.planner.drawing import Canvas

# the constants worked with by hand; any other the profile gains comes from the shipped one
MODEL = replace(load_profile().robot.motion, speed_in_per_s=0.5, turn_deg_per_s=5.0, vision_s=5.0, centring_s=15.0)
HERO = Robot(load_profile().robot.geometry, MODEL)  # the shipped profile's base and sonar
DOCK = Pose(30.0, 90.0, 180.0)


def test_the_executive_prices_with_the_simulators_rates() -> None:
    assert HERO_DRAIN.moving_per_s == sim_battery.MOVING_PER_S
    assert HERO_DRAIN.sensing_per_s == sim_battery.SENSING_PER_S
    assert HERO_DRAIN.charging_per_s == sim_battery.CHARGING_PER_S


def test_a_test_lasts_when_the_charge_stays_at_or_above_the_threshold() -> None:
    # 90 s moving = 90/18000 = 0.005; 36 s sensing = 36/36000 = 0.001: 0.206 - 0.006 = 0.2
    assert lasts(0.2061, 0.2, 90.0, 36.0, HERO_DRAIN)
    # 108 s moving = 0.006: 0.2061 - 0.007 = 0.1991, below
    assert not lasts(0.2061, 0.2, 108.0, 36.0, HERO_DRAIN)


def test_the_detour_is_the_round_trip_and_recharging_what_it_spent() -> None:
    # 400 s of driving spends 400/18000 of a charge, put back in 400/18000 * 1800 = 40 s
    assert detour_s(400.0, HERO_DRAIN) == pytest.approx(440.0)


def test_the_price_adds_the_detour_only_to_a_test_that_will_not_last() -> None:
    # level 0.21, threshold 0.2, a 105 s sensing allowance (105/36000 = 0.0029167):
    # a 100 s move (0.0055556) leaves 0.20153; a 150 s move (0.0083333) leaves 0.19875
    assert priced_move_s(100.0, 0.21, 0.2, 105.0, 400.0, HERO_DRAIN) == 100.0
    assert priced_move_s(150.0, 0.21, 0.2, 105.0, 400.0, HERO_DRAIN) == pytest.approx(150.0 + 440.0)
    # no way to the dock from there: nothing to price
    assert priced_move_s(150.0, 0.21, 0.2, 105.0, math.inf, HERO_DRAIN) == 150.0


@given(level=st.floats(0.0, 1.0), move=st.floats(0.0, 5000.0), trip=st.floats(0.0, 5000.0))
def test_the_detour_never_lowers_a_price(level: float, move: float, trip: float) -> None:
    assert priced_move_s(move, level, 0.2, 105.0, trip, HERO_DRAIN) >= move


def empty_room_navigator(level: float, dock: Pose | None = DOCK) -> tuple[DockDetourNavigator, Navigator]:
    image = Canvas(240.0, 180.0).robot(90.0, 90.0, 0.0).image()
    view = BatteryView(level=lambda: level, dock=lambda: dock, threshold=0.2, sense_allowance_s=105.0)
    priced, plain = DockDetourNavigator(HERO, view), Navigator(HERO)
    priced.observe(image)
    plain.observe(image)
    return priced, plain


def test_the_navigator_adds_the_dock_round_trip_to_a_move_that_will_not_last() -> None:
    start, goal = Pose(90.0, 90.0, 0.0), Pose(130.0, 90.0, 0.0)
    priced, plain = empty_room_navigator(0.205)
    # the move: 40 in east, no turn: 5 + 80 + 0 + 15 = 100 s (0.00556 of a charge) and a
    # 105 s sensing (0.00292) leave 0.1965 < 0.2
    move = plain.move_cost(start, goal).seconds
    assert move == pytest.approx(100.0, abs=1.0)
    # to the dock: 100 in west, turning 180 to the bearing and 0 to the dock's heading
    # (180): 5 + 200 + 36 + 15 = 256 s; back: 180 to the bearing east, which is the
    # goal's heading: 256 s again; the detour 1.1 * 512 = 563.2 s
    cost = priced.move_cost(start, goal)
    assert cost.detour_s == pytest.approx(563.2, abs=3.0)
    assert cost.seconds == pytest.approx(move + cost.detour_s)
    assert cost.length_in == plain.move_cost(start, goal).length_in


def test_the_navigator_leaves_a_move_that_lasts_alone() -> None:
    start, goal = Pose(90.0, 90.0, 0.0), Pose(130.0, 90.0, 0.0)
    priced, plain = empty_room_navigator(0.22)  # 0.22 - 0.0085 stays above 0.2
    assert priced.move_cost(start, goal) == plain.move_cost(start, goal)
    low_no_dock, _ = empty_room_navigator(0.05, dock=None)
    assert low_no_dock.move_cost(start, goal).detour_s == 0.0


def test_the_executive_prices_detours_only_when_asked_with_the_guard_on_and_a_dock(tmp_path) -> None:
    from hero_driver.sim_driver import SimulatedHero
    from tests.executive.test_battery_episode import small_world

    knowledge = load_profile().knowledge()
    docked = SimulatedHero("r1", world=small_world(tmp_path, 0.5), seed=0)
    undocked = SimulatedHero("r2", world=small_world(tmp_path, 0.5, dock=False), seed=0)
    on = Params(price_detours=True)
    priced = navigator_for(HERO, docked, knowledge, on)
    assert isinstance(priced, DockDetourNavigator)
    # the longest HERO sensing procedure is H-Scan-0.3, 105 s; the dock is the world's
    assert priced.battery.sense_allowance_s == 105.0 and priced.battery.threshold == 0.2
    assert priced.battery.dock() == Pose(20.0, 75.0, 180.0) and priced.battery.level() == 0.5
    for driver, params in ((docked, Params()), (docked, Params(price_detours=True, battery_low=0.0)),
                           (undocked, on)):
        assert type(navigator_for(HERO, driver, knowledge, params)) is Navigator
