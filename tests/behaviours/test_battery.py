"""The low-battery guard (behaviours.battery), behaviour by behaviour against a fake
driver whose battery level and dock the test sets, then the whole guard pausing and
resuming a piece of work.

Geometry (conftest's FakeNavigator): the object at (100, 50); the dock at (100, 110)
is 60 in from it at bearing 90°, so an object in hand resumes from position (60, 90).
"""

from __future__ import annotations

from concurrent.futures import Future

import numpy as np
import py_trees
import pytest
from py_trees.common import Status

from behaviours.actions import LocateObjects
from behaviours.battery import BatteryLow, Charge, DriveToDock, LookFromDock, dock_of, guarded
from behaviours.guard import KeepPlace
from behaviours.services import Params
from hero_driver.interface import Charger, Pose as DriverPose, RobotState
from learner.position import Position
from planner import Scene
from tests.behaviours.conftest import (PENDING, ROBOT, FakeDriver, FakeNavigator, fresh_board, get, image,
                                       make_services, moved, put, REGION, run, setup, start_object, tick)

DOCK = DriverPose(100.0, 110.0, 90.0)


class ChargingDriver(FakeDriver):
    """A FakeDriver with the battery feature: a level the test sets and a dock."""

    def __init__(self, level: float, dock: DriverPose | None = DOCK) -> None:
        super().__init__()
        self.level, self.where_to_charge, self.clock_s = level, dock, 0.0

    def state(self) -> RobotState:
        return RobotState(self.pose, self.clock_s, self.level)

    def dock(self) -> DriverPose | None:
        return self.where_to_charge

    def charge(self) -> Future[RobotState]:
        return self._answer("charge")


class MappedNavigator(FakeNavigator):
    """A FakeNavigator that, like the real one, has a scene only once it observed."""

    @property
    def scene(self) -> Scene:
        if not self.observed:
            raise ValueError("nothing observed yet")
        empty = np.zeros((1, 1), dtype=bool)
        return Scene(image(), (), None, empty, empty)


def guard_services(level: float, *, threshold: float = 0.2, mapped: bool = True,
                   dock: DriverPose | None = DOCK, driver: FakeDriver | None = None):  # noqa: ANN201
    nav = MappedNavigator()
    nav.observed = int(mapped)
    return make_services(params=Params(battery_low=threshold), driver=driver or ChargingDriver(level, dock),
                         navigator=nav)


def idle() -> py_trees.behaviour.Behaviour:
    return py_trees.behaviours.Success("work")


# -- BatteryLow? ------------------------------------------------------------------------------


@pytest.mark.parametrize(("level", "expected"), [(0.19, Status.SUCCESS), (0.2, Status.FAILURE), (0.8, Status.FAILURE)])
def test_battery_low_compares_the_reported_level_with_the_threshold(level: float, expected: Status) -> None:
    fresh_board()
    assert run(BatteryLow(ROBOT, protects=idle()), guard_services(level)) == expected


@pytest.mark.parametrize("why", ["threshold 0", "no dock", "no charge verb", "no map"])
def test_the_guard_is_off_without_the_battery_feature_a_threshold_or_a_map(why: str) -> None:
    fresh_board()
    services = {"threshold 0": lambda: guard_services(0.0, threshold=0.0),
                "no dock": lambda: guard_services(0.0, dock=None),
                "no charge verb": lambda: guard_services(0.0, driver=FakeDriver()),
                "no map": lambda: guard_services(0.0, mapped=False)}[why]()
    low = BatteryLow(ROBOT, protects=idle())
    assert run(low, services) == Status.FAILURE and low.fired is False


def test_the_guard_never_interrupts_a_verb_in_flight() -> None:
    fresh_board()
    services = guard_services(0.05)
    services.driver.script("camera", PENDING)  # type: ignore[attr-defined]
    work = setup(LocateObjects(ROBOT), services)
    assert tick(work, max_ticks=1) == Status.RUNNING
    low = BatteryLow(ROBOT, protects=work)
    assert run(low, services) == Status.FAILURE and low.feedback_message == "a verb is in flight"


def test_a_plain_fake_driver_has_no_dock_and_a_charging_one_does() -> None:
    assert dock_of(FakeDriver()) is None  # type: ignore[arg-type]
    assert isinstance(ChargingDriver(0.5), Charger) and dock_of(ChargingDriver(0.5)) == DOCK  # type: ignore[arg-type]


# -- DriveToDock and Charge -----------------------------------------------------------------------


def test_drive_to_dock_plans_from_where_the_robot_stands_and_drives_the_path() -> None:
    services = guard_services(0.1)
    fresh_board()
    put("pose", DriverPose(40.0, 50.0, 0.0))
    services.driver.script("move", moved(DOCK, seconds=120.0))  # type: ignore[attr-defined]
    assert run(DriveToDock(ROBOT), services) == Status.SUCCESS
    (start, goal), = services.navigator.plans  # type: ignore[attr-defined]
    assert (start.x_in, start.y_in, goal.x_in, goal.y_in) == (40.0, 50.0, 100.0, 110.0)
    assert services.driver.calls == [("move", (DOCK,), None)]  # type: ignore[attr-defined]
    assert get("pose") == DOCK
    assert get("dock_trip") == {"from": [40.0, 50.0, 0.0], "level": 0.1, "moving_s": 120.0, "collided": False}


def test_no_path_to_the_dock_fails_and_says_so() -> None:
    services = guard_services(0.1)
    fresh_board()
    services.navigator.blocked[(100.0, 110.0)] = "goal in an obstacle"  # type: ignore[attr-defined]
    assert run(DriveToDock(ROBOT), services) == Status.FAILURE
    assert services.log.events == [{"event": "no_path", "behaviour": "DriveToDock", "to": "dock",  # type: ignore[attr-defined]
                                    "reason": "goal in an obstacle"}]
    assert services.driver.calls == []  # type: ignore[attr-defined]


def test_charge_logs_the_visit_then_a_look_resumes_the_object_from_the_dock() -> None:
    """DriveToDock left the robot at (96, 104), short of the dock; the beacon put it on
    the dock at (100, 110). After the charge the robot's pose is unknown until
    ``LookFromDock`` has looked: then the pose is the dock's, and the object in hand
    (at (100, 50)) resumes from there, 60 in away at bearing 90°."""
    services = guard_services(0.1)
    fresh_board()
    record, _ = start_object(services, start=Position(6.0, 0.0))
    put("pose", DriverPose(96.0, 104.0, 90.0))
    put("dock_trip", {"from": [106.0, 50.0, 180.0], "level": 0.1, "moving_s": 150.0, "collided": False})
    driver: ChargingDriver = services.driver  # type: ignore[assignment]
    driver.clock_s = 500.0
    driver.pose = DOCK
    driver.script("charge", RobotState(DOCK, 500.0 + 1620.0, 1.0))
    assert run(Charge(ROBOT), services) == Status.SUCCESS
    assert services.log.events == [{  # type: ignore[attr-defined]
        "event": "charge", "object": 0, "behaviour": "Charge", "level_before": 0.1, "level": 1.0,
        "charging_s": 1620.0, "moving_s": 150.0, "came_from": [106.0, 50.0, 180.0], "dock": [100.0, 110.0, 90.0]}]
    assert record.session.position == Position(6.0, 0.0)  # not placed yet: the look does that
    driver.script("camera", image())
    services.navigator.scenes.append((REGION,))  # type: ignore[attr-defined]
    assert run(LookFromDock(ROBOT), services) == Status.SUCCESS
    assert driver.verbs()[-1] == "camera" and get("pose") == DOCK
    assert record.session.position == Position(60.0, 90.0)
    assert record.outcome is None  # nothing about the object changed but where the robot stands


# -- the guard around a piece of work ----------------------------------------------------------------


class Steps(py_trees.behaviour.Behaviour):
    """Work that takes ``ticks`` ticks and counts how often it was (re)started."""

    def __init__(self, name: str, ticks: int) -> None:
        super().__init__(name)
        self.ticks, self.left, self.starts = ticks, ticks, 0

    def initialise(self) -> None:
        self.starts += 1
        self.left = self.ticks

    def update(self) -> Status:
        self.left -= 1
        return Status.RUNNING if self.left > 0 else Status.SUCCESS


class Drain(py_trees.behaviour.Behaviour):
    """Drops the fake battery to ``level`` when ticked (the work spent it)."""

    def __init__(self, driver: ChargingDriver, level: float) -> None:
        super().__init__("drain")
        self.driver, self.level = driver, level

    def update(self) -> Status:
        self.driver.level = self.level
        return Status.SUCCESS


def test_the_guard_pauses_the_work_charges_and_resumes_it_where_it_was() -> None:
    services = guard_services(0.9)
    fresh_board()
    driver: ChargingDriver = services.driver  # type: ignore[assignment]
    first, second = Steps("first", 1), Steps("second", 3)
    work = py_trees.composites.Sequence("work", memory=True, children=[first, Drain(driver, 0.1), second])
    root = setup(guarded(work, ROBOT), services)
    driver.script("move", moved(DOCK, seconds=100.0)).script("charge", RobotState(DOCK, 1900.0, 1.0))
    driver.script("camera", image())
    services.navigator.scenes.append(())  # type: ignore[attr-defined]
    root.tick_once()  # first done, the battery drained, second started (2 ticks left)
    assert (first.starts, second.starts, second.left) == (1, 1, 2)
    root.tick_once()  # BatteryLow? fires: to the dock, charged, a look; the work is paused, not reset
    assert driver.verbs() == ["move", "charge", "camera"] and driver.level == 0.1  # the fake's level is the test's
    assert work.status == Status.RUNNING and second.status == Status.RUNNING
    driver.level = 1.0
    root.tick_once()  # charged: the work continues with second, first is not run again
    root.tick_once()
    assert root.status == Status.SUCCESS
    assert (first.starts, second.starts, second.left) == (1, 1, 0)
    assert [e["event"] for e in services.log.events] == ["charge"]  # type: ignore[attr-defined]


def test_keep_place_stops_the_work_when_the_episode_ends() -> None:
    services = guard_services(0.9)
    fresh_board()
    second = Steps("second", 5)
    work = py_trees.composites.Sequence("work", memory=True, children=[second])
    root = setup(guarded(work, ROBOT), services)
    root.tick_once()
    assert second.status == Status.RUNNING
    root.stop(Status.INVALID)  # not pre-empted by the guard: the work is really stopped
    assert second.status == Status.INVALID and work.status == Status.INVALID
    assert isinstance(root.children[1], KeepPlace)
