"""The calibration board the realistic camera preset prints on the floor: ArUco
markers at known floor positions (docs/camera.md, "The marker board").

A world has a board when its world file names one (``"board"``, docs/simulator.md; the
lab ships one). The executive reads the same file to calibrate, so the two ends agree
on where the markers are without the planner importing the simulator.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from hero_driver.sim.worldfile import WorldSpec

QUIET_MODULES = 1  # white paper around each marker, in marker modules


@dataclass(frozen=True)
class PrintedMarker:
    """One axis-aligned marker: its id and its centre on the floor (inches)."""

    marker_id: int
    x_in: float
    y_in: float


@dataclass(frozen=True)
class MarkerBoard:
    """ArUco markers of one dictionary, all ``marker_in`` wide."""

    dictionary: str
    marker_in: float
    markers: tuple[PrintedMarker, ...]

    def aruco_dictionary(self) -> cv2.aruco.Dictionary:
        return cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, self.dictionary))

    def modules(self) -> int:
        """Cells across one marker, its black border included."""
        return int(self.aruco_dictionary().markerSize) + 2

    def paper_in(self) -> float:
        """Side of the white square a marker is printed on."""
        return self.marker_in * (1 + 2 * QUIET_MODULES / self.modules())


def _spec(world: WorldSpec | str | Path) -> WorldSpec:
    """A world spec as given, or loaded from a shipped world's name or a world file."""
    if isinstance(world, WorldSpec):
        return world
    from hero_driver.sim.world import profile_and_catalogue  # the world imports this module
    from hero_driver.sim.worldfile import load_world

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


def load_board(path: Path) -> MarkerBoard:
    """Read a board file; a bad one raises ValueError naming the file and field."""
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        dictionary = str(data["dictionary"])
        if not dictionary.startswith("DICT_") or not hasattr(cv2.aruco, dictionary):
            raise ValueError(f"dictionary: unknown ArUco dictionary {dictionary!r}")
        marker_in = float(data["marker_in"])
        if not (math.isfinite(marker_in) and marker_in > 0):
            raise ValueError("marker_in: must be a positive number of inches")
        markers = tuple(PrintedMarker(int(m["id"]), float(m["x_in"]), float(m["y_in"])) for m in data["markers"])
    except (OSError, json.JSONDecodeError, KeyError, TypeError) as exc:
        raise ValueError(f"{path}: not a marker board ({type(exc).__name__}: {exc})") from None
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    return MarkerBoard(dictionary, marker_in, markers)


def print_board(board: MarkerBoard, albedo: np.ndarray, world_to_pixel: np.ndarray, paper: float,
                ink: float, supersample: int = 4) -> None:
    """Print the markers into ``albedo`` (float, HxW) in place.

    ``world_to_pixel`` is the 3x3 homography from floor inches to (col, row) pixel
    coordinates (pixel centres at integers). Each marker image is warped onto the
    floor with area averaging, as a camera pixel sees a printed edge.
    """
    dictionary = board.aruco_dictionary()
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
