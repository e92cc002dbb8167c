"""Undistorting a fish-eye image as docs/driver-protocol.md says: the pixel-to-floor
mapping holds for ``cv2.fisheye.undistortImage(pixels, K, D, Knew=K)``.

The sampling maps are OpenCV's fisheye model written out in numpy (equal to
``cv2.fisheye.initUndistortRectifyMap(K, D, I, K, ...)`` in float32, which
tests/camera_model checks), so the suite and the vision undistort alike without the
model needing OpenCV; the caller samples with them (nearest-neighbour, so no grey
level is invented between bands).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np


def undistortion_maps(camera_matrix: np.ndarray, coefficients: Sequence[float], rows: int,
                      cols: int) -> tuple[np.ndarray, np.ndarray]:
    """For each pixel of the undistorted ``rows`` x ``cols`` image, the (col, row) it
    comes from in the fish-eye image, as two float32 arrays (``cv2.remap``'s maps).

    With ``K = camera_matrix`` kept as the new camera matrix, a pixel (u, v) is the ray
    ``K^-1 (u, v, 1)`` at angle ``theta = atan(r)`` from the axis; the lens puts it at
    ``theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)``, and
    back into pixels by K's focal lengths and centre (OpenCV's fisheye model leaves
    out K's skew there, and so does this).
    """
    k = np.asarray(camera_matrix, dtype=np.float64)
    k1, k2, k3, k4 = (float(c) for c in np.asarray(coefficients, dtype=np.float64).ravel())
    fx, skew, cx, fy, cy = k[0, 0], k[0, 1], k[0, 2], k[1, 1], k[1, 2]
    u, v = np.meshgrid(np.arange(cols, dtype=np.float64), np.arange(rows, dtype=np.float64))
    y = (v - cy) / fy
    x = (u - cx - skew * y) / fx
    r = np.hypot(x, y)
    theta = np.arctan(r)
    t2 = theta * theta
    theta_d = theta * (1 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))))
    scale = np.divide(theta_d, r, out=np.ones_like(r), where=r > 1e-8)
    xd, yd = x * scale, y * scale
    return (fx * xd + cx).astype(np.float32), (fy * yd + cy).astype(np.float32)
