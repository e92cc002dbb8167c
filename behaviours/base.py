"""Base classes: a behaviour on the executive's blackboard, and one that waits on the robot.

Behaviours are built without resources: blackboard keys are declared in ``__init__``
and the services arrive in ``setup(services=...)``, as py_trees lays it out. Robot verbs
take seconds to minutes, so a :class:`DriverAction` starts its verb in ``initialise``
and watches the future in ``update``, returning RUNNING meanwhile: the tree keeps
ticking (and could pre-empt) instead of blocking inside one behaviour.
"""

from __future__ import annotations

import abc
from collections.abc import Callable
from concurrent.futures import Future
from typing import Any, TypeVar

import py_trees
from py_trees.common import Access, Status

from behaviours.bridge import to_planner_pose
from behaviours.events import Event
from behaviours.records import ObjectRecord, Step
from behaviours.services import Services, namespace
from hero_driver.interface import UNAVAILABLE, DriverError
from planner import Pose as PlannerPose

T = TypeVar("T")


def receive_services(behaviour: py_trees.behaviour.Behaviour, kwargs: dict[str, Any]) -> Services:
    """The services handed to ``tree.setup(services=...)``; a clear error without them."""
    services = kwargs.get("services")
    if not isinstance(services, Services):
        raise RuntimeError(f"{behaviour.name}: setup() needs services=Services(...)")
    return services


class CslBehaviour(py_trees.behaviour.Behaviour):
    """A behaviour with the executive's services and the object and step at hand."""

    POSE_ACCESS = Access.READ  # where the robot stands: written by the moves alone

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name)
        self.bb = self.attach_blackboard_client(name=name, namespace=namespace(robot))
        self.bb.register_key("object", access=Access.WRITE)
        self.bb.register_key("step", access=Access.WRITE)
        self.bb.register_key("pose", access=self.POSE_ACCESS)
        self._services: Services | None = None

    def setup(self, **kwargs: Any) -> None:
        self._services = receive_services(self, kwargs)

    @property
    def services(self) -> Services:
        if self._services is None:
            raise RuntimeError(f"{self.name}: ticked before setup(services=...)")
        return self._services

    @property
    def obj(self) -> ObjectRecord:
        return self.bb.object

    @property
    def step(self) -> Step:
        return self.bb.step

    def note(self, kind: Event, **data: object) -> None:
        """Report an event to the episode log, tagged with the object when there is one
        (locating happens before any object)."""
        obj: ObjectRecord | None = self.bb.get("object") if self.bb.exists("object") else None
        tagged: dict[str, object] = {"object": obj.index} if obj is not None else {}
        self.services.log.event(kind, **tagged, behaviour=self.name, **data)

    def timed(self, fn: Callable[[], T]) -> T:
        """Run learner or planner work, charging its wall time to the object's computation."""
        clock = self.services.clock
        start = clock()
        try:
            return fn()
        finally:
            self.obj.ledger.computing_s += clock() - start

    def robot_pose(self) -> PlannerPose:
        """Where the robot is: the end of its last move, else what the driver reports."""
        return to_planner_pose(self.bb.pose or self.services.driver.state().pose)


class DriverAction(CslBehaviour):
    """Starts one driver verb and reports RUNNING until its future completes."""

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name, robot)
        self._future: Future[Any] | None = None
        self._skip: Status | None = None

    def initialise(self) -> None:
        self._future, self._skip = None, None
        started = self.start()
        if isinstance(started, Status):
            self._skip = started
        else:
            self._future = started

    def update(self) -> Status:
        if self._skip is not None:
            return self._skip
        assert self._future is not None
        if not self._future.done():
            self.feedback_message = "waiting for the robot"
            return Status.RUNNING
        try:
            result = self._future.result()
        except DriverError as exc:
            self.feedback_message = str(exc)
            self.note(Event.DRIVER_ERROR, code=exc.code, message=exc.message)
            if exc.code == UNAVAILABLE:
                raise  # the robot is gone: no recovery branch can help, the episode stops
            return self.failed(exc)
        return self.finish(result)

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self._future is not None and not self._future.done():
            self._future.cancel()  # pre-empted: the result is no longer wanted
        self._future = None

    @abc.abstractmethod
    def start(self) -> Future[Any] | Status:
        """Start the verb, or return a status at once when there is nothing to do."""

    @abc.abstractmethod
    def finish(self, result: Any) -> Status:
        """Consume the verb's result."""

    def failed(self, exc: DriverError) -> Status:
        """The driver refused or failed; by default the behaviour fails."""
        return Status.FAILURE
