"""The world's true static occupancy as a grid: what a map built from the robot's own
scans is scored against (IoU of occupied cells), and the picture shown beside it.

A cell is occupied when a wall, a piece of furniture or (when asked) an object covers
any part of it (touching its edge is not covering): a wall thinner than a cell still
shows, as the cells a range sensor's hits fall in would. Two layers: ``scan`` is
what a planar range sensor just above the floor meets (a table is its four legs),
``footprint`` what the base may not enter (a table is its whole top). Ground truth, for reports and tests: never for the executive.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from hero_driver.sim.catalogue import CatalogueEntry
from hero_driver.sim.physics import WALL_IN
from hero_driver.sim.worldfile import WorldSpec, footprint_polygon, rect_polygon

LAYERS = ("scan", "footprint")
Polygon = list[tuple[float, float]]


@dataclass(frozen=True)
class TruthMap:
    """``occupied[row, col]`` is the cell ``x`` in ``[x0 + col*r, x0 + (col+1)*r)``,
    ``y`` in ``[y0 + row*r, y0 + (row+1)*r)`` (``r`` = ``resolution_in``): row 0 is the
    world's lowest ``y``, so the array is the world seen from above with y up, flipped."""

    occupied: np.ndarray
    x0_in: float
    y0_in: float
    resolution_in: float

    @property
    def extent(self) -> tuple[float, float, float, float]:
        """(x0, y0, x1, y1) in inches: the world rectangle the grid covers."""
        rows, cols = self.occupied.shape
        r = self.resolution_in
        return self.x0_in, self.y0_in, self.x0_in + cols * r, self.y0_in + rows * r

    def cell_of(self, x_in: float, y_in: float) -> tuple[int, int]:
        """(row, col) of the cell holding a world point (may lie outside the grid)."""
        return (math.floor((y_in - self.y0_in) / self.resolution_in),
                math.floor((x_in - self.x0_in) / self.resolution_in))

    def centre(self, row: int, col: int) -> tuple[float, float]:
        """The world point at a cell's centre."""
        return (self.x0_in + (col + 0.5) * self.resolution_in, self.y0_in + (row + 0.5) * self.resolution_in)


def static_polygons(spec: WorldSpec, layer: str = "scan") -> list[Polygon]:
    """The world's static shapes in ``layer``: the outer walls (``WALL_IN`` thick,
    outside the room, as the physics has them), the interior walls' solid pieces and
    the furniture (at the scan plane, or its footprints)."""
    if layer not in LAYERS:
        raise ValueError(f"truth map layer {layer!r}: expected one of {', '.join(LAYERS)}")
    w, d, t = spec.room_width_in, spec.room_depth_in, WALL_IN
    polygons = [rect_polygon(x, y, length, width, 0.0) for x, y, length, width in (
        (w / 2, -t / 2, w + 2 * t, t), (w / 2, d + t / 2, w + 2 * t, t),
        (-t / 2, d / 2, t, d + 2 * t), (w + t / 2, d / 2, t, d + 2 * t))]
    polygons += spec.wall_outlines()
    for f in spec.furniture:
        polygons += f.at_scan_plane() if layer == "scan" else [f.outline]
    return polygons


def truth_map(spec: WorldSpec, catalogue: Mapping[str, CatalogueEntry], resolution_in: float, *,
              layer: str = "scan", objects: bool = False, margin_in: float = WALL_IN) -> TruthMap:
    """The true occupancy of ``spec`` at ``resolution_in`` inches per cell over the
    room and ``margin_in`` around it (the default takes in the outer walls); objects
    at their start poses too when ``objects``."""
    if not (math.isfinite(resolution_in) and resolution_in > 0):
        raise ValueError(f"truth map resolution must be a number of inches > 0, got {resolution_in!r}")
    x0, y0 = -margin_in, -margin_in
    cols = math.ceil((spec.room_width_in + 2 * margin_in) / resolution_in - 1e-9)
    rows = math.ceil((spec.room_depth_in + 2 * margin_in) / resolution_in - 1e-9)
    grid = TruthMap(np.zeros((rows, cols), dtype=bool), x0, y0, resolution_in)
    polygons = static_polygons(spec, layer)
    if objects:
        polygons += [footprint_polygon(catalogue[p.entry_id].footprint, p.x_in, p.y_in, p.yaw_deg)
                     for p in spec.objects]
    for polygon in polygons:
        _fill_convex(grid, polygon)
    return grid


def _fill_convex(grid: TruthMap, polygon: Polygon) -> None:
    """Mark the cells a convex polygon overlaps with positive area (separating axes:
    the cell's two and the polygon's edge normals)."""
    xs, ys = [p[0] for p in polygon], [p[1] for p in polygon]
    rows, cols = grid.occupied.shape
    r = grid.resolution_in
    c0 = max(0, math.floor((min(xs) - grid.x0_in) / r))
    c1 = min(cols, math.ceil((max(xs) - grid.x0_in) / r))
    r0 = max(0, math.floor((min(ys) - grid.y0_in) / r))
    r1 = min(rows, math.ceil((max(ys) - grid.y0_in) / r))
    if c0 >= c1 or r0 >= r1:
        return
    cx = grid.x0_in + (np.arange(c0, c1) + 0.5) * r
    cy = grid.y0_in + (np.arange(r0, r1) + 0.5) * r
    px, py = np.meshgrid(cx, cy)
    half = r / 2
    overlaps = ((px + half > min(xs)) & (px - half < max(xs)) & (py + half > min(ys)) & (py - half < max(ys)))
    for (x1, y1), (x2, y2) in zip(polygon, polygon[1:] + polygon[:1]):
        nx, ny = y2 - y1, x1 - x2
        norm = math.hypot(nx, ny)
        if norm == 0:
            continue
        nx, ny = nx / norm, ny / norm
        projected = [nx * x + ny * y for x, y in polygon]
        centre, reach = nx * px + ny * py, half * (abs(nx) + abs(ny))
        overlaps &= (centre + reach > min(projected) + 1e-9) & (centre - reach < max(projected) - 1e-9)
    grid.occupied[r0:r1, c0:c1] |= overlaps


def write_png(path: str | Path, grid: TruthMap, spec: WorldSpec, pixels_per_cell: int = 2) -> Path:
    """The map as a PNG, north (+y) up: occupied cells black, free white, each named
    room's name written at the middle of its outline. Returns the path written."""
    if pixels_per_cell < 1:
        raise ValueError(f"pixels_per_cell must be >= 1, got {pixels_per_cell}")
    image = np.where(grid.occupied[::-1], 0, 255).astype(np.uint8)
    image = np.repeat(np.repeat(image, pixels_per_cell, axis=0), pixels_per_cell, axis=1)
    image = cv2.cvtColor(image, cv2.COLOR_GRAY2BGR)
    rows = grid.occupied.shape[0]
    for room in spec.home.rooms:
        x = sum(p[0] for p in room.outline) / len(room.outline)
        y = sum(p[1] for p in room.outline) / len(room.outline)
        row, col = grid.cell_of(x, y)
        (w, h), _ = cv2.getTextSize(room.name, cv2.FONT_HERSHEY_SIMPLEX, 0.5, 1)
        origin = (int(col * pixels_per_cell - w / 2), int((rows - 1 - row) * pixels_per_cell + h / 2))
        for colour, thickness in (((255, 255, 255), 3), ((160, 90, 0), 1)):  # a white halo: legible on furniture
            cv2.putText(image, room.name, origin, cv2.FONT_HERSHEY_SIMPLEX, 0.5, colour, thickness, cv2.LINE_AA)
    out = Path(path)
    if not cv2.imwrite(str(out), image):
        raise OSError(f"{out}: cannot write the truth map image")
    return out
