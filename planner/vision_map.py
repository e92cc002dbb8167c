"""The vision map: where the robot's base centre may be, from one overhead image.

Obstacles are furniture, walls and objects (never the robot itself). The robot is a
disc, so the map is inflated by its radius once and the planner then treats the base
as a point: a cell is free when no obstacle pixel centre lies within
``base_radius_in + (1 + √½) · inches_per_pixel`` of its centre. The margin makes the
guarantee hold for every point of a free cell, not just its centre: a pixel shows an
obstacle when the obstacle covers half of it, so the true edge may lie up to one pixel
beyond the outermost obstacle pixel centre, and a point of a cell may lie √½ pixel from
the cell's centre. A base centred anywhere in a free cell therefore touches nothing.

Besides what the image shows, a map may hold discs the robot was told about: a moving
obstacle a driver reported when it stopped a move (docs/planner.md, "Moving
obstacles") is drawn in as occupied, so the next plan goes around where it stood.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

import cv2
import numpy as np

from camera_model.image import CameraImage
from planner.vision import Scene
from robot_profile import RobotGeometry


@dataclass(frozen=True, eq=False)
class VisionMap:
    """Occupancy and inflated occupancy on the undistorted image's pixel grid.

    ``free`` is where the base centre may be; ``key`` identifies the obstacles it was
    built from (see :func:`map_key`). ``free_strict`` is ``free`` shrunk by one
    more cell: a motion whose states, sampled at most half a cell apart, all lie in it
    cannot touch a cell that ``free`` forbids (every point of the motion is within a
    quarter cell of a sample, hence in the sample's cell or a neighbour of it).
    """

    image: CameraImage
    occupied: np.ndarray
    free: np.ndarray
    free_strict: np.ndarray
    inflation_in: float
    key: str

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """World extent ``(x_min, x_max, y_min, y_max)`` in inches."""
        return self.image.grid.extent(*self.image.shape)

    def cell_of(self, x_in: float, y_in: float) -> tuple[int, int] | None:
        """The (row, col) containing a world point, or None outside the map."""
        gy, gx = self.image.grid.to_cell(x_in, y_in)
        if not (math.isfinite(gx) and math.isfinite(gy)):
            return None
        row, col = math.floor(gy), math.floor(gx)
        rows, cols = self.free.shape
        if 0 <= row < rows and 0 <= col < cols:
            return row, col
        return None

    def contains(self, x_in: float, y_in: float) -> bool:
        """True when the point lies on the map."""
        return self.cell_of(x_in, y_in) is not None

    def is_free(self, x_in: float, y_in: float) -> bool:
        """True when the base centre may stand at the point."""
        cell = self.cell_of(x_in, y_in)
        return cell is not None and bool(self.free[cell])

    def nearest_free(self, x_in: float, y_in: float, within_in: float) -> tuple[float, float] | None:
        """The centre of the free cell nearest to a point, if one lies within ``within_in``."""
        cell = self.cell_of(x_in, y_in)
        if cell is None:
            return None
        if self.free[cell]:
            return x_in, y_in
        ipp = self.image.inches_per_pixel
        reach = math.ceil(within_in / ipp) + 1
        row0, col0 = max(cell[0] - reach, 0), max(cell[1] - reach, 0)
        window = self.free[row0:cell[0] + reach + 1, col0:cell[1] + reach + 1]
        rows, cols = np.nonzero(window)
        if rows.size == 0:
            return None
        centres = self.image.to_world(rows + row0, cols + col0)
        distances = np.hypot(centres[:, 0] - x_in, centres[:, 1] - y_in)
        best = int(np.argmin(distances))
        if distances[best] > within_in:
            return None
        return float(centres[best, 0]), float(centres[best, 1])

    def points_strictly_free(self, points: np.ndarray) -> np.ndarray:
        """For an Nx2 array of world points, which lie in ``free_strict`` (vectorised)."""
        gy, gx = self.image.grid.to_cell(points[:, 0], points[:, 1])
        cols, rows = np.floor(gx).astype(int), np.floor(gy).astype(int)
        n_rows, n_cols = self.free_strict.shape
        inside = (rows >= 0) & (rows < n_rows) & (cols >= 0) & (cols < n_cols)
        out = np.zeros(len(points), dtype=bool)
        out[inside] = self.free_strict[rows[inside], cols[inside]]
        return out

    def segment_is_free(self, start: tuple[float, float], end: tuple[float, float]) -> bool:
        """True when every cell the straight segment passes through is free.

        Exact: the segment is cut at every grid line it crosses and the middle of each
        piece is tested, so no cell it enters is skipped (touching a cell corner only is
        not entering it).
        """
        gy0, gx0 = self.image.grid.to_cell(*start)
        gy1, gx1 = self.image.grid.to_cell(*end)
        cuts = [np.array([0.0, 1.0])]
        for a, b in ((gx0, gx1), (gy0, gy1)):
            if a != b:
                lines = np.arange(math.ceil(min(a, b)), math.floor(max(a, b)) + 1, dtype=float)
                cuts.append((lines - a) / (b - a))
        t = np.unique(np.clip(np.concatenate(cuts), 0.0, 1.0))
        mids = np.concatenate([[0.0, 1.0], (t[:-1] + t[1:]) / 2])
        cols = np.floor(gx0 + mids * (gx1 - gx0)).astype(int)
        rows = np.floor(gy0 + mids * (gy1 - gy0)).astype(int)
        n_rows, n_cols = self.free.shape
        inside = (rows >= 0) & (rows < n_rows) & (cols >= 0) & (cols < n_cols)
        return bool(inside.all() and self.free[rows, cols].all())


def disc_kernel(radius_px: float) -> np.ndarray:
    """A 0/1 structuring element of the cells whose centres lie within ``radius_px``."""
    reach = int(math.floor(radius_px))
    offsets = np.arange(-reach, reach + 1)
    dy, dx = np.meshgrid(offsets, offsets, indexing="ij")
    return (dx * dx + dy * dy <= radius_px * radius_px + 1e-9).astype(np.uint8)


Disc = tuple[float, float, float]  # an obstacle drawn in: centre x, y and radius, inches


def map_key(scene: Scene, robot: RobotGeometry, discs: tuple[Disc, ...] = ()) -> str:
    """A digest of what the map is made of: obstacles, pixel grid and base radius.

    The robot is not an obstacle, so images taken as it drives about share one key, and
    with it one map, roadmap and set of distance fields.
    """
    image = scene.image
    digest = hashlib.blake2b(digest_size=16)
    occupied = np.packbits(scene.furniture | scene.objects)
    digest.update(repr((scene.furniture.shape, image.inches_per_pixel, image.origin_x_in, image.origin_y_in,
                        robot.base_radius_in)).encode())
    digest.update(occupied.tobytes())
    if discs:
        digest.update(repr(discs).encode())
    return digest.hexdigest()


def draw_discs(scene: Scene, discs: tuple[Disc, ...]) -> np.ndarray:
    """The scene's obstacle pixels with ``discs`` drawn in: every pixel whose centre
    lies within a disc's radius of its centre."""
    occupied = scene.furniture | scene.objects
    if not discs:
        return occupied
    image = scene.image
    rows, cols = np.indices(occupied.shape)
    centres = image.to_world(rows.ravel(), cols.ravel())
    drawn = occupied.copy().ravel()
    for x, y, r in discs:
        drawn |= np.hypot(centres[:, 0] - x, centres[:, 1] - y) <= r
    return drawn.reshape(occupied.shape)


def build_vision_map(scene: Scene, robot: RobotGeometry, discs: tuple[Disc, ...] = ()) -> VisionMap:
    """Inflate the scene's obstacles, ``discs`` drawn in, by the base's radius
    (cv2.dilate with a disc)."""
    return inflated_map(scene.image, draw_discs(scene, discs), robot.base_radius_in, map_key(scene, robot, discs))


def inflated_map(image: CameraImage, occupied: np.ndarray, base_radius_in: float, key: str) -> VisionMap:
    """The map of ``occupied`` cells on ``image``'s grid, inflated by the base's radius
    plus the margin of the module docstring; ``key`` names what it was built from. The
    overhead image's map and the scan-built one (``mapping.planning``) are both made here."""
    ipp = image.inches_per_pixel
    inflation_in = base_radius_in + (1.0 + math.sqrt(0.5)) * ipp
    inflated = cv2.dilate(occupied.astype(np.uint8), disc_kernel(inflation_in / ipp))
    free = inflated == 0
    strict = cv2.dilate(inflated, np.ones((3, 3), np.uint8)) == 0
    return VisionMap(image=image, occupied=occupied, free=free, free_strict=strict,
                     inflation_in=inflation_in, key=key)
