"""A driver that records what it is asked and answers: the executive drives it as any
other ``Driver``, and each verb's result reaches the recorder when its future settles
(at once in process, on the reply thread over zenoh)."""

from __future__ import annotations

from collections.abc import Callable
from concurrent.futures import Future
from typing import Any

from camera_model.image import CameraImage
from recording.recorder import Recorder
from hero_driver.decorator import DriverDecorator, argument
from hero_driver.interface import Driver, DriverError, DriverVerb, MoveResult, RobotState, SenseResult


class RecordingDriver(DriverDecorator):
    """Forwards every verb to ``inner`` and records its result, whatever the verb (the
    verb table, :data:`~hero_driver.interface.DRIVER_VERBS`, says which take the robot's
    time and what they answer): a move as its planned and driven path, a sensing
    procedure as its sonar ray, an image as the camera, any state as where the robot
    stands; what nothing draws (a grasp's verdict) is seen and left. The verbs that
    fail are in the episode log, not drawn."""

    def __init__(self, inner: Driver, recorder: Recorder) -> None:
        super().__init__(inner)
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

    def call(self, verb: DriverVerb, method: Callable[..., Any], args: tuple[Any, ...],
             kwargs: dict[str, Any]) -> Any:
        if not verb.robot_time:
            return method(*args, **kwargs)
        from_where = verb.result in (MoveResult, SenseResult)  # drawn from where the robot stood
        before = self.known_state() if from_where else None
        planned = tuple(argument(verb, args, kwargs, "waypoints") or ()) if verb.result is MoveResult else ()
        future: Future[Any] = method(*args, **kwargs)
        if from_where and before is None:
            return future
        future.add_done_callback(lambda settled: self._record(settled, before, planned))
        return future

    def _record(self, settled: Future[Any], before: RobotState | None, planned: tuple[Any, ...]) -> None:
        if settled.cancelled() or settled.exception() is not None:
            return
        result = settled.result()
        if isinstance(result, MoveResult) and before is not None:
            self.recorder.move(before.pose, planned, result, before.clock_s)
        elif isinstance(result, SenseResult) and before is not None:
            self.recorder.sense(before.pose, result, before.clock_s)
        elif isinstance(result, CameraImage):
            self.recorder.camera(result, result.clock_s)
        elif isinstance(result, RobotState):
            self.recorder.state(result)
