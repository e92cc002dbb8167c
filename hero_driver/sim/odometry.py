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
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Drift:
    """True position minus reported position, in inches (zero at every reset)."""

    dx_in: float = 0.0
    dy_in: float = 0.0

    def plus(self, dx_in: float, dy_in: float) -> Drift:
        return Drift(self.dx_in + dx_in, self.dy_in + dy_in)

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
