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

A perception that measures what lies straight ahead (the onboard scan) also checks the
end of a move to an object's position: one look, and the difference between the
distance it measures and the position's driven straight on or back
(:class:`LeggedMove`).
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


APPROACH_DEADBAND_IN = 0.5
"""A final approach whose range straight ahead is off the wanted distance by no more than
this is left as it is (a procedure accepts its range within 1.5 in: docs/conventions.md)."""
APPROACH_MAX_IN = 5.0
"""A range straight ahead off the wanted distance by more than this is not the object's
near face (a beam past a small object to the wall behind it): no correction is driven."""


class LeggedMove(DriverAction):
    """A driver action whose move is driven in legs (the module docstring).

    A subclass starts the move with :meth:`drive_path` and begins its ``finish`` with
    :meth:`leg_done`: None while the move goes on (the next look or leg is under way),
    else the whole move's result, its ``duration_s`` the robot time of every leg and
    look between them. :attr:`sent` holds every waypoint sent, for the move's event.

    A move to a position at ``standoff_in`` from an object (the learner position's
    distance) ends, when the perception measures what lies straight ahead
    (``Perception.measures_ahead``: the onboard scan), with one look from where it
    stopped: when that look puts the object's near face more than
    :data:`APPROACH_DEADBAND_IN` nearer or farther than wanted, the robot drives straight
    ahead or back by the difference (the ``approach_in`` it drove is on the move's
    event). The check is relative to the robot, so it holds whatever error the robot's
    or the object's place in the map has: an object outlined from a few scans, and a
    pose matched scan by scan, are each an inch or two off, and the procedures accept
    their range within an inch and a half. The camera does not measure it: its moves end
    where they end, as in the paper.
    """

    def __init__(self, name: str, robot: str) -> None:
        super().__init__(name, robot)
        self.sent: tuple[DriverPose, ...] = ()
        self.legs = 0  # legs driven in the move under way
        self.approach_in: float | None = None  # the final approach's correction, when one was driven
        self._rest: list[PlannerPose] = []
        self._face: tuple[float, float] | None = None
        self._standoff: float | None = None
        self._seconds = 0.0
        self._looking: float | None = None  # the robot clock when a look of the move began
        self._phase = "leg"  # "leg", "between" (a look between legs), "check" (the look after the last), "approach"
        self._last: MoveResult | None = None

    def initialise(self) -> None:
        self.sent, self.legs, self.approach_in, self._rest, self._seconds = (), 0, None, [], 0.0
        self._looking, self._phase, self._last = None, "leg", None
        super().initialise()

    def verb(self) -> str:
        return self.services.perception.verb if self._looking is not None else super().verb()

    def drive_path(self, path: Sequence[PlannerPose], face: tuple[float, float] | None = None,
                   fallback: DriverPose | None = None, standoff_in: float | None = None) -> Future[MoveResult]:
        """Start the move along ``path`` (planner poses, the robot's start first), turning
        to ``face`` at its end; an empty path drives to ``fallback``. ``standoff_in``: the
        sonar's distance from the object ``face`` is wanted at (the class docstring)."""
        self._face, self._standoff = face, standoff_in
        if not path and fallback is not None:
            return self._send_leg([fallback], last=True)
        return self._next_leg(list(path))

    def leg_done(self, result: Any) -> MoveResult | None:
        """Take a leg's or a look's result (the class docstring)."""
        if self._phase in ("between", "check"):
            self.look(result)  # the correction: the blackboard's pose is where the look placed the robot
            assert self._looking is not None
            self._seconds += max(0.0, self.services.driver.state().clock_s - self._looking)
            self._looking = None
            if self._phase == "between":
                self._phase = "leg"
                self._future = self._next_leg([self.robot_pose(), *self._rest[1:]])
                return None
            return self._approach(result)
        assert isinstance(result, MoveResult)
        self._seconds += result.duration_s
        self._last = result
        stopped = result.collided or result.blocked is not None
        if self._phase == "leg" and not stopped and (
                self._rest or (self._standoff is not None and self.services.perception.measures_ahead)):
            self.bb.pose = result.pose
            self._phase = "between" if self._rest else "check"
            self._looking = self.services.driver.state().clock_s
            self._future = self.services.perception.look()
            return None
        return dataclasses.replace(result, duration_s=self._seconds)

    def _approach(self, observation: Any) -> MoveResult | None:
        """After the look at the end of the move: drive the difference straight ahead, or
        end the move where it is."""
        assert self._last is not None and self._standoff is not None
        ahead = self.services.perception.distance_ahead(observation)
        here = self.robot_pose()
        off = None if ahead is None else ahead - self._standoff
        if off is None or abs(off) <= APPROACH_DEADBAND_IN or abs(off) > APPROACH_MAX_IN:
            return dataclasses.replace(self._last, pose=self.bb.pose, duration_s=self._seconds)
        self.approach_in = round(off, 2)
        self._phase = "approach"
        h = math.radians(here.heading_deg)
        there = PlannerPose(here.x_in + off * math.cos(h), here.y_in + off * math.sin(h), here.heading_deg)
        self._future = self._send_leg([to_driver_pose(here), to_driver_pose(there)], last=True)
        return None

    def _next_leg(self, path: list[PlannerPose]) -> Future[MoveResult]:
        leg, self._rest = split_leg(path, self.services.perception.leg_in)
        return self._send_leg([to_driver_pose(p) for p in leg], last=not self._rest)

    def _send_leg(self, waypoints: list[DriverPose], last: bool) -> Future[MoveResult]:
        self.sent += tuple(waypoints)
        self.legs += 1
        return self.services.driver.move(waypoints, **({"face": self._face} if last and self._face else {}))
