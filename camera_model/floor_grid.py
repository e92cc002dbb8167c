"""The pixel-to-floor mapping of an overhead image (docs/driver-protocol.md).

Row 0 is the image's high-y edge and rows count down the floor; pixel ``(row, col)``'s
centre is at ``x = origin_x_in + (col + 0.5) * inches_per_pixel`` and
``y = origin_y_in - (row + 0.5) * inches_per_pixel`` (on a band image once its lens is
undistorted; on a real camera's image once rectified by its calibration).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Coordinate = float | np.ndarray


@dataclass(frozen=True)
class FloorGrid:
    """A square grid of ``inches_per_pixel`` on the floor whose top-left corner (the
    outer corner of pixel (0, 0)) is at (``origin_x_in``, ``origin_y_in``)."""

    inches_per_pixel: float
    origin_x_in: float
    origin_y_in: float

    def __post_init__(self) -> None:
        if not (math.isfinite(self.inches_per_pixel) and self.inches_per_pixel > 0):
            raise ValueError(f"inches_per_pixel must be positive, got {self.inches_per_pixel}")
        if not (math.isfinite(self.origin_x_in) and math.isfinite(self.origin_y_in)):
            raise ValueError("overhead image origin is not finite")

    def to_world(self, rows: np.ndarray | float, cols: np.ndarray | float) -> np.ndarray:
        """World (x, y) inches of (fractional) pixel coordinates, as an Nx2 array."""
        s = self.inches_per_pixel
        xs = self.origin_x_in + (np.asarray(cols, dtype=float) + 0.5) * s
        ys = self.origin_y_in - (np.asarray(rows, dtype=float) + 0.5) * s
        return np.column_stack([xs, ys])

    def to_pixel(self, x_in: float, y_in: float) -> tuple[float, float]:
        """Fractional (row, col) of a world point; the inverse of :meth:`to_world`."""
        row, col = self.to_cell(x_in, y_in)
        return row - 0.5, col - 0.5

    def to_cell(self, x_in: Coordinate, y_in: Coordinate) -> tuple[Coordinate, Coordinate]:
        """(row, col) of world points with the pixels' edges at whole numbers: a point
        lies in pixel ``(floor(row), floor(col))`` (scalars or arrays alike)."""
        s = self.inches_per_pixel
        return (self.origin_y_in - y_in) / s, (x_in - self.origin_x_in) / s

    def extent(self, rows: int, cols: int) -> tuple[float, float, float, float]:
        """The floor a ``rows`` x ``cols`` image covers: ``(x_min, x_max, y_min, y_max)``."""
        s = self.inches_per_pixel
        return self.origin_x_in, self.origin_x_in + cols * s, self.origin_y_in - rows * s, self.origin_y_in

    def world_to_pixel(self) -> np.ndarray:
        """The mapping as a 3x3 homography from floor ``(x, y, 1)`` to ``(col, row, 1)``
        (pixel centres at integers), for warping and perspective transforms."""
        s = self.inches_per_pixel
        return np.array([[1 / s, 0, -self.origin_x_in / s - 0.5],
                         [0, -1 / s, self.origin_y_in / s - 0.5],
                         [0, 0, 1]])

    def finer(self, factor: int) -> FloorGrid:
        """The same floor divided ``factor`` times finer (for drawing supersampled)."""
        return FloorGrid(self.inches_per_pixel / factor, self.origin_x_in, self.origin_y_in)
