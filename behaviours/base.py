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
from behaviours.records import DRIVER_BACK, DRIVER_LOST, LostVerb, ObjectRecord, Refusal, Step
from behaviours.resume import Reconnecting
from behaviours.services import Services, namespace
from hero_driver.interface import INTERNAL, OUT_OF_RANGE, TIMEOUT, UNAVAILABLE, DriverError, MoveResult
from hero_driver.interface import Pose as DriverPose  # noqa: I001 (the planner has a Pose too)
from planner import Pose as PlannerPose, Scene

T = TypeVar("T")


def receive_services(behaviour: py_trees.behaviour.Behaviour, kwargs: dict[str, Any]) -> Services:
    """The services handed to ``tree.setup(services=...)``; a clear error without them."""
    services = kwargs.get("services")
    if not isinstance(services, Services):
        raise RuntimeError(f"{behaviour.name}: setup() needs services=Services(...)")
    return services


class CslBehaviour(py_trees.behaviour.Behaviour):
    """A behaviour with the executive's services and the object and step at hand."""

    POSE_ACCESS = Access.READ  # where the robot stands: written by the moves, and by the looks that correct it

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

    def object_at_hand(self) -> ObjectRecord | None:
        """The object being worked on; None before any is located (locating, the first
        image) or between objects."""
        return self.bb.get("object") if self.bb.exists("object") else None

    @property
    def step(self) -> Step:
        return self.bb.step

    def note(self, kind: Event, **data: object) -> None:
        """Report an event to the episode log, tagged with the object when there is one
        (locating happens before any object)."""
        obj = self.object_at_hand()
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

    def look(self, observation: Any) -> Scene:
        """Read a new look (an overhead image, or an onboard scan: :mod:`behaviours.perception`;
        plans are made on it from now on) and let it correct the driver's dead reckoning
        (:mod:`behaviours.localisation`): when the look places the robot away from where
        its pose says, the pose on the blackboard becomes the corrected one. Only a
        behaviour with write access to the pose looks."""
        services = self.services
        perception = services.perception
        working = self.object_at_hand() is not None  # else nothing to charge it to
        scene = self.timed(lambda: perception.scene(observation)) if working else perception.scene(observation)
        localise = getattr(services.driver, "localise", None)
        seen = scene.robot
        if seen is not None and localise is not None and localise(
                seen.x_in, seen.y_in, *((seen.heading_deg,) if perception.corrects_heading else ())):
            was = self.bb.pose
            self.bb.pose = services.driver.state().pose
            turn = getattr(services.driver, "turn_deg", 0.0)
            self.note(Event.LOCALISED, seen=[round(seen.x_in, 1), round(seen.y_in, 1)],
                      was=None if was is None else [round(was.x_in, 1), round(was.y_in, 1)],
                      offset=[round(v, 2) for v in services.driver.offset],
                      **({"turn_deg": round(turn, 2)} if turn else {}))
        return scene

    def robot_pose(self) -> PlannerPose:
        """Where the robot is: the end of its last move, else what the driver reports."""
        return to_planner_pose(self.bb.pose or self.services.driver.state().pose)


class DriverAction(CslBehaviour):
    """Starts one driver verb and reports RUNNING until its future completes; then maps
    the reply, or the driver's error, to a status, as Nav2's ``BtActionNode`` does.
    Why a verb failed is recorded where a recovery branch's condition reads it; the
    recoveries themselves are branches of the tree (docs/executive.md, "Recoveries").

    How a verb that did not come back ends (docs/reliability.md): one the robot left
    unanswered (``timeout``) gives up the object at hand, which then sends no further
    verb; the next object goes on once the robot takes verbs again
    (:mod:`behaviours.overdue`). A driver that went away (``unavailable``) stops the
    episode, unless ``Params.wait_driver_s`` and a driver that can come back
    (:class:`~behaviours.resume.Reconnecting`) let the reconnect branch wait for one:
    the loss is then recorded (``DRIVER_LOST``) and the behaviour stays RUNNING, paused
    by that branch, until it says a driver is back and the objects are located again
    (``DRIVER_BACK``). Then it fails, so the step under way starts over from where the
    robot now stands; or, with nothing located yet (the first image), it sends its verb
    again. A driver gone between two verbs (the behaviour's start asked where the robot
    stands, or sent its verb, with none alive) is a verb lost the same way. A procedure
    refused as out of range is recorded on the step for the re-approach branch
    (:meth:`refused_for_range`, ``behaviours.reapproach``). An ``internal`` reply (the driver failed, or its reply was malformed: the zenoh client
    says so with that code) is also a ``driver_fault`` event under the behaviour's
    :meth:`verb`: the run's exit status counts them (``executive.exit_status``).
    """

    VERB = ""
    """The driver verb this behaviour sends, as driver faults are counted per verb."""

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name, robot)
        self._robot = robot
        self.bb.register_key(DRIVER_LOST, access=Access.WRITE)
        self.bb.register_key(DRIVER_BACK, access=Access.READ)
        self._future: Future[Any] | None = None
        self._skip: Status | None = None
        self._lost: LostVerb | None = None

    def verb(self) -> str:
        """The verb under way (a behaviour that sends one of several says which)."""
        return self.VERB or self.name

    def initialise(self) -> None:
        self._future, self._skip, self._lost = None, None, None
        obj = self.object_at_hand()
        if obj is not None and obj in self.services.given_up:
            self.feedback_message = f"object {obj.index} was given up: no verb is sent for it"
            self._skip = Status.FAILURE
            return
        try:
            started = self.start()
        except DriverError as exc:
            if exc.code != UNAVAILABLE:
                raise
            # the driver went between two verbs: asked where the robot stands (or sent the
            # verb) with none alive, this is the verb lost with it, for update to handle so
            started = Future()
            started.set_exception(exc)
        if isinstance(started, Status):
            self._skip = started
        else:
            self._future = started

    def update(self) -> Status:
        if self._skip is not None:
            return self._skip
        if self._lost is not None:
            return self._resumed(self._lost)
        assert self._future is not None
        if not self._future.done():
            self.feedback_message = "waiting for the robot"
            return Status.RUNNING
        try:
            result = self._future.result()
        except DriverError as exc:
            self.feedback_message = str(exc)
            self.note(Event.DRIVER_ERROR, code=exc.code, message=exc.message)
            if exc.code == INTERNAL:  # an `internal` or malformed reply: the driver failed, not the test
                self.note(Event.DRIVER_FAULT, verb=self.verb(), message=exc.message)
            if exc.code == UNAVAILABLE:
                return self._driver_lost(exc)
            if exc.code == TIMEOUT:
                return self._unanswered(exc)
            return self.failed(exc)
        if isinstance(result, MoveResult) and result.collided:
            self._bumped(result.pose)
        return self.finish(result)

    def _bumped(self, pose: DriverPose) -> None:
        """Tell the perception where a move stopped collided; a place it keeps out from
        now on is an event (``behaviours.perception.Perception.bumped``)."""
        kept = self.services.perception.bumped(to_planner_pose(pose))
        if kept is not None:
            self.note(Event.BUMPED, at=[round(kept[0], 1), round(kept[1], 1)],
                      pose=[round(pose.x_in, 1), round(pose.y_in, 1), round(pose.heading_deg, 1)])

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

    def refused_for_range(self, exc: DriverError, procedure: str, grasp: bool) -> bool:
        """True when the driver refused ``procedure`` (a grasp when ``grasp``) as out of
        range for the object at hand: nothing was tried, and the refusal is recorded on
        the step (``Step.refusal``) for ``RefusedForRange?`` to judge; the behaviour then
        fails without counting the verb as failed (``behaviours.reapproach``)."""
        if exc.code != OUT_OF_RANGE or self.object_at_hand() is None:
            return False
        self.step.refusal = Refusal(procedure, grasp, exc.message, self.name)
        return True

    def _unanswered(self, exc: DriverError) -> Status:
        """The robot did not answer in time: what it measured or did is unknown, so the
        object at hand is given up (an object already handled stays handled)."""
        obj = self.object_at_hand()
        if obj is not None:
            self.services.given_up.add(obj)
            if not obj.done:
                obj.finish("failed")
                self.note(Event.GAVE_UP, reason=f"the robot did not answer in time ({exc.message})")
        self.feedback_message = f"the robot did not answer in time ({exc.message})"
        return Status.FAILURE

    def _driver_lost(self, exc: DriverError) -> Status:
        wait_s = self.services.params.wait_driver_s
        if wait_s <= 0 or not isinstance(self.services.driver, Reconnecting):
            raise exc  # the robot is gone: no recovery branch can help, the episode stops
        self._lost = LostVerb(self.name, self.services.clock())
        self.bb.set(DRIVER_LOST, self._lost)
        self.feedback_message = f"driver for {self._robot} lost: waiting up to {wait_s:g} s for one to come back"
        return Status.RUNNING

    def _resumed(self, lost: LostVerb) -> Status:
        """Ticked again after the verb was lost: paused until the reconnect branch says a
        driver is back, then the step starts over (or the first image is asked again)."""
        back = self.bb.get(DRIVER_BACK) if self.bb.exists(DRIVER_BACK) else None
        if back is not lost:
            return Status.RUNNING
        self.bb.set(DRIVER_LOST, None)
        if self.object_at_hand() is None:  # nothing located yet: this verb (the first image) again
            self.initialise()
            return Status.RUNNING if self._skip is None else self._skip
        self.feedback_message = "driver back, objects located again: the step starts over"
        return Status.FAILURE


class LookAction(DriverAction):
    """A driver action whose verb is a look of the executive's perception: the overhead
    camera's image, or the onboard scan (:mod:`behaviours.perception`)."""

    def verb(self) -> str:
        return self.services.perception.verb

    def take_look(self) -> Future[Any]:
        """Start one look."""
        return self.services.perception.look()
