"""A planar range scan as the mapping reads it: beams, ranges and the pose they were taken from.

The driver has its own scan type (the protocol's); the caller converts it field by field,
so that the mapping depends on nothing of the driver. A beam that returned nothing has
range ``inf``: a dropout, glass, a specular miss or nothing within ``max_range_in`` — the
scan cannot tell which, and the occupancy grid treats it as saying nothing
(:mod:`mapping.occupancy`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class PlanarScan:
    """Beam ``i`` leaves the robot at ``heading_deg`` plus ``angles_rad[i]`` (counter-clockwise)
    and met something at ``ranges_in[i]`` inches (``inf``: no return). The pose is the one
    the robot reported (its odometry) when it took the scan, at robot time ``stamp_s``.

    Checked when made (ValueError naming the field); compared by identity (it holds arrays).
    """

    angles_rad: np.ndarray
    ranges_in: np.ndarray
    x_in: float
    y_in: float
    heading_deg: float
    stamp_s: float
    max_range_in: float

    def __post_init__(self) -> None:
        angles = np.asarray(self.angles_rad, dtype=float)
        ranges = np.asarray(self.ranges_in, dtype=float)
        if angles.ndim != 1 or angles.shape != ranges.shape:
            raise ValueError(f"scan angles_rad and ranges_in must be 1-D of one length, got shapes "
                             f"{angles.shape} and {ranges.shape}")
        if not np.isfinite(angles).all():
            raise ValueError("scan angles_rad must be finite")
        if np.isnan(ranges).any() or (ranges <= 0).any():
            raise ValueError("scan ranges_in must be positive (inf for no return), got NaN or a range <= 0")
        for name in ("x_in", "y_in", "heading_deg", "stamp_s"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"scan {name} must be finite, got {getattr(self, name)}")
        if not (math.isfinite(self.max_range_in) and self.max_range_in > 0):
            raise ValueError(f"scan max_range_in must be positive and finite, got {self.max_range_in}")
        object.__setattr__(self, "angles_rad", angles)
        object.__setattr__(self, "ranges_in", ranges)

    @property
    def returned(self) -> np.ndarray:
        """Which beams met something within range."""
        return np.isfinite(self.ranges_in) & (self.ranges_in <= self.max_range_in)

    def points(self) -> np.ndarray:
        """The returns as an Nx2 array in the robot's frame (x forward, y left), inches."""
        seen = self.returned
        r, a = self.ranges_in[seen], self.angles_rad[seen]
        return np.column_stack([r * np.cos(a), r * np.sin(a)])

    def world_points(self, x_in: float, y_in: float, heading_deg: float) -> np.ndarray:
        """The returns as an Nx2 array in world inches, the scan taken at (``x_in``,
        ``y_in``) facing ``heading_deg`` (its corrected pose, not necessarily its own)."""
        local = self.points()
        h = math.radians(heading_deg)
        c, s = math.cos(h), math.sin(h)
        return np.column_stack([x_in + c * local[:, 0] - s * local[:, 1], y_in + s * local[:, 0] + c * local[:, 1]])
