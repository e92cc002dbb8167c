"""Dead reckoning corrected by the overhead camera.

A wheeled base's odometry drifts: wheel slip it cannot sense moves the base while the
pose it reports stays put (docs/simulator.md, "Drift": about 1 in per axis over an
episode under the ``paper`` preset). The 6 in procedures accept the object within
1.5 in of their range, so a drift of that size makes the driver refuse every procedure
at a test position the executive believes it stands at (a refused procedure is
re-approached only once a look has corrected that belief,
:meth:`behaviours.base.DriverAction.refused_out_of_range`). The overhead camera sees
where the robot really is; that is the correction.

The executive drives its driver through :class:`CameraLocalised`, which keeps an
*offset*, the camera's robot position less the driver's reported one. Every pose the
driver reports (a move's end, its state, the dock, a blocking obstacle) comes out
shifted by the offset, and every waypoint and face point sent goes in shifted back, so
plans, regions and poses share the camera's frame. Behaviours call :meth:`localise`
with the robot's position in each new image (:meth:`CslBehaviour.look`); the offset
changes only when the image places the robot more than ``deadband_in`` from where the
corrected pose says, since smaller differences are the camera's own error (measured in
the simulator under the ``paper`` preset: 0.07 in median, 0.25 in at most, against a
drift of 0.54 in median and 1.55 in at most), and a robot that does not drift must
never be moved by camera noise. Heading is left to the driver (the drift model has none,
and the sonar centring faces the object).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from concurrent.futures import Future
from dataclasses import replace
from typing import Any, TypeVar

from hero_driver.interface import Driver, MoveResult, Obstacle, Pose, RobotState

DEADBAND_IN = 0.5
"""A camera position nearer than this to the corrected pose leaves the offset alone."""

A = TypeVar("A")
B = TypeVar("B")


def mapped(future: Future[A], fn: Callable[[A], B]) -> Future[B]:
    """A future settled with ``fn`` of ``future``'s result, or with its exception."""
    out: Future[B] = Future()

    def done(f: Future[A]) -> None:
        try:
            out.set_result(fn(f.result()))
        except BaseException as exc:  # noqa: BLE001 (the driver's error, handed on as it came)
            out.set_exception(exc)

    future.add_done_callback(done)
    return out


class CameraLocalised:
    """``inner`` with its poses in the overhead camera's frame (the module docstring
    says how). The optional features' verbs (``dock``, ``charge``, ``wait``) and
    everything else a driver offers are ``inner``'s, shifted where they carry a pose."""

    def __init__(self, inner: Driver, deadband_in: float = DEADBAND_IN) -> None:
        self.inner = inner
        self.robot = inner.robot
        self.deadband_in = deadband_in
        self.offset: tuple[float, float] = (0.0, 0.0)

    def __getattr__(self, name: str) -> Any:
        if name == "inner":  # not set yet (copying, unpickling): no recursion through inner
            raise AttributeError(name)
        verb = getattr(self.inner, name)
        if name == "dock":
            return lambda: None if (at := verb()) is None else self.to_camera(at)
        if name in ("charge", "wait"):
            return lambda *args: mapped(verb(*args), self._state)
        return verb

    # -- the two frames ------------------------------------------------------------------
    def to_camera(self, pose: Pose) -> Pose:
        """A pose the driver reported, in the camera's frame."""
        return Pose(pose.x_in + self.offset[0], pose.y_in + self.offset[1], pose.heading_deg)

    def to_driver(self, pose: Pose) -> Pose:
        """A pose in the camera's frame, as the driver reckons it."""
        return Pose(pose.x_in - self.offset[0], pose.y_in - self.offset[1], pose.heading_deg)

    def localise(self, seen_x_in: float, seen_y_in: float) -> bool:
        """The camera saw the robot's centre at (``seen_x_in``, ``seen_y_in``): take it
        for the truth when it is more than ``deadband_in`` from the corrected pose.
        True when the offset changed."""
        reported = self.inner.state().pose
        believed = self.to_camera(reported)
        if math.hypot(seen_x_in - believed.x_in, seen_y_in - believed.y_in) <= self.deadband_in:
            return False
        self.offset = (seen_x_in - reported.x_in, seen_y_in - reported.y_in)
        return True

    def _state(self, state: RobotState) -> RobotState:
        return replace(state, pose=self.to_camera(state.pose))

    # -- the verbs -----------------------------------------------------------------------
    def state(self) -> RobotState:
        return self._state(self.inner.state())

    def move(self, waypoints: Sequence[Pose], face: tuple[float, float] | None = None) -> Future[MoveResult]:
        dx, dy = self.offset
        sent = [Pose(w.x_in - dx, w.y_in - dy, w.heading_deg) for w in waypoints]
        toward = None if face is None else (face[0] - dx, face[1] - dy)

        def back(result: MoveResult) -> MoveResult:
            b = result.blocked
            return replace(result, pose=Pose(result.pose.x_in + dx, result.pose.y_in + dy, result.pose.heading_deg),
                           blocked=None if b is None else Obstacle(b.x_in + dx, b.y_in + dy, b.radius_in))

        return mapped(self.inner.move(sent, toward), back)

    def sense(self, procedure: str) -> Future[Any]:
        return self.inner.sense(procedure)

    def grasp(self, procedure: str) -> Future[Any]:
        return self.inner.grasp(procedure)

    def release(self) -> Future[RobotState]:
        return mapped(self.inner.release(), self._state)

    def camera(self) -> Future[Any]:
        return self.inner.camera()

    def reset(self, world: str | None = None, seed: int | None = None) -> Future[RobotState]:
        self.offset = (0.0, 0.0)  # a restored world starts with the robot where it says
        return mapped(self.inner.reset(world, seed), self._state)

    def close(self) -> None:
        self.inner.close()
