"""Synthetic overhead images drawn in world inches, with the bands of docs/conventions.md.

A pixel takes a shape's intensity when the shape covers at least half of it (drawn
SUPERSAMPLE times finer and area-averaged), as the simulator's camera does, so pixel
counts track true areas and the tests know every answer by hand.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from camera_model.image import CameraImage

FLOOR, WALL, ROBOT, MARKER, OBJECT = 30, 110, 170, 250, 220
IPP = 0.8
SHIFT = 4
SUPERSAMPLE = 8


class Canvas:
    """A room ``width_in`` x ``depth_in`` with 8-inch walls; world (0, 0) is its lower-left."""

    def __init__(self, width_in: float = 240.0, depth_in: float = 180.0, wall_in: float = 8.0) -> None:
        self.origin_x_in = -wall_in
        self.origin_y_in = depth_in + wall_in
        cols = math.ceil((width_in + 2 * wall_in) / IPP)
        rows = math.ceil((depth_in + 2 * wall_in) / IPP)
        self.pixels = np.full((rows, cols), WALL, np.uint8)
        self.rect(width_in / 2, depth_in / 2, width_in, depth_in, 0.0, FLOOR)

    def _fine(self, points) -> np.ndarray:
        pts = np.asarray(points, dtype=float)
        step = IPP / SUPERSAMPLE
        cols = (pts[:, 0] - self.origin_x_in) / step - 0.5
        rows = (self.origin_y_in - pts[:, 1]) / step - 0.5
        return np.round(np.stack([cols, rows], axis=1) * (1 << SHIFT)).astype(np.int32)

    def polygon(self, points, value: int) -> Canvas:
        rows, cols = self.pixels.shape
        fine = np.zeros((rows * SUPERSAMPLE, cols * SUPERSAMPLE), np.uint8)
        cv2.fillPoly(fine, [self._fine(points)], 255, lineType=cv2.LINE_8, shift=SHIFT)
        coverage = cv2.resize(fine, (cols, rows), interpolation=cv2.INTER_AREA)
        self.pixels[coverage >= 128] = value
        return self

    def rect(self, x: float, y: float, length: float, width: float, yaw_deg: float, value: int = OBJECT) -> Canvas:
        return self.polygon(rect_corners(x, y, length, width, yaw_deg), value)

    def disc(self, x: float, y: float, r: float, value: int = OBJECT) -> Canvas:
        return self.polygon([(x + r * math.cos(2 * math.pi * k / 64), y + r * math.sin(2 * math.pi * k / 64))
                             for k in range(64)], value)

    def robot(self, x: float, y: float, heading_deg: float, radius: float = 9.0) -> Canvas:
        self.disc(x, y, radius, ROBOT)
        h = math.radians(heading_deg)
        return self.disc(x + 2 * radius / 3 * math.cos(h), y + 2 * radius / 3 * math.sin(h), radius / 4, MARKER)

    def noisy(self, seed: int = 0, sigma: float = 4.0) -> Canvas:
        rng = np.random.default_rng(seed)
        jitter = np.clip(np.round(rng.normal(0, sigma, self.pixels.shape)), -12, 12)
        self.pixels = np.clip(self.pixels.astype(int) + jitter, 0, 255).astype(np.uint8)
        return self

    def image(self) -> CameraImage:
        return CameraImage(self.pixels.copy(), IPP, self.origin_x_in, self.origin_y_in)


def rect_corners(x: float, y: float, length: float, width: float, yaw_deg: float) -> list[tuple[float, float]]:
    c, s = math.cos(math.radians(yaw_deg)), math.sin(math.radians(yaw_deg))
    local = ((length / 2, width / 2), (-length / 2, width / 2), (-length / 2, -width / 2), (length / 2, -width / 2))
    return [(x + c * a - s * b, y + s * a + c * b) for a, b in local]
