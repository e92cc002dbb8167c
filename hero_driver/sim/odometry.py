"""Dead-reckoning drift: how far the robot's own idea of its position has wandered from
the truth.

The base knows where it is only by counting wheel turns. Slip, an uneven floor and
wheels that are not quite round add a small error for every inch driven, and nothing
on the robot ever takes it out again, so the error is a random walk over the distance
travelled: after ``s`` inches its sigma per axis is ``drift x √s``. The simulator keeps
the true pose (the sonar, the bumper and the overhead camera see the truth) and reports
the true pose less this offset, which is what a driver reading its encoders would say.
An executive that trusts the reported pose sets off from the wrong place by the
offset; the overhead camera's view of the robot would correct it.

A base without a gyro also loses its heading: every turn and every inch driven adds
an unsensed heading error (a random walk over the degrees turned and the inches
driven, :func:`heading_slip`), so the robot's whole frame turns away from the truth
about where the base stands, and the position error then grows with every inch driven
along the wrong heading. Only worlds that ask for it drift in heading (a home with no
ceiling camera to correct it); with no heading drift the offset is a translation,
exactly as before.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Drift:
    """How the robot's reckoned frame lies in the true one (zero at every reset): a
    reckoned point ``p`` is truly at ``R(dheading_deg) p + (dx_in, dy_in)``, and a
    reckoned heading is truly ``dheading_deg`` more. Without heading drift it is the
    true position minus the reported one."""

    dx_in: float = 0.0
    dy_in: float = 0.0
    dheading_deg: float = 0.0

    def plus(self, dx_in: float, dy_in: float) -> Drift:
        """The base slipped by (dx, dy) without sensing it."""
        return Drift(self.dx_in + dx_in, self.dy_in + dy_in, self.dheading_deg)

    def turned(self, error_deg: float, at: tuple[float, float]) -> Drift:
        """The base's heading slipped by ``error_deg`` while it stood truly at ``at``:
        the reckoned frame turns about that point, so the robot's belief of where it
        stands is unchanged and every later reckoned point lies turned about it."""
        reckoned = self.to_reckoned(at)
        heading = self.dheading_deg + error_deg
        c, s = math.cos(math.radians(heading)), math.sin(math.radians(heading))
        return Drift(at[0] - (c * reckoned[0] - s * reckoned[1]), at[1] - (s * reckoned[0] + c * reckoned[1]), heading)

    def to_true(self, point: tuple[float, float]) -> tuple[float, float]:
        """Where a reckoned point truly is."""
        if self.dheading_deg == 0.0:
            return point[0] + self.dx_in, point[1] + self.dy_in
        c, s = math.cos(math.radians(self.dheading_deg)), math.sin(math.radians(self.dheading_deg))
        return c * point[0] - s * point[1] + self.dx_in, s * point[0] + c * point[1] + self.dy_in

    def to_reckoned(self, point: tuple[float, float]) -> tuple[float, float]:
        """Where the robot reckons a true point to be."""
        x, y = point[0] - self.dx_in, point[1] - self.dy_in
        if self.dheading_deg == 0.0:
            return x, y
        c, s = math.cos(math.radians(self.dheading_deg)), math.sin(math.radians(self.dheading_deg))
        return c * x + s * y, -s * x + c * y

    @property
    def size_in(self) -> float:
        return math.hypot(self.dx_in, self.dy_in)


def slip(travel_in: float, drift: float, rng: np.random.Generator) -> tuple[float, float]:
    """The unsensed displacement, per axis N(0, drift² x travel), that driving
    ``travel_in`` inches adds; draws nothing when there is no drift or no travel, so a
    run without drift keeps its random stream."""
    if drift <= 0 or travel_in <= 0:
        return 0.0, 0.0
    dx, dy = rng.normal(0.0, drift * math.sqrt(travel_in), 2)
    return float(dx), float(dy)


def heading_slip(turned_deg: float, travel_in: float, per_turn: float, per_travel: float,
                 rng: np.random.Generator) -> float:
    """The unsensed heading error, N(0, per_turn² x |turned| + per_travel² x travel)
    degrees, that turning ``turned_deg`` and then driving ``travel_in`` inches adds;
    draws nothing when neither rate applies, so a run without heading drift keeps its
    random stream."""
    variance = per_turn ** 2 * abs(turned_deg) + per_travel ** 2 * max(travel_in, 0.0)
    if variance <= 0:
        return 0.0
    return float(rng.normal(0.0, math.sqrt(variance)))
