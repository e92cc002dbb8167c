"""The episode loop: each object in turn, and recognition steps until it is handled.

``ForEachObject`` runs the per-object subtree once for each object located;
``StartObject`` opens an object's record and run-time session; ``UntilHandled``
repeats one recognition step until the object is grasped (or left, or given up on),
replacing the step record before each step. Everything within a step is an ordinary
composite.
"""

from __future__ import annotations

from typing import Any

import py_trees
from py_trees.common import Access, Status

from behaviours.appearance import appearance_of
from behaviours.base import CslBehaviour, receive_services
from behaviours.bridge import PlannerMoveCost
from behaviours.events import Event
from behaviours.records import ObjectRecord, Step
from behaviours.sameness import PUSHED_IN
from behaviours.services import Services, namespace
from learner.position import Position
from learner.runtime import RecognitionSession
from planner import Region


class ForEachObject(py_trees.decorators.Decorator):
    """Re-run the child for every object still queued; succeed when none is left."""

    def __init__(self, child: py_trees.behaviour.Behaviour, robot: str, name: str = "ForEachObject") -> None:
        super().__init__(name=name, child=child)
        self.bb = self.attach_blackboard_client(name=name, namespace=namespace(robot))
        self.bb.register_key("objects", access=Access.READ)

    def update(self) -> Status:
        if self.decorated.status == Status.RUNNING:
            return Status.RUNNING
        if self.bb.objects:
            self.feedback_message = f"{len(self.bb.objects)} objects left"
            return Status.RUNNING  # the child starts afresh on the next object
        return Status.SUCCESS


def open_session(services: Services, region: Region, estimator: PlannerMoveCost, start: Position,
                 index: int) -> RecognitionSession:
    """Object ``index``'s run-time tree for ``region`` from ``start``, with what the camera
    measured of it (round, area, elongation) and the episode's control parameters: the
    object loop opens one per object, and a disturbance that swapped the object opens
    a fresh one (behaviours.disturbance.StartAfresh)."""
    params = services.params
    return RecognitionSession(services.library.current(), services.criterion, estimator, start,
                              max_alternatives=params.max_alternatives, orientation_free=region.round,
                              seed=params.seed + index, appearance=appearance_of(region),
                              use_appearance=params.use_appearance)


class StartObject(CslBehaviour):
    """Start on the next object: remember its appearance (pixel count, for the side-effect
    check) and open its run-time tree from where the robot stands, handing the learner
    what the camera measured (round, area, elongation) to rule candidates out for free."""

    def __init__(self, robot: str, name: str = "RememberAppearance") -> None:
        super().__init__(name, robot)
        self.bb.register_key("objects", access=Access.WRITE)
        self.bb.register_key("results", access=Access.WRITE)

    def update(self) -> Status:
        if not self.bb.objects:
            return Status.FAILURE
        region: Region = self.bb.objects.pop(0)
        services = self.services
        began = services.clock()
        estimator = PlannerMoveCost(services.navigator, region, beam_check=services.params.beam_check,
                                    same_within_in=PUSHED_IN)
        start = estimator.stand_at(self.robot_pose())
        session = open_session(services, region, estimator, start, len(self.bb.results))
        appearance, use_appearance = session.appearance, services.params.use_appearance
        record = ObjectRecord(len(self.bb.results), region, region.pixel_count, session, estimator,
                              first_region=region)
        record.ledger.computing_s += services.clock() - began
        self.bb.object, self.bb.step = record, Step()
        self.bb.results.append(record)
        seen = {} if appearance is None or not use_appearance else {
            "appearance": appearance.to_json(), "ruled_out": len(session.unlike_rows()),
            **({"appearance_ignored": True} if session.appearance_ignored else {})}
        self.note(Event.OBJECT, centroid=[round(c, 1) for c in region.centroid], pixels=region.pixel_count,
                  start=start.to_json(), **seen, **({"cluster": True} if region.cluster else {}))
        return Status.SUCCESS


class UntilHandled(py_trees.decorators.Decorator):
    """Repeat a recognition step until the object is handled or the step budget is spent.

    A step that fails has merely not made progress (an unreliable value, say); the next
    one decides afresh with a new step record. What belongs to the node (an unreliable
    value awaiting reselection) stays with the object's session.
    """

    def __init__(self, child: py_trees.behaviour.Behaviour, robot: str, name: str = "UntilHandled") -> None:
        super().__init__(name=name, child=child)
        self.bb = self.attach_blackboard_client(name=name, namespace=namespace(robot))
        self.bb.register_key("object", access=Access.WRITE)
        self.bb.register_key("step", access=Access.WRITE)
        self._services: Services | None = None

    def setup(self, **kwargs: Any) -> None:
        self._services = receive_services(self, kwargs)

    def update(self) -> Status:
        if self.decorated.status == Status.RUNNING:
            return Status.RUNNING
        if self._services is None:
            raise RuntimeError(f"{self.name}: ticked before setup(services=...)")
        obj: ObjectRecord = self.bb.object
        obj.steps += 1
        if obj.done:
            return Status.SUCCESS if obj.outcome != "failed" else Status.FAILURE
        if obj.steps >= self._services.params.max_steps:
            obj.finish("failed")
            self._services.log.event(Event.GAVE_UP, object=obj.index, behaviour=self.name,
                                     reason=f"{obj.steps} steps")
            return Status.FAILURE
        self.bb.step = Step()
        return Status.RUNNING
