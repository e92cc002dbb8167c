"""After a verb went unanswered: wait for the robot to take verbs again.

When the executive stops waiting for a verb (its client timeout), the driver may still
be working on it until its own bound, and refuses every other verb as ``busy`` until
then (docs/driver-protocol.md, "Bounds"). Failing those verbs would fail every object
after the one that timed out, for nothing but the robot finishing what it was told.
So the executive drives the robot through :class:`OverdueRobot`: while a verb of ours
timed out and no verb has been accepted since, a ``busy`` refusal is the robot still
finishing that verb, and the refused verb is sent again a moment later, until the robot
takes it or ``wait_s`` has passed since the timeout (then it fails with ``timeout``,
as the robot did not answer in time). A ``busy`` with nothing overdue is someone else
driving the robot and fails as before.

The same request is sent again, not rebuilt: a behaviour's ``start`` may decide things
(a grasp's other end, a learn) that must happen once.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable, Sequence
from concurrent.futures import Future, InvalidStateError
from typing import Any

from camera_model.image import CameraImage
from hero_driver.interface import (
    BUSY, TIMEOUT, Driver, DriverError, GraspResult, MoveResult, Pose, RobotState, SenseResult,
)

RETRY_S = 0.25  # between two tries of a verb the robot refused as busy


class OverdueRobot:
    """``inner`` with the verbs it refuses as ``busy`` after a timeout sent again (the
    module docstring says when). Everything else a driver offers (its ``dock``,
    ``alive``, the simulator's ``truth``) is ``inner``'s."""

    def __init__(self, inner: Driver, wait_s: float, *, clock: Callable[[], float] = time.monotonic,
                 retry_s: float = RETRY_S) -> None:
        self.inner = inner
        self.robot = inner.robot
        self.wait_s = wait_s
        self.retry_s = retry_s
        self._clock = clock
        self._lock = threading.Lock()
        self._overdue: tuple[str, float] | None = None  # the verb that went unanswered, and when

    @property
    def overdue(self) -> str | None:
        """The verb the robot may still be working on (None: the robot answered since)."""
        with self._lock:
            return None if self._overdue is None else self._overdue[0]

    def __getattr__(self, name: str) -> Any:
        if name == "inner":  # not set yet (copying, unpickling): no recursion through inner
            raise AttributeError(name)
        if name == "charge":  # the battery feature's verb, when ``inner`` has it
            charge = getattr(self.inner, "charge")
            return lambda: self._send("charge", charge)
        return getattr(self.inner, name)

    def state(self) -> RobotState:
        return self.inner.state()

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        sent = list(waypoints)
        return self._send("move", lambda: self.inner.move(sent, face))

    def sense(self, procedure: str) -> Future[SenseResult]:
        return self._send("sense", lambda: self.inner.sense(procedure))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return self._send("grasp", lambda: self.inner.grasp(procedure))

    def release(self) -> Future[RobotState]:
        return self._send("release", self.inner.release)

    def camera(self) -> Future[CameraImage]:
        return self._send("camera", self.inner.camera)

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        return self._send("reset", lambda: self.inner.reset(world, seed))

    def close(self) -> None:
        self.inner.close()

    def _send(self, verb: str, call: Callable[[], Future[Any]]) -> Future[Any]:
        """``call`` once; its future, or one that follows its tries while the robot is
        busy finishing an overdue verb. A driver that settles its futures at once (the
        in-process simulator) gets back a settled future, so ticks stay deterministic."""
        outer: Future[Any] = Future()
        self._try(verb, call, outer)
        return outer

    def _try(self, verb: str, call: Callable[[], Future[Any]], outer: Future[Any]) -> None:
        if outer.cancelled():
            return  # the behaviour no longer wants it
        try:
            inner = call()
        except DriverError as exc:  # a driver may refuse before it returns a future
            self._settle(verb, call, outer, exc, None)
            return
        inner.add_done_callback(lambda done: self._done(verb, call, outer, done))

    def _done(self, verb: str, call: Callable[[], Future[Any]], outer: Future[Any], done: Future[Any]) -> None:
        if done.cancelled():
            _complete(outer, lambda: outer.cancel())
            return
        error = done.exception()
        if error is not None and not isinstance(error, DriverError):
            _complete(outer, lambda: outer.set_exception(error))
            return
        self._settle(verb, call, outer, error, None if error is not None else done.result())

    def _settle(self, verb: str, call: Callable[[], Future[Any]], outer: Future[Any], error: DriverError | None,
                result: object) -> None:
        now = self._clock()
        with self._lock:
            overdue = self._overdue
            if error is None or error.code not in (BUSY, TIMEOUT):
                self._overdue = None  # the robot took a verb: nothing is overdue any more
            elif error.code == TIMEOUT:
                self._overdue = (verb, now)
        if error is None:
            _complete(outer, lambda: outer.set_result(result))
            return
        if error.code == BUSY and overdue is not None:
            waited = now - overdue[1]
            if waited < self.wait_s:
                timer = threading.Timer(self.retry_s, self._try, (verb, call, outer))
                timer.daemon = True
                timer.start()
                return
            error = DriverError(TIMEOUT, f"{verb}: the robot was still busy {waited:.0f} s after "
                                f"{overdue[0]} went unanswered")
        failure = error
        _complete(outer, lambda: outer.set_exception(failure))


def _complete(future: Future[Any], settle: Callable[[], object]) -> None:
    try:
        settle()
    except InvalidStateError:
        pass  # cancelled by the behaviour meanwhile
