"""A driver that records what it is asked and answers: the executive drives it as any
other ``Driver``, and each verb's result reaches the recorder when its future settles
(at once in process, on the reply thread over zenoh)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import Future
from typing import TypeVar

from camera_model.image import CameraImage
from executive.recording.recorder import Recorder
from hero_driver.interface import Driver, DriverError, GraspResult, MoveResult, Pose, RobotState, SenseResult

T = TypeVar("T")


class RecordingDriver:
    """Forwards every verb to ``inner`` and records its result (the verbs that fail are
    in the episode log, not drawn)."""

    def __init__(self, inner: Driver, recorder: Recorder) -> None:
        self.inner = inner
        self.robot = inner.robot
        self.recorder = recorder
        self._known: RobotState | None = None

    def known_state(self) -> RobotState | None:
        """The driver's state, or the last one it gave while it has none (over zenoh:
        not published yet, or the driver gone). The recording never raises for the
        robot: the episode reports a lost driver, in its own words."""
        try:
            self._known = self.inner.state()
        except DriverError:
            pass
        return self._known

    def __getattr__(self, name: str) -> object:
        """What a particular driver offers beyond the protocol (the simulator's
        ``truth``, the zenoh client's ``profile``) stays reachable."""
        return getattr(self.inner, name)

    def _then(self, future: Future[T], record: Callable[[T], None]) -> Future[T]:
        def done(settled: Future[T]) -> None:
            if not settled.cancelled() and settled.exception() is None:
                record(settled.result())

        future.add_done_callback(done)
        return future

    def state(self) -> RobotState:
        return self.inner.state()

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        before = self.known_state()
        planned = tuple(waypoints)
        future = self.inner.move(waypoints, face)
        if before is None:
            return future
        return self._then(future, lambda result: self.recorder.move(before.pose, planned, result, before.clock_s))

    def sense(self, procedure: str) -> Future[SenseResult]:
        before = self.known_state()
        future = self.inner.sense(procedure)
        if before is None:
            return future
        return self._then(future, lambda result: self.recorder.sense(before.pose, result, before.clock_s))

    def grasp(self, procedure: str) -> Future[GraspResult]:
        return self.inner.grasp(procedure)

    def release(self) -> Future[RobotState]:
        return self._then(self.inner.release(), self.recorder.state)

    def camera(self) -> Future[CameraImage]:
        return self._then(self.inner.camera(), lambda image: self.recorder.camera(image, image.clock_s))

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        return self._then(self.inner.reset(world, seed), self.recorder.state)

    def close(self) -> None:
        self.inner.close()
