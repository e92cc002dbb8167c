"""The two loops of an episode, as decorators so they show in the tree.

``ForEachObject`` runs the per-object subtree once for each object located;
``UntilHandled`` repeats one recognition step until the object is grasped (or left, or
given up on). Everything that happens within a step is an ordinary composite.
"""

from __future__ import annotations

import py_trees
from py_trees.common import Access, Status

from behaviours.context import Services


class ForEachObject(py_trees.decorators.Decorator):
    """Re-run the child for every object still queued; succeed when none is left."""

    def __init__(self, child: py_trees.behaviour.Behaviour, services: Services, name: str = "ForEachObject") -> None:
        super().__init__(name=name, child=child)
        self.bb = self.attach_blackboard_client(name=name, namespace=services.namespace)
        self.bb.register_key("objects", access=Access.READ)

    def update(self) -> Status:
        if self.decorated.status == Status.RUNNING:
            return Status.RUNNING
        if self.bb.objects:
            self.feedback_message = f"{len(self.bb.objects)} objects left"
            return Status.RUNNING  # the child starts afresh on the next object
        return Status.SUCCESS


class UntilHandled(py_trees.decorators.Decorator):
    """Repeat a recognition step until the object is handled or the step budget is spent.

    A step that fails has merely not made progress (an unreliable value, say); the next
    one decides afresh. Per-step choices are cleared between steps; per-node state (an
    unreliable value awaiting reselection) stays with the object.
    """

    def __init__(self, child: py_trees.behaviour.Behaviour, services: Services,
                 name: str = "UntilHandled") -> None:
        super().__init__(name=name, child=child)
        self.services = services
        self.bb = self.attach_blackboard_client(name=name, namespace=services.namespace)
        self.bb.register_key("object", access=Access.WRITE)

    def update(self) -> Status:
        if self.decorated.status == Status.RUNNING:
            return Status.RUNNING
        obj = self.bb.object
        obj.steps += 1
        if obj.done:
            return Status.SUCCESS if obj.outcome != "failed" else Status.FAILURE
        if obj.steps >= self.services.params.max_steps:
            obj.outcome = "failed"
            self.services.log.event("gave_up", object=obj.index, reason=f"{obj.steps} steps")
            return Status.FAILURE
        obj.test, obj.values, obj.no_alternative, obj.attempt = None, None, False, None
        return Status.RUNNING
