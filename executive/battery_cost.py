"""The dock detour in the move prices the learner sees (docs/executive.md, "Battery").

With the low-battery guard on, a test that leaves the charge below the guard's
threshold sends the robot to its dock right after it: the robot drives from the test
position to the dock, charges, and drives back. The learner only sees seconds, so the
detour is added to the price of the move to such a test, and the learner prefers a test
that finishes before a charge when it tells as much.

What the detour costs: the round trip (test position to dock and back, priced by the
planner like any move) plus the charging time of the charge that round trip spends.
The charge the work itself spends is not counted: it must be put back at the dock
sooner or later whichever test is chosen, so it is not a consequence of the choice;
the round trip is (one more visit to the dock, or the same visit brought forward from a
place farther from it).

Whether a test lasts is judged on the move's drain plus a sensing allowance, the
longest sensing procedure the robot has (the learner prices the sensing apart, and any
of them may follow the move), at the documented drain rates (docs/simulator.md,
"Battery"; the protocol's ``battery`` feature reports the level, not the rates).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from behaviours.battery import dock_of
from behaviours.bridge import to_planner_pose
from behaviours.services import Params
from hero_driver.interface import Driver
from learner.knowledge import Knowledge
from planner import MoveCost, Navigator, Pose
from robot_profile import Robot


@dataclass(frozen=True)
class DrainRates:
    """Share of a full charge per robot second: spent moving, spent sensing, put back
    charging at the dock."""

    moving_per_s: float
    sensing_per_s: float
    charging_per_s: float


HERO_DRAIN = DrainRates(moving_per_s=1.0 / 18000.0, sensing_per_s=1.0 / 36000.0, charging_per_s=1.0 / 1800.0)
"""The HERO 2000's rates as docs/simulator.md documents them (a test keeps them equal to
the simulator's)."""


def lasts(level: float, threshold: float, move_s: float, sense_s: float, rates: DrainRates) -> bool:
    """True when a move of ``move_s`` then a sensing of ``sense_s`` leave the charge at
    or above the guard's threshold (the guard fires only below it)."""
    return level - move_s * rates.moving_per_s - sense_s * rates.sensing_per_s >= threshold


def detour_s(round_trip_s: float, rates: DrainRates) -> float:
    """What a dock visit adds: the round trip and the charging of what it spends."""
    return round_trip_s * (1.0 + rates.moving_per_s / rates.charging_per_s)


def priced_move_s(move_s: float, level: float, threshold: float, sense_s: float, round_trip_s: float,
                  rates: DrainRates) -> float:
    """The move's price for the learner: its seconds, plus the detour when the test
    will not last. A round trip that cannot be made adds nothing: the guard cannot
    dock from there either, and no price can help."""
    if lasts(level, threshold, move_s, sense_s, rates) or not math.isfinite(round_trip_s):
        return move_s
    return move_s + detour_s(round_trip_s, rates)


@dataclass(frozen=True)
class BatteryView:
    """What the detour pricing reads of the robot: its charge now (read at pricing
    time), where its dock is (None: no dock, nothing to price), the guard's threshold,
    the sensing allowance and the drain rates."""

    level: Callable[[], float]
    dock: Callable[[], Pose | None]
    threshold: float
    sense_allowance_s: float
    rates: DrainRates = HERO_DRAIN


class DockDetourNavigator(Navigator):
    """The planner as the executive hands it to the learner's move-cost estimator, with
    the dock detour in every move's price (:func:`priced_move_s`). Paths are planned as
    usual; only the price changes, and ``MoveCost.detour_s`` says by how much."""

    def __init__(self, robot: Robot, battery: BatteryView, **kwargs: object) -> None:
        super().__init__(robot, **kwargs)  # type: ignore[arg-type]
        self.battery = battery

    def move_cost(self, start: Pose, goal: Pose, *, exact: bool = False) -> MoveCost:
        cost = super().move_cost(start, goal, exact=exact)
        if not cost.possible or cost.seconds == 0.0:
            return cost
        b = self.battery
        level = b.level()
        if lasts(level, b.threshold, cost.seconds, b.sense_allowance_s, b.rates):
            return cost
        dock = b.dock()
        if dock is None:
            return cost
        trip = (super().move_cost(goal, dock, exact=exact).seconds
                + super().move_cost(dock, goal, exact=exact).seconds)
        seconds = priced_move_s(cost.seconds, level, b.threshold, b.sense_allowance_s, trip, b.rates)
        return MoveCost(seconds, cost.length_in, cost.turning_deg, cost.exact, cost.reason,
                        detour_s=seconds - cost.seconds)


def navigator_for(robot: Robot, driver: Driver, knowledge: Knowledge, params: Params,
                  **kwargs: object) -> Navigator:
    """The planner the executive hands its behaviours: with the detour pricing when it
    is on (``Params.price_detours``), the guard is on (``Params.battery_low`` > 0) and
    the driver has a dock; the plain planner otherwise (no detour can happen)."""
    if not (params.price_detours and params.battery_low > 0.0 and dock_of(driver) is not None):
        return Navigator(robot, **kwargs)  # type: ignore[arg-type]

    def dock() -> Pose | None:
        at = dock_of(driver)
        return None if at is None else to_planner_pose(at)

    view = BatteryView(level=lambda: driver.state().battery, dock=dock, threshold=params.battery_low,
                       sense_allowance_s=max((s.time_s for s in knowledge.sensing), default=0.0))
    return DockDetourNavigator(robot, view, **kwargs)
