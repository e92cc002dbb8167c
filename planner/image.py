"""The planner's view of an overhead camera image and its pixel-to-world mapping.

:class:`OverheadImage` carries the same fields, with the same meaning, as the driver's
``CameraImage``; the executive builds one from the other. The pixel-to-world mapping
(once undistorted) is the protocol's, :class:`camera_model.floor_grid.FloorGrid`.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from functools import cached_property, lru_cache

import cv2
import numpy as np

from camera_model.fisheye import undistortion_maps
from camera_model.floor_grid import FloorGrid


@dataclass(frozen=True, eq=False)
class OverheadImage:
    """An overhead grayscale image (HxW uint8) and how it maps onto the floor."""

    pixels: np.ndarray
    inches_per_pixel: float
    origin_x_in: float
    origin_y_in: float
    camera_matrix: np.ndarray | None = None
    fisheye: tuple[float, float, float, float] | None = None

    def __post_init__(self) -> None:
        pixels = np.asarray(self.pixels)
        if pixels.ndim != 2 or pixels.size == 0:
            raise ValueError(f"overhead image must be a non-empty HxW array, got shape {pixels.shape}")
        FloorGrid(self.inches_per_pixel, self.origin_x_in, self.origin_y_in)  # raises on a bad mapping
        if self.fisheye is not None and self.camera_matrix is None:
            raise ValueError("a fisheye image needs its camera_matrix to be undistorted")

    @cached_property
    def grid(self) -> FloorGrid:
        """The image's pixel-to-floor mapping."""
        return FloorGrid(self.inches_per_pixel, self.origin_x_in, self.origin_y_in)

    @property
    def shape(self) -> tuple[int, int]:
        """(rows, cols)."""
        rows, cols = self.pixels.shape
        return int(rows), int(cols)

    def content_key(self) -> str:
        """A digest of pixels and mapping: equal keys mean an unchanged world view."""
        digest = hashlib.blake2b(digest_size=16)
        pixels = np.ascontiguousarray(self.pixels)
        digest.update(str((pixels.shape, pixels.dtype.str)).encode())
        digest.update(pixels.tobytes())
        digest.update(repr((self.inches_per_pixel, self.origin_x_in, self.origin_y_in, self.fisheye)).encode())
        if self.camera_matrix is not None:
            digest.update(np.asarray(self.camera_matrix, dtype=float).tobytes())
        return digest.hexdigest()

    def undistorted(self) -> OverheadImage:
        """The image with fish-eye distortion removed (itself when there is none).

        The mapping is ``cv2.fisheye.undistortImage``'s with ``Knew = K`` (so the scale,
        hence the pixel-to-world mapping, is kept; :mod:`camera_model.fisheye`), but
        sampled nearest-neighbour: interpolating would blend an object's 220 with the
        floor's 30 into the furniture and robot bands along every edge, and thin
        objects would lose the pixels that tell what they are.
        """
        if self.fisheye is None:
            return self
        matrix = np.asarray(self.camera_matrix, dtype=np.float64)
        coefficients = np.asarray(self.fisheye, dtype=np.float64).reshape(4, 1)
        rows, cols = self.shape
        map_x, map_y = _undistortion_maps(matrix.tobytes(), coefficients.tobytes(), rows, cols)
        flat = cv2.remap(np.ascontiguousarray(self.pixels, dtype=np.uint8), map_x, map_y,
                         interpolation=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        return OverheadImage(flat, self.inches_per_pixel, self.origin_x_in, self.origin_y_in)

    def to_world(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """World (x, y) inches of (fractional) pixel coordinates, as an Nx2 array."""
        return self.grid.to_world(rows, cols)

    def to_pixel(self, x_in: float, y_in: float) -> tuple[float, float]:
        """Fractional (row, col) of a world point; the inverse of :meth:`to_world`."""
        return self.grid.to_pixel(x_in, y_in)


@lru_cache(maxsize=4)
def _undistortion_maps(matrix: bytes, coefficients: bytes, rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    """Remap tables for one lens and image size (computed once: the camera is fixed)."""
    k = np.frombuffer(matrix, dtype=np.float64).reshape(3, 3)
    return undistortion_maps(k, np.frombuffer(coefficients, dtype=np.float64), rows, cols)
