"""The low-battery guard: py_trees' battery-check idiom at the top of the tree.

The paper's CSL "can not handle ... low battery" (docs/method.md). Here a Selector
without memory puts a ``recharge`` branch before the work: every tick ``BatteryLow?``
looks at the level the driver reports, and when it is below ``Params.battery_low`` the
robot plans a path to the dock on the vision map, drives there and charges. The work
branch is not restarted afterwards: :class:`~behaviours.guard.KeepPlace` pauses it while the robot
charges, so the object in hand resumes where it left off with every measurement its
recognition session holds (only where the robot stands relative to the object is new).

Charging moves the base: the dock's beacon guides it the last inches onto the contacts,
and a driver may reset its dead reckoning there (the simulator's does: the dock is a
known landmark). The correction the perception keeps (:mod:`behaviours.localisation`)
was worked out against the old dead reckoning, so after a charge it no longer says
where the robot stands: in the simulated apartment-2 under ``paper`` the robot left the
dock believing itself feet from where it was, bumped into the hall's walls and marked
them as obstacles, and every later object failed. So ``LookFromDock`` takes a look
before anything moves again, and that look places the robot (the overhead camera; the
onboard scan matcher, which aligns a scan once more from the reported pose when the
odometry's step does not fit)::

    recharge
      BatteryLow?
      DriveToDock
      Charge
      LookFromDock

The guard is off (``BatteryLow?`` always fails) when the driver lacks the optional
``battery`` feature (:class:`~hero_driver.interface.Charger` naming a dock),
when ``Params.battery_low`` is 0, and until the first overhead image gives a map to
plan the trip on. It never interrupts a verb in flight: the robot finishes the move,
sensing or grasp it is doing, and the guard fires at the next tick.

With ``Params.price_detours`` the learner's move prices count the trip to the dock a
test would cause (executive.battery_cost); :class:`LookFromDock` then drops the object's
cached prices, made on the low level.
"""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any

import py_trees
from py_trees.common import Access, Status

from behaviours.actions import pose_json
from behaviours.base import CslBehaviour, DriverAction, LookAction
from behaviours.bridge import to_driver_pose, to_planner_pose
from behaviours.events import Event
from behaviours.guard import KeepPlace
from behaviours.legs import LeggedMove
from hero_driver.interface import Charger, Driver, MoveResult, Pose, RobotState

DOCK_TRIP = "dock_trip"  # blackboard: what the drive to the dock cost, for the charge event


def dock_of(driver: Driver) -> Pose | None:
    """Where the driver says its charging dock is; None without the ``battery`` feature."""
    return driver.dock() if isinstance(driver, Charger) else None


class BatteryLow(CslBehaviour):
    """Condition ``BatteryLow?``: the reported level is below the threshold and the
    guard may act (see the module docstring); ``protects`` is the work it pre-empts."""

    def __init__(self, robot: str, protects: py_trees.behaviour.Behaviour, name: str = "BatteryLow?") -> None:
        super().__init__(name, robot)
        self.protects = protects
        self.fired = False  # read by KeepPlace (behaviours.guard): the work is being paused, not abandoned

    def update(self) -> Status:
        self.fired = self._low()
        return Status.SUCCESS if self.fired else Status.FAILURE

    def _low(self) -> bool:
        services = self.services
        threshold = services.params.battery_low
        if threshold <= 0.0 or dock_of(services.driver) is None:
            self.feedback_message = "guard off"
            return False
        try:
            services.navigator.scene
        except ValueError:  # nothing observed: no map to plan the trip on
            self.feedback_message = "no map yet"
            return False
        tip = self.protects.tip()
        if isinstance(tip, DriverAction) and tip.status == Status.RUNNING:
            self.feedback_message = "a verb is in flight"
            return False
        level = services.driver.state().battery
        self.feedback_message = f"battery {level:.2f} (low below {threshold:g})"
        return level < threshold


class DriveToDock(LeggedMove):
    """Plan a collision-free path from where the robot stands to the dock and drive it."""

    POSE_ACCESS = Access.WRITE  # the move changes where the robot stands

    VERB = "move"

    def __init__(self, robot: str, name: str = "DriveToDock") -> None:
        super().__init__(name, robot)
        self.bb.register_key(DOCK_TRIP, access=Access.WRITE)

    def start(self) -> Future[MoveResult] | Status:
        dock = dock_of(self.services.driver)
        if dock is None:
            return Status.FAILURE
        start = self.robot_pose()
        self.bb.set(DOCK_TRIP, {"from": pose_json(to_driver_pose(start)), "level": self.services.driver.state().battery})
        plan = self.services.navigator.plan(start, to_planner_pose(dock))
        if not plan.found:
            self.note(Event.NO_PATH, to="dock", reason=plan.reason)
            return Status.FAILURE
        return self.drive_path(plan.path or (), fallback=dock)

    def finish(self, result: Any) -> Status:
        whole = self.leg_done(result)
        if whole is None:
            return Status.RUNNING  # a long way to the dock is driven in legs (behaviours.legs)
        result = whole
        self.bb.pose = result.pose
        trip = dict(self.bb.get(DOCK_TRIP))
        trip.update(moving_s=round(result.duration_s, 1), collided=result.collided)
        self.bb.set(DOCK_TRIP, trip)
        return Status.FAILURE if result.collided else Status.SUCCESS


class Charge(DriverAction):
    """Charge at the dock until full and log the visit (event ``charge``)."""

    VERB = "charge"

    def __init__(self, robot: str, name: str = "Charge") -> None:
        super().__init__(name, robot)
        self.bb.register_key(DOCK_TRIP, access=Access.READ)
        self._before: RobotState | None = None

    def start(self) -> Future[RobotState] | Status:
        driver = self.services.driver
        if not isinstance(driver, Charger):
            return Status.FAILURE
        self._before = driver.state()
        return driver.charge()

    def finish(self, result: RobotState) -> Status:
        assert self._before is not None
        trip = self.bb.get(DOCK_TRIP) or {}
        self.note(Event.CHARGE, level_before=round(float(trip.get("level", self._before.battery)), 3),
                  level=round(result.battery, 3), charging_s=round(result.clock_s - self._before.clock_s, 1),
                  moving_s=trip.get("moving_s"), came_from=trip.get("from"), dock=pose_json(result.pose))
        self.feedback_message = f"charged to {result.battery:.2f}"
        return Status.SUCCESS


class LookFromDock(LookAction):
    """After a charge, one look that places the robot where it now stands (the module
    docstring says why), then place the object in hand relative to the dock."""

    POSE_ACCESS = Access.WRITE  # the look corrects where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, name: str = "LookFromDock") -> None:
        super().__init__(name, robot)

    def start(self) -> Future[Any]:
        return self.take_look()

    def finish(self, result: Any) -> Status:
        self.bb.pose = self.services.driver.state().pose  # the base moved onto the contacts
        self.look(result)
        pose = self.robot_pose()
        obj = self.bb.get("object")
        if obj is not None and not obj.done:  # resume from here: the session keeps what it measured
            obj.estimator.retarget(obj.region)  # forget prices made on the low charge (dock detours)
            obj.session.position = obj.estimator.stand_at(pose)
        self.feedback_message = f"at ({pose.x_in:.0f}, {pose.y_in:.0f}) after the charge"
        return Status.SUCCESS


def guarded(work: py_trees.behaviour.Behaviour, robot: str) -> py_trees.behaviour.Behaviour:
    """``work`` under the low-battery guard (the module docstring says how it behaves).

    The recharge branch reports RUNNING when the robot has charged, so the Selector
    does not end the episode there: the next tick ``BatteryLow?`` fails and the work
    resumes."""
    low = BatteryLow(robot, protects=work)
    recharge = py_trees.composites.Sequence("recharge", memory=True, children=[
        low, DriveToDock(robot), Charge(robot), LookFromDock(robot)])
    return py_trees.composites.Selector("battery check", memory=False, children=[
        py_trees.decorators.SuccessIsRunning("until charged", recharge),
        KeepPlace(work, low)])
