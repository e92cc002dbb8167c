"""A long move driven in legs, a look after each: dead reckoning corrected on the way.

A base's odometry drifts with the distance it drives. The overhead camera corrects it
whenever it looks, and a move is driven whole, as in the paper. The onboard perception
corrects it by matching each scan to the map (``mapping.localisation``), and the
matcher trusts a step only as far as its gate: a move across two rooms drifts past it
(seen in a simulated apartment under the ``paper`` preset: one move between two
objects in different rooms came out past the gate, the matcher refused every scan
after it, and the rest of the episode was handled far from where the robot was). So a
perception says how far a move may go between looks (``Perception.leg_in``; None: as
far as it likes), and a move longer than that is driven a leg at a time: after each leg
a look corrects where the robot stands (:meth:`CslBehaviour.look`, the ``localised``
event when it moved the pose), and the rest of the planned path is driven from there.

The rest is the plan's own waypoints in the map's frame: the path was planned clear of
obstacles there, and a correction of a few inches moves only the start of the next
leg. (Re-planning after each look would cost a plan's computation per leg for little.)
The robot time of the looks between legs is the move's: they are how it is driven.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from concurrent.futures import Future
from typing import Any

from behaviours.base import DriverAction
from behaviours.bridge import to_driver_pose
from hero_driver.interface import MoveResult
from hero_driver.interface import Pose as DriverPose  # noqa: I001 (the planner has a Pose too)
from planner import Pose as PlannerPose


def split_leg(path: Sequence[PlannerPose], leg_in: float | None) -> tuple[list[PlannerPose], list[PlannerPose]]:
    """``path`` cut ``leg_in`` along it: the first leg's waypoints (the last one at the
    cut, heading along the path) and the rest (from the cut on). The whole path and no
    rest when it is no longer than ``leg_in`` (or ``leg_in`` is None)."""
    if not path:
        return [], []
    out, driven = [path[0]], 0.0
    for i, (a, b) in enumerate(zip(path, path[1:])):
        step = math.hypot(b.x_in - a.x_in, b.y_in - a.y_in)
        if leg_in is not None and driven + step > leg_in and step > 0:
            t = (leg_in - driven) / step
            heading = math.degrees(math.atan2(b.y_in - a.y_in, b.x_in - a.x_in))
            cut = PlannerPose(a.x_in + t * (b.x_in - a.x_in), a.y_in + t * (b.y_in - a.y_in), heading)
            return out + [cut], [cut, *path[i + 1:]]
        driven += step
        out.append(b)
    return out, []


def first_leg(path: Sequence[PlannerPose], leg_in: float | None) -> list[PlannerPose]:
    """The waypoints of ``path`` up to ``leg_in`` along it (:func:`split_leg`'s first leg)."""
    return split_leg(path, leg_in)[0]


class LeggedMove(DriverAction):
    """A driver action whose move is driven in legs (the module docstring).

    A subclass starts the move with :meth:`drive_path` and begins its ``finish`` with
    :meth:`leg_done`: None while the move goes on (the next look or leg is under way),
    else the whole move's result, its ``duration_s`` the robot time of every leg and
    look between them. :attr:`sent` holds every waypoint sent, for the move's event.
    """

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name, robot)
        self.sent: tuple[DriverPose, ...] = ()
        self.legs = 0  # legs driven in the move under way
        self._rest: list[PlannerPose] = []
        self._face: tuple[float, float] | None = None
        self._seconds = 0.0
        self._looking: float | None = None  # the robot clock when the look between legs began

    def initialise(self) -> None:
        self.sent, self.legs, self._rest, self._seconds, self._looking = (), 0, [], 0.0, None
        super().initialise()

    def verb(self) -> str:
        return self.services.perception.verb if self._looking is not None else super().verb()

    def drive_path(self, path: Sequence[PlannerPose], face: tuple[float, float] | None = None,
                   fallback: DriverPose | None = None) -> Future[MoveResult]:
        """Start the move along ``path`` (planner poses, the robot's start first), turning
        to ``face`` at its end; an empty path drives to ``fallback``."""
        self._face = face
        if not path and fallback is not None:
            return self._send_leg([fallback], last=True)
        return self._next_leg(list(path))

    def leg_done(self, result: Any) -> MoveResult | None:
        """Take a leg's or a look's result (the class docstring)."""
        if self._looking is not None:
            self.look(result)  # the correction: the blackboard's pose is where the look placed the robot
            self._seconds += max(0.0, self.services.driver.state().clock_s - self._looking)
            self._looking = None
            here = self.robot_pose()
            self._future = self._next_leg([here, *self._rest[1:]])
            return None
        assert isinstance(result, MoveResult)
        self._seconds += result.duration_s
        if self._rest and not result.collided and result.blocked is None:
            self.bb.pose = result.pose
            self._looking = self.services.driver.state().clock_s
            self._future = self.services.perception.look()
            return None
        return dataclasses.replace(result, duration_s=self._seconds)

    def _next_leg(self, path: list[PlannerPose]) -> Future[MoveResult]:
        leg, self._rest = split_leg(path, self.services.perception.leg_in)
        return self._send_leg([to_driver_pose(p) for p in leg], last=not self._rest)

    def _send_leg(self, waypoints: list[DriverPose], last: bool) -> Future[MoveResult]:
        self.sent += tuple(waypoints)
        self.legs += 1
        return self.services.driver.move(waypoints, **({"face": self._face} if last and self._face else {}))

