"""Exploring a home the robot has never mapped, before its objects are located.

Without a ceiling camera one look shows only what the robot's range sensor reaches
from where it stands (:mod:`behaviours.perception`). So before the objects are
located, the branch "explore the home" repeats one round — ``LookAround`` (a scan where
the robot stands, read into the map; then the perception's next view), ``MoreToSee?``
(there is one), ``GoToView`` (plan a path on the map built so far and drive it) —
until the perception has no view left to offer: the home is mapped, or what is left
unknown cannot be reached. A view the robot cannot reach (no path, or the move
collided) is told to the perception, which does not offer it again. A bound on the
rounds (``Params.max_views``) stops a search that would not end; the event says so.

With the ceiling camera the branch is not in the tree (``build_tree(explore=False)``):
the camera sees the whole room at once, and the tree is the paper's.

Robot time spent exploring belongs to no object: each round's seconds are on its
events (``view``, ``explore_move``) and their sum on ``mapped``.
"""

from __future__ import annotations

from concurrent.futures import Future
from typing import Any

import py_trees
from py_trees.common import Access, Status
from py_trees.composites import Sequence

from behaviours.actions import pose_json
from behaviours.base import CslBehaviour, DriverAction, LookAction, receive_services
from behaviours.bridge import to_driver_pose
from behaviours.events import Event
from behaviours.legs import first_leg
from behaviours.services import Services, namespace
from hero_driver.interface import MoveResult
from planner import Pose as PlannerPose

VIEW = "view"  # blackboard: the next view to look from (None: nothing more to see)
EXPLORED_S = "explored_s"  # blackboard: robot seconds spent exploring so far
SEEN = "candidates_seen"  # blackboard: object candidates the latest look found


class LookAround(LookAction):
    """Take a look where the robot stands, read it into the map, and choose the next view."""

    POSE_ACCESS = Access.WRITE  # the scan matcher corrects where the robot stands (CslBehaviour.look)

    def __init__(self, robot: str, name: str = "LookAround") -> None:
        super().__init__(name, robot)
        self.bb.register_key(VIEW, access=Access.WRITE)
        self.bb.register_key(EXPLORED_S, access=Access.WRITE)
        self.bb.register_key(SEEN, access=Access.WRITE)
        self._clock_before: float | None = None

    def start(self) -> Future[Any]:
        self._clock_before = self.services.driver.state().clock_s
        return self.take_look()

    def finish(self, result: Any) -> Status:
        services = self.services
        scene = self.look(result)
        spent = max(0.0, services.driver.state().clock_s - (self._clock_before or 0.0))
        _add_explored(self.bb, spent)
        self.bb.set(SEEN, len(scene.regions))
        here = self.robot_pose()
        view = services.perception.next_view(here)
        self.bb.set(VIEW, view)
        self.note(Event.VIEW, pose=[round(here.x_in, 1), round(here.y_in, 1), round(here.heading_deg, 1)],
                  candidates=len(scene.regions), seconds=round(spent, 1),
                  next=None if view is None else [round(view.x_in, 1), round(view.y_in, 1), round(view.heading_deg, 1)])
        self.feedback_message = f"{len(scene.regions)} candidates; " + (
            "nothing more to see" if view is None else f"next view ({view.x_in:.0f}, {view.y_in:.0f})")
        return Status.SUCCESS


class MoreToSee(CslBehaviour):
    """Condition ``MoreToSee?``: the perception offered a view to look from next."""

    def __init__(self, robot: str, name: str = "MoreToSee?") -> None:
        super().__init__(name, robot)
        self.bb.register_key(VIEW, access=Access.READ)

    def update(self) -> Status:
        return Status.SUCCESS if self.bb.get(VIEW) is not None else Status.FAILURE


class GoToView(DriverAction):
    """Plan a path to the next view on the map built so far and drive it, or its first
    ``leg_in`` of the perception (then a look, and the next view chosen again:
    ``behaviours.legs`` says why); a view with no path,
    or a move that collided, is unreachable (told to the perception)."""

    VERB = "move"
    POSE_ACCESS = Access.WRITE  # the end of the move is where the robot stands

    def __init__(self, robot: str, name: str = "GoToView") -> None:
        super().__init__(name, robot)
        self.bb.register_key(VIEW, access=Access.READ)
        self.bb.register_key(EXPLORED_S, access=Access.WRITE)
        self._view: PlannerPose | None = None

    def start(self) -> Future[MoveResult] | Status:
        view = self._view = self.bb.get(VIEW)
        if view is None:
            return Status.FAILURE
        plan = self.services.navigator.plan(self.robot_pose(), view)
        if not plan.found:
            return self._unreachable(f"no path: {plan.reason}")
        leg = first_leg(plan.path or (), self.services.perception.leg_in)
        return self.services.driver.move([to_driver_pose(p) for p in leg])

    def finish(self, result: MoveResult) -> Status:
        self.bb.pose = result.pose
        _add_explored(self.bb, result.duration_s)
        self.note(Event.EXPLORE_MOVE, seconds=round(result.duration_s, 1), collided=result.collided,
                  pose=pose_json(result.pose))
        if result.collided or result.blocked is not None:
            return self._unreachable("the move stopped short")
        return Status.SUCCESS

    def _unreachable(self, reason: str) -> Status:
        assert self._view is not None
        self.services.perception.unreachable(self._view)
        self.note(Event.EXPLORE_MOVE, unreachable=[round(self._view.x_in, 1), round(self._view.y_in, 1)],
                  reason=reason)
        self.feedback_message = f"view unreachable: {reason}"
        return Status.FAILURE


def _explored(bb: py_trees.blackboard.Client) -> float:
    """Robot seconds spent exploring so far (none before the first round)."""
    return float(bb.get(EXPLORED_S)) if bb.exists(EXPLORED_S) else 0.0


def _add_explored(bb: py_trees.blackboard.Client, seconds: float) -> None:
    bb.set(EXPLORED_S, _explored(bb) + seconds)


class UntilMapped(py_trees.decorators.Decorator):
    """Repeat a round of exploring until no view is left, or ``Params.max_views`` rounds."""

    def __init__(self, child: py_trees.behaviour.Behaviour, robot: str, name: str = "until mapped") -> None:
        super().__init__(name=name, child=child)
        self.bb = self.attach_blackboard_client(name=name, namespace=namespace(robot))
        self.bb.register_key(VIEW, access=Access.READ)
        self.bb.register_key(EXPLORED_S, access=Access.READ)
        self.bb.register_key(SEEN, access=Access.READ)
        self._services: Services | None = None
        self.rounds = 0

    def setup(self, **kwargs: Any) -> None:
        self._services = receive_services(self, kwargs)

    def initialise(self) -> None:
        self.rounds = 0

    def update(self) -> Status:
        if self.decorated.status == Status.RUNNING:
            return Status.RUNNING
        self.rounds += 1
        view = self.bb.get(VIEW) if self.bb.exists(VIEW) else None
        if self._services is None:
            raise RuntimeError(f"{self.name}: ticked before setup(services=...)")
        limit = self._services.params.max_views
        if view is not None and self.rounds < limit:
            self.feedback_message = f"round {self.rounds}"
            return Status.RUNNING  # the child starts afresh: look again from where the robot now stands
        reason = ((self._services.perception.stranded or "the home is mapped") if view is None
                  else f"the bound of {limit} views was spent")
        spent = _explored(self.bb)
        found = self.bb.get(SEEN) if self.bb.exists(SEEN) else 0
        self._services.log.event(Event.MAPPED, behaviour=self.name, views=self.rounds, seconds=round(spent, 1),
                                 candidates=found, reason=reason)
        self.feedback_message = reason
        return Status.SUCCESS


def explore(robot: str) -> py_trees.behaviour.Behaviour:
    """The exploration branch (the module docstring)."""
    return UntilMapped(Sequence("look further", memory=True, children=[
        LookAround(robot), MoreToSee(robot), GoToView(robot)]), robot, name="explore the home")
