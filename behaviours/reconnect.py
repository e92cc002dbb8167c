"""A driver lost mid-episode: wait for one under the same robot name, then look again.

A driver process that dies (its zenoh liveliness token goes) and is restarted under
the same robot name may have lost track of the world (``csl run --wait-driver``,
docs/reliability.md). The verb under way fails ``unavailable``; with
``Params.wait_driver_s`` and a driver that can come back
(:class:`~behaviours.resume.Reconnecting`), its behaviour records the loss
(``DRIVER_LOST``, :class:`~behaviours.base.DriverAction`) and stays RUNNING. At the top
of the tree, the lost-driver guard (py_trees' guard idiom, as the battery check) then
pauses the work, with its place kept (:class:`~behaviours.guard.KeepPlace`), and
runs a branch that ``csl bt`` shows::

    driver check
      until back
        reconnect
          DriverLost?       a verb was lost with its driver, no driver back for it yet
          WaitForDriver     until one serves the robot (else, past the wait: the episode stops)
          LocateAgain       an overhead image; the objects located again (behaviours.resume)
      keep place            the work, paused meanwhile

Once the objects are located again (``DRIVER_BACK``) the work resumes and the lost
verb's behaviour fails, so the step under way starts over from where the robot now
stands; lost before anything was located (the first image), it sends its verb again.
A driver gone again before its image came is waited for again. No driver within the
wait, one that serves another robot profile, or one whose camera fails, stops the
episode with one line, as a lost driver does without the wait.
"""

from __future__ import annotations

from typing import Any
from concurrent.futures import Future

import py_trees
from py_trees.common import Access, Status
from py_trees.composites import Selector, Sequence

from behaviours.base import CslBehaviour
from behaviours.guard import KeepPlace
from behaviours.records import DRIVER_BACK, DRIVER_LOST, LostVerb
from behaviours.resume import Reconnecting, relocate, same_robot
from hero_driver.interface import UNAVAILABLE, DriverError


class DriverLost(CslBehaviour):
    """Condition ``DriverLost?``: a verb was lost with its driver and no driver has come
    back for it yet; ``fired`` tells the paused work (``KeepPlace``) it is paused."""

    def __init__(self, robot: str, name: str = "DriverLost?") -> None:
        super().__init__(name, robot)
        self.bb.register_key(DRIVER_LOST, access=Access.READ)
        self.bb.register_key(DRIVER_BACK, access=Access.READ)
        self.fired = False

    def update(self) -> Status:
        lost = self.lost()
        back = self.bb.get(DRIVER_BACK) if self.bb.exists(DRIVER_BACK) else None
        self.fired = lost is not None and back is not lost
        self.feedback_message = (f"{lost.behaviour}'s verb lost with its driver" if self.fired and lost is not None
                                 else "driver here")
        return Status.SUCCESS if self.fired else Status.FAILURE

    def lost(self) -> LostVerb | None:
        return self.bb.get(DRIVER_LOST) if self.bb.exists(DRIVER_LOST) else None


class WaitForDriver(CslBehaviour):
    """RUNNING until a driver serves the robot again, for up to ``Params.wait_driver_s``
    since the verb was lost (since it went again, the second time); past that the
    episode stops (``DriverError`` ``unavailable``), as when the driver answers for
    another robot profile (:func:`~behaviours.resume.same_robot`)."""

    def __init__(self, robot: str, lost: DriverLost, name: str = "WaitForDriver") -> None:
        super().__init__(name, robot)
        self._robot, self._condition = robot, lost
        self._for: LostVerb | None = None
        self.since = 0.0  # read by LocateAgain: how long the robot was without a driver

    def initialise(self) -> None:
        lost = self._condition.lost()
        assert lost is not None
        if self._for is lost:  # gone again before the objects were located: wait afresh
            self.since = self.services.clock()
        else:
            self._for, self.since = lost, lost.since

    def update(self) -> Status:
        services, wait_s = self.services, self.services.params.wait_driver_s
        driver = services.driver
        assert isinstance(driver, Reconnecting)  # DriverAction records a loss only for one
        if not driver.wait_ready(0.0):
            if services.clock() - self.since > wait_s:
                raise DriverError(UNAVAILABLE, f"no driver for robot {self._robot} came back within {wait_s:g} s")
            self.feedback_message = f"no driver for {self._robot}: waiting up to {wait_s:g} s"
            return Status.RUNNING
        same_robot(services, self._robot)
        self.feedback_message = f"a driver for {self._robot} is back"
        return Status.SUCCESS


class LocateAgain(CslBehaviour):
    """An overhead image from the driver that came back and the objects located again
    (:func:`~behaviours.resume.relocate`); with nothing located yet, nothing to do (the
    first image is asked again by its own behaviour). Marks the loss handled
    (``DRIVER_BACK``); fails when the driver went again before the image came."""

    def __init__(self, robot: str, waiting: WaitForDriver, name: str = "LocateAgain") -> None:
        super().__init__(name, robot)
        self.bb.register_key(DRIVER_LOST, access=Access.READ)
        self.bb.register_key(DRIVER_BACK, access=Access.WRITE)
        self._robot, self._waiting = robot, waiting
        self._image: Future[Any] | None = None

    def initialise(self) -> None:
        located = self.object_at_hand() is not None
        self._image = self.services.perception.look() if located else None

    def update(self) -> Status:
        services, robot = self.services, self._robot
        if self._image is not None:
            if not self._image.done():
                return Status.RUNNING
            try:
                image = self._image.result()
            except DriverError as exc:
                if exc.code == UNAVAILABLE:
                    self.feedback_message = f"driver for {robot} gone again before it answered"
                    return Status.FAILURE  # "until back" waits again
                raise DriverError(UNAVAILABLE, f"driver for robot {robot} came back, but its {services.perception.verb} failed: "
                                  f"{exc}") from None
            waited = services.clock() - self._waiting.since
            relocate(services, robot, image, f"driver for {robot} came back after {waited:.1f} s")
        self.bb.set(DRIVER_BACK, self.bb.get(DRIVER_LOST))
        self.feedback_message = "driver back" if self._image is None else "driver back, objects located again"
        return Status.SUCCESS

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self._image is not None and not self._image.done():
            self._image.cancel()  # pre-empted: the image is no longer wanted


class UntilBack(py_trees.decorators.Decorator):
    """The reconnect branch, RUNNING until its work is done: when a driver is back and
    the objects located again (the work resumes at the next tick, when ``DriverLost?``
    fails), and while the driver went again before they were (it is waited for again)."""

    def __init__(self, child: py_trees.behaviour.Behaviour, lost: DriverLost, name: str = "until back") -> None:
        super().__init__(name=name, child=child)
        self.lost = lost

    def update(self) -> Status:
        status = self.decorated.status
        if status == Status.SUCCESS or (status == Status.FAILURE and self.lost.fired):
            return Status.RUNNING
        return status


def reconnecting(work: py_trees.behaviour.Behaviour, robot: str) -> py_trees.behaviour.Behaviour:
    """``work`` under the lost-driver guard (the module docstring says how it behaves)."""
    lost = DriverLost(robot)
    waiting = WaitForDriver(robot, lost)
    reconnect = Sequence("reconnect", memory=True, children=[lost, waiting, LocateAgain(robot, waiting)])
    return Selector("driver check", memory=False, children=[UntilBack(reconnect, lost), KeepPlace(work, lost)])
