"""Each robot verb on Python's ``logging``: what was sent, and how long the robot took
to answer (``csl -v``).

The executive sends every verb through :class:`VerbLog`, innermost, right over the
driver it was given: a line says what the driver was asked (in the driver's own frame)
and when its reply came, and a verb sent again after a ``busy`` refusal is a line each
time it is sent. The reply time is the wall clock's, the one number a person watching a
robot wants and an episode log must not hold; the robot's own seconds follow it where
the reply has them. Verbs answered at once from what the driver knows (``state``,
``dock``) are not told: the tree asks for them at every tick.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Future
from typing import Any

from camera_model.image import CameraImage
from hero_driver.decorator import DriverDecorator
from hero_driver.interface import (Driver, DriverError, DriverVerb, GraspResult, MoveResult, Pose, RobotState,
                                   SenseResult)

log = logging.getLogger(__name__)


class VerbLog(DriverDecorator):
    """``inner`` with every verb that takes the robot's time told on the log: at DEBUG
    when sent, at INFO when answered (with its reply time) or refused."""

    def __init__(self, inner: Driver, clock: Callable[[], float] = time.perf_counter) -> None:
        super().__init__(inner)
        self._clock = clock

    def call(self, verb: DriverVerb, method: Callable[..., Any], args: tuple[Any, ...],
             kwargs: dict[str, Any]) -> Any:
        if not verb.robot_time or not log.isEnabledFor(logging.INFO):
            return method(*args, **kwargs)
        said = verb.name + _arguments(verb, args, kwargs)
        log.debug("%s: %s sent", self.robot, said)
        start = self._clock()
        try:
            future: Future[Any] = method(*args, **kwargs)
        except DriverError as exc:  # a driver may refuse before it returns a future
            log.info("%s: %s refused at once: %s", self.robot, said, exc)
            raise
        future.add_done_callback(lambda done: self._answered(said, done, self._clock() - start))
        return future

    def _answered(self, said: str, done: Future[Any], wall_s: float) -> None:
        if done.cancelled():
            log.info("%s: %s cancelled after %.3f s", self.robot, said, wall_s)
            return
        error = done.exception()
        if error is not None:
            log.info("%s: %s failed after %.3f s: %s", self.robot, said, wall_s, error)
            return
        reply = _reply(done.result())
        log.info("%s: %s answered in %.3f s%s", self.robot, said, wall_s, f": {reply}" if reply else "")


def _arguments(verb: DriverVerb, args: Sequence[Any], kwargs: Mapping[str, Any]) -> str:
    named = {**dict(zip(verb.args, args)), **kwargs}
    given = [f"{name} {_value(value)}" for name, value in named.items() if value is not None]
    return f" ({', '.join(given)})" if given else ""


def _value(value: Any) -> str:
    """A pose as (x, y, heading°), a path as its length and goal, a point as (x, y)."""
    if isinstance(value, Pose):
        return f"({value.x_in:.1f}, {value.y_in:.1f}, {value.heading_deg:.1f}°)"
    if isinstance(value, (list, tuple)) and value and all(isinstance(p, Pose) for p in value):
        return f"{len(value)} to {_value(value[-1])}"
    if isinstance(value, (list, tuple)) and all(isinstance(v, (int, float)) for v in value):
        return "(" + ", ".join(f"{v:.1f}" for v in value) + ")"
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _reply(result: object) -> str:
    """What the robot answered, in a few words: the robot's seconds first."""
    if isinstance(result, MoveResult):
        stopped = " (collided)" if result.collided else " (blocked)" if result.blocked is not None else ""
        return f"{result.duration_s:.1f} robot s, at {_value(result.pose)}{stopped}"
    if isinstance(result, SenseResult):
        values = ", ".join(f"{f} {'none' if v is None else f'{v:g}'}" for f, v in result.values.items())
        return f"{result.duration_s:.1f} robot s, {values or 'no values'}"
    if isinstance(result, GraspResult):
        return f"{result.duration_s:.1f} robot s, {'held' if result.success else 'not held'}"
    if isinstance(result, RobotState):
        return f"at {_value(result.pose)}, battery {result.battery:.2f}"
    if isinstance(result, CameraImage):
        height, width = result.pixels.shape[:2]
        return f"{width}x{height} image"
    return ""
