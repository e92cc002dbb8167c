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
from dataclasses import dataclass
from typing import Any, TypeVar

import py_trees
from py_trees.common import Access, Status

from behaviours.bridge import to_planner_pose
from behaviours.events import Event
from behaviours.records import ObjectRecord, Step
from behaviours.resume import Reconnecting, relocate, same_robot
from behaviours.services import Services, namespace
from camera_model.image import CameraImage
from hero_driver.interface import OUT_OF_RANGE, TIMEOUT, UNAVAILABLE, DriverError
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

    def look(self, image: CameraImage) -> Scene:
        """Observe a new overhead image (plans are made on it from now on) and let it
        correct the driver's dead reckoning (:mod:`behaviours.localisation`): when the
        image places the robot away from where its pose says, the pose on the blackboard
        becomes the corrected one. Only a behaviour with write access to the pose looks."""
        services = self.services
        working = self.bb.exists("object") and self.bb.get("object") is not None  # else nothing to charge it to
        scene = self.timed(lambda: services.navigator.observe(image)) if working else services.navigator.observe(image)
        localise = getattr(services.driver, "localise", None)
        if scene.robot is not None and localise is not None and localise(scene.robot.x_in, scene.robot.y_in):
            was = self.bb.pose
            self.bb.pose = services.driver.state().pose
            self.note(Event.LOCALISED, seen=[round(scene.robot.x_in, 1), round(scene.robot.y_in, 1)],
                      was=None if was is None else [round(was.x_in, 1), round(was.y_in, 1)],
                      offset=[round(v, 2) for v in services.driver.offset])
        return scene

    def robot_pose(self) -> PlannerPose:
        """Where the robot is: the end of its last move, else what the driver reports."""
        return to_planner_pose(self.bb.pose or self.services.driver.state().pose)


class DriverAction(CslBehaviour):
    """Starts one driver verb and reports RUNNING until its future completes.

    How a verb that did not come back ends (docs/reliability.md): one the robot left
    unanswered (``timeout``) gives up the object at hand, which then sends no further
    verb; the next object goes on once the robot takes verbs again
    (:mod:`behaviours.overdue`). A driver that went away (``unavailable``) stops the
    episode, unless ``Params.wait_driver_s`` lets the behaviour wait for a driver under
    the same robot name: it then stays RUNNING while none serves, has the objects
    located again once one does (:func:`behaviours.resume.relocate`), and fails, so
    the step under way starts over from where the robot now stands.
    """

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name, robot)
        self._robot = robot
        self._future: Future[Any] | None = None
        self._skip: Status | None = None
        self._lost: _Lost | None = None

    def initialise(self) -> None:
        self._future, self._skip, self._lost = None, None, None
        obj = self._object_at_hand()
        if obj is not None and obj in self.services.given_up:
            self.feedback_message = f"object {obj.index} was given up: no verb is sent for it"
            self._skip = Status.FAILURE
            return
        started = self.start()
        if isinstance(started, Status):
            self._skip = started
        else:
            self._future = started

    def update(self) -> Status:
        if self._skip is not None:
            return self._skip
        if self._lost is not None:
            return self._await_driver(self._lost)
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
                return self._driver_lost(exc)
            if exc.code == TIMEOUT:
                return self._unanswered(exc)
            return self.failed(exc)
        return self.finish(result)

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID:  # pre-empted: the results are no longer wanted
            for pending in (self._future, None if self._lost is None else self._lost.image):
                if pending is not None and not pending.done():
                    pending.cancel()
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

    def refused_out_of_range(self, exc: DriverError, procedure: str) -> bool:
        """True when the driver refused ``procedure`` as out of range and the robot is to
        re-approach and try it again: the step then fails without the verb counting as
        failed, and the next step's move drives to the same position, planned from where
        the camera last placed the robot. A refusal means nothing was tried: the robot
        stands off the position its dead reckoning claims (drift the look before the verb
        corrected, docs/simulator.md "Drift"), so counting it as a failed grasp would drop
        the right grasp, and counting it as an unusable test would lose every test at that
        position. Only when a look has corrected the pose since the robot arrived: else
        the same plan from the same pose would end where it stands, and the refusal counts
        as the verb failing, as it always did. Bounded by ``Params.reapproach_tries`` per
        procedure and object, after which it counts so too."""
        obj = self._object_at_hand()
        if exc.code != OUT_OF_RANGE or obj is None:
            return False
        if obj.reapproaches[procedure] >= self.services.params.reapproach_tries:
            return False
        if obj.arrived is not None and self.bb.pose == obj.arrived:
            return False  # nothing has corrected where the robot stands since it arrived
        obj.reapproaches[procedure] += 1
        obj.off_position = True
        obj.ledger.recoveries["re-approach"] += 1
        self.note(Event.REAPPROACH, procedure=procedure, tries=obj.reapproaches[procedure], message=exc.message)
        return True

    def _object_at_hand(self) -> ObjectRecord | None:
        return self.bb.get("object") if self.bb.exists("object") else None

    def _unanswered(self, exc: DriverError) -> Status:
        """The robot did not answer in time: what it measured or did is unknown, so the
        object at hand is given up (an object already handled stays handled)."""
        obj = self._object_at_hand()
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
        self._lost = _Lost(self.services.clock())
        self.feedback_message = f"driver for {self._robot} lost: waiting up to {wait_s:g} s for one to come back"
        return Status.RUNNING

    def _await_driver(self, lost: _Lost) -> Status:
        """Paused: wait for a driver, then look again (module docstring of :mod:`behaviours.resume`)."""
        services, wait_s = self.services, self.services.params.wait_driver_s
        driver = services.driver
        if lost.image is None:
            assert isinstance(driver, Reconnecting)
            if not driver.wait_ready(0.0):
                waited = services.clock() - lost.since
                if waited > wait_s:
                    raise DriverError(UNAVAILABLE, f"no driver for robot {self._robot} came back within {wait_s:g} s")
                return Status.RUNNING
            same_robot(services, self._robot)
            if self._object_at_hand() is None:  # nothing located yet: this verb (the first image) again
                self.initialise()
                return Status.RUNNING if self._skip is None else self._skip
            lost.image = driver.camera()
            self.feedback_message = "driver back: locating the objects again"
        if not lost.image.done():
            return Status.RUNNING
        try:
            image = lost.image.result()
        except DriverError as exc:
            if exc.code == UNAVAILABLE:  # gone again before it answered: wait again
                self._lost = _Lost(services.clock())
                return Status.RUNNING
            raise DriverError(UNAVAILABLE, f"driver for robot {self._robot} came back, but its camera failed: "
                              f"{exc}") from None
        waited = services.clock() - lost.since
        relocate(services, self._robot, image, f"driver for {self._robot} came back after {waited:.1f} s")
        self.feedback_message = "driver back, objects located again: the step starts over"
        return Status.FAILURE


@dataclass
class _Lost:
    """A verb lost with its driver: since when, and the image asked of the driver that came back."""

    since: float
    image: Future[CameraImage] | None = None
