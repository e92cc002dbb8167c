"""The planner's undistortion of an overhead camera image
(:class:`camera_model.image.CameraImage`, the driver's image as it arrives).

Kept here, not with the image type: it needs OpenCV, and the image's leaf package
imports none.
"""

from __future__ import annotations

import dataclasses
from functools import lru_cache

import cv2
import numpy as np

from camera_model.fisheye import undistortion_maps
from camera_model.image import CameraImage


def undistorted(image: CameraImage) -> CameraImage:
    """The image with fish-eye distortion removed (itself when there is none).

    The mapping is ``cv2.fisheye.undistortImage``'s with ``Knew = K`` (so the scale,
    hence the pixel-to-world mapping, is kept; :mod:`camera_model.fisheye`), but
    sampled nearest-neighbour: interpolating would blend an object's 220 with the
    floor's 30 into the furniture and robot bands along every edge, and thin
    objects would lose the pixels that tell what they are.
    """
    if image.check().fisheye is None:
        return image
    matrix = np.asarray(image.camera_matrix, dtype=np.float64)
    coefficients = np.asarray(image.fisheye, dtype=np.float64).reshape(4, 1)
    rows, cols = image.shape
    map_x, map_y = _undistortion_maps(matrix.tobytes(), coefficients.tobytes(), rows, cols)
    flat = cv2.remap(np.ascontiguousarray(image.pixels, dtype=np.uint8), map_x, map_y,
                     interpolation=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return dataclasses.replace(image, pixels=flat, camera_matrix=None, fisheye=None)


@lru_cache(maxsize=4)
def _undistortion_maps(matrix: bytes, coefficients: bytes, rows: int, cols: int) -> tuple[np.ndarray, np.ndarray]:
    """Remap tables for one lens and image size (computed once: the camera is fixed)."""
    k = np.frombuffer(matrix, dtype=np.float64).reshape(3, 3)
    return undistortion_maps(k, np.frombuffer(coefficients, dtype=np.float64), rows, cols)
