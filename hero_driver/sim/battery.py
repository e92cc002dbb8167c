"""The simulated HERO's battery: drained by the robot time it spends moving, sensing and
grasping, and recharged at a charging dock placed in the world file.

The paper names a low battery among what CSL cannot handle (docs/method.md); the
simulator makes it happen so the executive's guard can be tested. Rates are per second
of robot time, so a run stays repeatable and as fast as the CPU allows. The rates are
documented in docs/simulator.md ("Battery"): change them there too. A world file may
scale all three drain rates by one multiplier (:class:`Charge`), the battery study's
swept disturbance rate: an older pack, a heavier load.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from hero_driver.interface import BATTERY_EMPTY, DriverError, Pose

MOVING_PER_S = 1.0 / 18000.0  # the drive motors: a full charge drives for 5 hours
SENSING_PER_S = 1.0 / 36000.0  # the sonar head and its servo: 10 hours of sensing
GRASPING_PER_S = 1.0 / 12000.0  # the arm's motors: 3 hours 20 minutes of grasping
CHARGING_PER_S = 1.0 / 1800.0  # at the dock: empty to full in 30 minutes
DOCK_REACH_IN = 24.0  # the dock's infrared beacon guides the base onto its contacts from this near


@dataclass(frozen=True)
class Dock:
    """Where the charging dock is: the pose the base must stand at to charge."""

    x_in: float
    y_in: float
    heading_deg: float = 0.0

    @property
    def pose(self) -> Pose:
        return Pose(self.x_in, self.y_in, self.heading_deg)


@dataclass(frozen=True)
class Charge:
    """The battery as a world file sets it: the start ``level`` (0..1) and ``drain``, a
    multiplier (> 0) on the documented drain rates; charging keeps its own rate."""

    level: float = 1.0
    drain: float = 1.0

    def __post_init__(self) -> None:
        if not 0.0 <= self.level <= 1.0:
            raise ValueError(f"battery level must be in [0, 1], got {self.level!r}")
        if not (isinstance(self.drain, (int, float)) and math.isfinite(self.drain) and self.drain > 0.0):
            raise ValueError(f"battery drain must be a number > 0, got {self.drain!r}")


class Battery:
    """The charge left, 0..1. A verb starts only with charge left; the verb that empties
    the battery finishes on the reserve (the level stops at 0), and every later move,
    sensing or grasp is refused with ``battery_empty`` until the robot charges.

    An unmetered battery (``metered=False``) is a tethered robot: the level stays where
    it is. Worlds without a dock or a start level run so (docs/simulator.md), so the
    training floor and the probe worlds, which spend many hours of robot time, never
    run flat."""

    def __init__(self, start: float | Charge = 1.0, metered: bool = True) -> None:
        charge = start if isinstance(start, Charge) else Charge(start)
        self.level, self.drain_scale, self.metered = charge.level, charge.drain, metered

    def require(self, verb: str) -> None:
        """Refuse ``verb`` when the battery is flat."""
        if self.level <= 0.0:
            raise DriverError(BATTERY_EMPTY, f"{verb}: the battery is empty; charge at the dock first")

    def drain(self, seconds: float, per_s: float) -> None:
        """Spend ``seconds`` of robot time at a rate of ``per_s`` of a full charge,
        scaled by the world's drain multiplier."""
        if self.metered:
            self.level = max(0.0, self.level - seconds * per_s * self.drain_scale)

    def charge(self) -> float:
        """Charge to full; the robot seconds it took."""
        seconds = (1.0 - self.level) / CHARGING_PER_S
        self.level = 1.0
        return seconds
