"""Dead reckoning corrected by the overhead camera.

A wheeled base's odometry drifts: wheel slip it cannot sense moves the base while the
pose it reports stays put (docs/simulator.md, "Drift": about 1 in per axis over an
episode under the ``paper`` preset). The 6 in procedures accept the object within
1.5 in of their range, so a drift of that size makes the driver refuse every procedure
at a test position the executive believes it stands at (a refused procedure is
re-approached only once a look has corrected that belief,
the re-approach branch, :mod:`behaviours.reapproach`). The overhead camera sees
where the robot really is; that is the correction.

The executive drives its driver through :class:`CameraLocalised`, which keeps an
*offset*, the camera's robot position less the driver's reported one. Every pose the
driver reports (a move's end, its state, the dock, a blocking obstacle) comes out
shifted by the offset, and every waypoint and face point sent goes in shifted back, so
plans, regions and poses share the camera's frame. Behaviours call :meth:`localise`
with the robot's position in each new image (:meth:`CslBehaviour.look`); the offset
changes only when the image places the robot more than ``deadband_in`` from where the
corrected pose says, since smaller differences are the camera's own error (well under
the drift in the simulator under the ``paper`` preset: BENCHMARKS.md, "Dead
reckoning"), and a robot that does not drift must never be moved by camera noise. Heading is left to the driver (the drift model has none,
and the sonar centring faces the object).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from hero_driver.decorator import DriverDecorator, mapped, poses_in, poses_out
from hero_driver.interface import Driver, DriverVerb, Pose

DEADBAND_IN = 0.5
"""A camera position nearer than this to the corrected pose leaves the offset alone."""


class CameraLocalised(DriverDecorator):
    """``inner`` with its poses in the overhead camera's frame (the module docstring
    says how): every argument and result the verb table
    (:data:`~hero_driver.interface.DRIVER_VERBS`) names as a pose is shifted, whatever
    the verb. Everything else a driver offers is ``inner``'s."""

    def __init__(self, inner: Driver, deadband_in: float = DEADBAND_IN) -> None:
        super().__init__(inner)
        self.deadband_in = deadband_in
        self.offset: tuple[float, float] = (0.0, 0.0)

    def call(self, verb: DriverVerb, method: Callable[..., Any], args: tuple[Any, ...],
             kwargs: dict[str, Any]) -> Any:
        if verb.name == "reset":
            self.offset = (0.0, 0.0)  # a restored world starts with the robot where it says
        dx, dy = self.offset
        args, kwargs = poses_in(verb, args, kwargs, -dx, -dy)
        answer = method(*args, **kwargs)
        if not verb.poses_out:
            return answer
        if verb.robot_time:
            return mapped(answer, lambda result: poses_out(verb, result, dx, dy))
        return poses_out(verb, answer, dx, dy)

    def to_camera(self, pose: Pose) -> Pose:
        """A pose the driver reported, in the camera's frame."""
        return Pose(pose.x_in + self.offset[0], pose.y_in + self.offset[1], pose.heading_deg)

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
