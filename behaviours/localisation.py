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
reckoning"), and a robot that does not drift must never be moved by camera noise. The
camera leaves the heading to the driver (the lab's drift model has none, and the sonar
centring faces the object). Without a ceiling camera the onboard scan matcher places
the robot instead (``executive.onboard``), heading and all: a home's base drifts in
heading too, and the correction then turns as well as shifts.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from hero_driver.decorator import DriverDecorator, mapped, poses_in, poses_out, translated
from hero_driver.interface import Driver, DriverVerb, Pose

DEADBAND_IN = 0.5
"""A camera position nearer than this to the corrected pose leaves the offset alone."""
DEADBAND_DEG = 0.5
"""A matched heading nearer than this to the corrected one leaves the turn alone."""


class CameraLocalised(DriverDecorator):
    """``inner`` with its poses in the perception's frame (the module docstring says
    how): every argument and result the verb table
    (:data:`~hero_driver.interface.DRIVER_VERBS`) names as a pose is moved, whatever
    the verb. Everything else a driver offers is ``inner``'s.

    The correction is a rigid motion of the floor: a turn by ``turn_deg`` about the
    origin, then a shift by ``offset``. The overhead camera corrects the position only
    (``turn_deg`` stays 0); the onboard scan matcher corrects the heading as well
    (:meth:`localise` given one), since a base whose heading drifts turns its whole map.
    """

    def __init__(self, inner: Driver, deadband_in: float = DEADBAND_IN,
                 deadband_deg: float = DEADBAND_DEG) -> None:
        super().__init__(inner)
        self.deadband_in = deadband_in
        self.deadband_deg = deadband_deg
        self.offset: tuple[float, float] = (0.0, 0.0)
        self.turn_deg = 0.0

    def call(self, verb: DriverVerb, method: Callable[..., Any], args: tuple[Any, ...],
             kwargs: dict[str, Any]) -> Any:
        if verb.name == "reset":
            self.offset, self.turn_deg = (0.0, 0.0), 0.0  # a restored world starts with the robot where it says
        (dx, dy), turn = self.offset, self.turn_deg
        back_x, back_y = _turned(-dx, -dy, -turn)
        args, kwargs = poses_in(verb, args, kwargs, back_x, back_y, -turn)
        answer = method(*args, **kwargs)
        if not verb.poses_out:
            return answer
        if verb.robot_time:
            return mapped(answer, lambda result: poses_out(verb, result, dx, dy, turn))
        return poses_out(verb, answer, dx, dy, turn)

    def to_camera(self, pose: Pose) -> Pose:
        """A pose the driver reported, in the perception's frame."""
        moved: Pose = translated(pose, *self.offset, self.turn_deg)
        return moved

    def to_driver(self, pose: Pose) -> Pose:
        """A pose in the perception's frame, in the driver's (its reported frame)."""
        back_x, back_y = _turned(-self.offset[0], -self.offset[1], -self.turn_deg)
        moved: Pose = translated(pose, back_x, back_y, -self.turn_deg)
        return moved

    def localise(self, seen_x_in: float, seen_y_in: float, seen_heading_deg: float | None = None) -> bool:
        """The perception placed the robot's centre at (``seen_x_in``, ``seen_y_in``),
        facing ``seen_heading_deg`` when it can tell (the scan matcher; the overhead
        camera leaves the heading to the driver): take it for the truth when it is more
        than ``deadband_in`` (or ``deadband_deg``) from the corrected pose. True when the
        correction changed."""
        reported = self.inner.state().pose
        believed = self.to_camera(reported)
        turn = self.turn_deg
        if seen_heading_deg is not None:
            turn = seen_heading_deg - reported.heading_deg
        off_deg = abs(math.remainder(turn - self.turn_deg, 360.0))
        if math.hypot(seen_x_in - believed.x_in, seen_y_in - believed.y_in) <= self.deadband_in \
                and off_deg <= self.deadband_deg:
            return False
        turn = math.remainder(turn, 360.0)
        rx, ry = _turned(reported.x_in, reported.y_in, turn)
        self.offset, self.turn_deg = (seen_x_in - rx, seen_y_in - ry), turn
        return True


def _turned(x: float, y: float, turn_deg: float) -> tuple[float, float]:
    c, s = math.cos(math.radians(turn_deg)), math.sin(math.radians(turn_deg))
    return c * x - s * y, s * x + c * y
