"""A move a moving obstacle blocked: look again, go around it or wait, give up after a bound.

The paper's CSL "can not handle ... moving obstacles" (docs/method.md). A driver with
the optional ``blocked_moves`` feature (docs/driver-protocol.md, "Moving obstacles")
stops a move short of a person or cart that comes within its safety distance ahead and
answers where it stood. Each move to a test or grasp position then sits in a branch
(:func:`around_movers`) that ``csl bt`` shows::

    MoveTo                      the move as before
    until past                  while the move ends blocked:
      Blocked?                    a blocked move, rounds left (else: give up the object)
      LookAgain                   a new overhead image, the obstacle drawn into the map
      re-plan or wait
        MoveTo (around it)        a path around where it stood
        wait and retry            or: wait for it to pass, then the plain path again
          WaitForMover
          MoveTo (retry)

Every round is one look; after ``Params.blocked_tries`` rounds the object fails with a
clear reason (event ``gave_up``) and the episode goes on with the next one: a busy
floor costs an object, never the run. With ``Params.blocked_tries`` 0, or a driver
without the feature, the branch is off and a blocked move counts as a collision.
Waiting is robot time spent on the move, charged to the object's moving seconds.
"""

from __future__ import annotations

import math
from concurrent.futures import Future
from typing import Any

import py_trees
from py_trees.common import Access, Status
from py_trees.composites import Selector, Sequence

from behaviours.actions import BLOCKED, Blockage, MoveTo
from behaviours.base import CslBehaviour, DriverAction, LookAction
from behaviours.events import Event
from behaviours.services import namespace
from hero_driver.interface import BlockedMoves, Driver, RobotState

AVOID_MARGIN_IN = 3.0
"""The obstacle is drawn into the map this much wider than the driver says it reaches:
it keeps walking while the robot plans."""
START_CLEAR_IN = 1.0
"""...but never over the robot itself, whose base must stay this clear of the drawn disc's
inflated edge, or the plan could not start."""


def blocked_moves_on(driver: Driver) -> bool:
    """Whether the driver offers the ``blocked_moves`` feature (and has it on)."""
    return isinstance(driver, BlockedMoves) and driver.safety_in() is not None


def branch_off_notice(driver: Driver, tries: int) -> str | None:
    """The one line ``csl run`` prints when the branch cannot act because the driver
    lacks the feature (None when it can, or when ``tries`` 0 turned it off on purpose)."""
    if tries <= 0 or blocked_moves_on(driver):
        return None
    return (f"blocked moves: driver {driver.robot} has no blocked_moves feature: the blocked-move branch is off "
            f"(a move into a person or cart ends collided)")


class Blocked(CslBehaviour):
    """Condition ``Blocked?``: the last move of this branch ended blocked and a round is
    left; it spends one. With none left it gives the object up (reason logged) and
    fails, so the move fails and no further verb is sent for that object."""

    def __init__(self, robot: str, name: str = "Blocked?") -> None:
        super().__init__(name, robot)
        self.bb.register_key(BLOCKED, access=Access.WRITE)

    def update(self) -> Status:
        blockage: Blockage | None = self.bb.get(BLOCKED) if self.bb.exists(BLOCKED) else None
        if blockage is None:
            self.feedback_message = "not blocked"
            return Status.FAILURE
        bound = self.services.params.blocked_tries
        if blockage.rounds >= bound:
            self.bb.set(BLOCKED, None)
            return self._give_up(blockage, bound)
        self.bb.set(BLOCKED, Blockage(blockage.obstacle, blockage.rounds + 1))
        o = blockage.obstacle
        self.feedback_message = f"blocked by an obstacle at ({o.x_in:.0f}, {o.y_in:.0f}): round {blockage.rounds + 1}"
        return Status.SUCCESS

    def _give_up(self, blockage: Blockage, bound: int) -> Status:
        obj = self.object_at_hand()
        o = blockage.obstacle
        reason = (f"a moving obstacle kept blocking the way ({bound} rounds of re-planning and waiting; "
                  f"last at ({o.x_in:.0f}, {o.y_in:.0f}))")
        if obj is not None and not obj.done:
            self.services.given_up.add(obj)
            obj.finish("failed")
            self.note(Event.GAVE_UP, reason=reason)
        self.feedback_message = reason
        return Status.FAILURE


class LookAgain(LookAction):
    """A new overhead image, with the obstacle the move met drawn into the planner's map
    (a disc ``AVOID_MARGIN_IN`` wider than it reaches, kept clear of the robot)."""

    POSE_ACCESS = Access.WRITE  # an image may correct where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, name: str = "LookAgain") -> None:
        super().__init__(name, robot)
        self.bb.register_key(BLOCKED, access=Access.READ)

    def start(self) -> Future[Any] | Status:
        return self.take_look()

    def finish(self, result: Any) -> Status:
        navigator = self.services.navigator
        blockage: Blockage | None = self.bb.get(BLOCKED)
        self.look(result)
        if blockage is None:
            return Status.FAILURE
        o, robot = blockage.obstacle, self.robot_pose()
        room = math.hypot(o.x_in - robot.x_in, o.y_in - robot.y_in) - navigator.vision_map.inflation_in - START_CLEAR_IN
        radius = min(o.radius_in + AVOID_MARGIN_IN, room)
        if radius > 0.0:
            self.timed(lambda: navigator.avoid(((o.x_in, o.y_in, radius),)))
        self.feedback_message = f"obstacle drawn in at ({o.x_in:.0f}, {o.y_in:.0f}), {radius:.0f} in"
        return Status.SUCCESS


class WaitForMover(DriverAction):
    """Stand still ``Params.blocked_wait_s`` for the obstacle to walk on, then forget
    where it stood (the retry plans on the image alone)."""

    VERB = "wait"

    def __init__(self, robot: str, name: str = "WaitForMover") -> None:
        super().__init__(name, robot)
        self._since = 0.0

    def start(self) -> Future[RobotState] | Status:
        driver = self.services.driver
        if not blocked_moves_on(driver):
            return Status.FAILURE
        assert isinstance(driver, BlockedMoves)
        self._since = driver.state().clock_s
        return driver.wait(self.services.params.blocked_wait_s)

    def finish(self, result: RobotState) -> Status:
        waited = max(0.0, result.clock_s - self._since)
        self.obj.ledger.moving_s += waited
        self.note(Event.MOVE, to=None, seconds=round(waited, 1), collided=False, waited=True,
                  pose=[round(result.pose.x_in, 1), round(result.pose.y_in, 1), round(result.pose.heading_deg, 1)],
                  path=[])
        self.services.navigator.avoid(())
        return Status.SUCCESS


class UntilPast(py_trees.decorators.Decorator):
    """Runs the blocked-move rounds again while a move in them ends blocked; stops when
    one gets through (SUCCESS) or the branch has nothing more to try (FAILURE)."""

    def __init__(self, child: py_trees.behaviour.Behaviour, robot: str, name: str = "until past") -> None:
        super().__init__(name=name, child=child)
        self.bb = self.attach_blackboard_client(name=name, namespace=namespace(robot))
        self.bb.register_key(BLOCKED, access=Access.READ)

    def update(self) -> Status:
        status = self.decorated.status
        if status == Status.FAILURE and self.bb.exists(BLOCKED) and self.bb.get(BLOCKED) is not None:
            self.feedback_message = "blocked again: another round"
            return Status.RUNNING
        return status


def around_movers(robot: str, first: MoveTo, around: MoveTo, retry: MoveTo) -> py_trees.behaviour.Behaviour:
    """``first`` (a move to a test or grasp position) with the blocked-move branch: see
    the module docstring. ``around`` and ``retry`` are moves to the same target with
    roles ``around`` and ``retry``."""
    moves: tuple[Any, ...] = (first, around, retry)
    if {m.target for m in moves} != {first.target} or [m.role for m in moves] != list(MoveTo.ROLES):
        raise ValueError("around_movers needs moves to one target with roles first, around and retry")
    for move in moves:
        move.in_branch = True
    rounds = Sequence("blocked", memory=True, children=[
        Blocked(robot), LookAgain(robot),
        Selector("re-plan or wait", memory=True, children=[
            around, Sequence("wait and retry", memory=True, children=[WaitForMover(robot), retry])])])
    return Selector(f"{first.name} or around", memory=True, children=[first, UntilPast(rounds, robot)])
