"""The overhead camera's image: its pixels and how they map onto the floor.

One type for both ends of the driver protocol: a driver returns it from ``camera``
(docs/driver-protocol.md), the codec carries it over zenoh, and the planner's vision
reads it as it is; nothing converts it on the way. It lives in this leaf so the driver
side and the planner can share it without importing each other.

``pixels`` is HxW uint8. Pixel (row, col)'s centre, once undistorted, is at world
``x = origin_x_in + (col + 0.5) * inches_per_pixel`` and
``y = origin_y_in - (row + 0.5) * inches_per_pixel`` (row 0 is the room's far, high-y
edge; :class:`camera_model.floor_grid.FloorGrid`). When ``fisheye`` is set the image
was distorted with OpenCV's fisheye model: ``camera_matrix`` (3x3) and ``fisheye`` (4
coefficients) undistort it with ``cv2.fisheye.undistortImage(pixels, K, D, Knew=K)``
(the planner does, ``planner.image.undistorted``; this leaf imports no OpenCV).
"""

from __future__ import annotations

import hashlib
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from camera_model.floor_grid import FloorGrid


@dataclass(frozen=True, eq=False)
class CameraImage:
    """An overhead grayscale image, how it maps onto the floor, and when it was taken
    (``clock_s``, robot time; ``meta``: what the driver adds, docs/driver-protocol.md).

    Built as given, so a driver's bad image reaches the codec and is refused there with
    the protocol's field-named error; whoever reads one calls :meth:`check` first (the
    planner's vision does). Compared by identity (its pixels are an array).
    """

    pixels: np.ndarray
    inches_per_pixel: float
    origin_x_in: float
    origin_y_in: float
    camera_matrix: np.ndarray | None = None
    fisheye: tuple[float, float, float, float] | None = None
    clock_s: float = 0.0
    meta: Mapping[str, object] = field(default_factory=dict)

    def check(self) -> CameraImage:
        """The image itself when a vision can place it; ValueError for an empty or
        non-2-D array, a mapping that is not finite and positive, or a fish-eye image
        without the camera matrix that undistorts it."""
        pixels = np.asarray(self.pixels)
        if pixels.ndim != 2 or pixels.size == 0:
            raise ValueError(f"overhead image must be a non-empty HxW array, got shape {pixels.shape}")
        FloorGrid(self.inches_per_pixel, self.origin_x_in, self.origin_y_in)  # raises on a bad mapping
        if self.fisheye is not None and self.camera_matrix is None:
            raise ValueError("a fisheye image needs its camera_matrix to be undistorted")
        return self

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
        """A digest of pixels and mapping: equal keys mean an unchanged world view (the
        time it was taken and the driver's notes aside)."""
        digest = hashlib.blake2b(digest_size=16)
        pixels = np.ascontiguousarray(self.pixels)
        digest.update(str((pixels.shape, pixels.dtype.str)).encode())
        digest.update(pixels.tobytes())
        digest.update(repr((self.inches_per_pixel, self.origin_x_in, self.origin_y_in, self.fisheye)).encode())
        if self.camera_matrix is not None:
            digest.update(np.asarray(self.camera_matrix, dtype=float).tobytes())
        return digest.hexdigest()

    def to_world(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        """World (x, y) inches of (fractional) pixel coordinates, as an Nx2 array."""
        return self.grid.to_world(rows, cols)

    def to_pixel(self, x_in: float, y_in: float) -> tuple[float, float]:
        """Fractional (row, col) of a world point; the inverse of :meth:`to_world`."""
        return self.grid.to_pixel(x_in, y_in)
