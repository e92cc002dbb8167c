"""The calibration board the realistic camera preset prints on the floor: ArUco
markers at known floor positions (docs/camera.md, "The marker board").

A world has a board when its world file names one (``"board"``, docs/simulator.md; the
lab ships one). The file is read by :mod:`camera_model.board`, as the executive reads
it to calibrate, so the two ends agree on where the markers are.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from camera_model.board import QUIET_MODULES, MarkerBoard, load_board
from hero_driver.sim.catalogue import profile_and_catalogue
from hero_driver.sim.worldfile import WorldSpec, load_world


def _spec(world: WorldSpec | str | Path) -> WorldSpec:
    """A world spec as given, or loaded from a shipped world's name or a world file."""
    if isinstance(world, WorldSpec):
        return world
    return load_world(world, profile_and_catalogue()[1])


def board_path(world: str | Path) -> Path:
    """The board file world ``world`` (a shipped world's name or a world file) names;
    ValueError when it names none."""
    spec = _spec(world)
    if spec.board is None:
        raise ValueError(f"{spec.source}: names no marker board (field 'board', docs/camera.md)")
    return spec.board


def board_for(world: WorldSpec | str | Path) -> MarkerBoard | None:
    """The board printed on a world's floor (a spec, a shipped world's name or a world
    file), or None when it has none."""
    spec = _spec(world)
    return None if spec.board is None else load_board(spec.board)


def aruco_dictionary(board: MarkerBoard) -> cv2.aruco.Dictionary:
    """OpenCV's dictionary the board's markers come from."""
    return cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, board.dictionary))


def print_board(board: MarkerBoard, albedo: np.ndarray, world_to_pixel: np.ndarray, paper: float,
                ink: float, supersample: int = 4) -> None:
    """Print the markers into ``albedo`` (float, HxW) in place.

    ``world_to_pixel`` is the 3x3 homography from floor inches to (col, row) pixel
    coordinates (pixel centres at integers). Each marker image is warped onto the
    floor with area averaging, as a camera pixel sees a printed edge.
    """
    dictionary = aruco_dictionary(board)
    modules = board.modules()
    side_px = (modules + 2 * QUIET_MODULES) * 8 * supersample
    half = board.paper_in() / 2
    for marker in board.markers:
        printed = np.full((side_px, side_px), 255, np.uint8)
        inner = modules * 8 * supersample
        offset = QUIET_MODULES * 8 * supersample
        printed[offset:offset + inner, offset:offset + inner] = cv2.aruco.generateImageMarker(
            dictionary, marker.marker_id, inner)
        tone = paper * (printed.astype(np.float32) / 255.0) + ink * (1.0 - printed.astype(np.float32) / 255.0)
        floor = np.float64([[marker.x_in - half, marker.y_in + half], [marker.x_in + half, marker.y_in + half],
                            [marker.x_in + half, marker.y_in - half], [marker.x_in - half, marker.y_in - half]])
        dst = cv2.perspectiveTransform(floor.reshape(-1, 1, 2), world_to_pixel).reshape(-1, 2).astype(np.float32)
        # Shrink to about the size it will have in the image first (area averaging, as a
        # camera pixel sees a printed edge), then warp it into place.
        target = max(int(round(float(np.linalg.norm(dst[1] - dst[0])))), 4)
        small = cv2.resize(tone, (target, target), interpolation=cv2.INTER_AREA)
        # Image corners (col, row), rows growing downwards, onto the floor corners.
        src = np.float32([[-0.5, -0.5], [target - 0.5, -0.5], [target - 0.5, target - 0.5], [-0.5, target - 0.5]])
        to_image = cv2.getPerspectiveTransform(src, dst)
        h, w = albedo.shape
        warped = cv2.warpPerspective(small, to_image, (w, h), flags=cv2.INTER_LINEAR,
                                     borderMode=cv2.BORDER_CONSTANT, borderValue=0.0)
        cover = cv2.warpPerspective(np.ones_like(small), to_image, (w, h), flags=cv2.INTER_LINEAR,
                                    borderMode=cv2.BORDER_CONSTANT, borderValue=0.0)
        inside = cover > 0
        albedo[inside] = warped[inside] + (1 - cover[inside]) * albedo[inside]
