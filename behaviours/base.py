"""Base classes: a behaviour on the executive's blackboard, and one that waits on the robot.

Robot verbs take seconds to minutes, so a behaviour starts the verb in ``initialise``
and watches its future in ``update``, returning RUNNING meanwhile: the tree keeps
ticking (and could pre-empt) instead of blocking inside one behaviour.
"""

from __future__ import annotations

import abc
from concurrent.futures import Future
from typing import Any

import py_trees
from py_trees.common import Access, Status

from behaviours.context import ObjectRecord, Services
from hero_driver.interface import UNAVAILABLE, DriverError


class CslBehaviour(py_trees.behaviour.Behaviour):
    """A behaviour with the executive's services and read/write access to the object."""

    def __init__(self, name: str, services: Services) -> None:
        super().__init__(name)
        self.services = services
        self.bb = self.attach_blackboard_client(name=name, namespace=services.namespace)
        self.bb.register_key("object", access=Access.WRITE)

    @property
    def obj(self) -> ObjectRecord:
        return self.bb.object

    def note(self, kind: str, **data: object) -> None:
        """Report an event to the episode log, tagged with the object."""
        self.services.log.event(kind, object=self.obj.index, behaviour=self.name, **data)


class DriverAction(CslBehaviour):
    """Starts one driver verb and reports RUNNING until its future completes."""

    def __init__(self, name: str, services: Services) -> None:
        super().__init__(name, services)
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
            self.note("driver_error", code=exc.code, message=exc.message)
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
