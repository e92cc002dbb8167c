"""A scan-built map as the planner plans on it: the same :class:`planner.vision_map.VisionMap`.

The planner reads from its map only the floor grid (origin, cell size, shape), the
``free`` and ``free_strict`` cells, the inflation and a key; the image in it serves for
its floor grid. So the scan-built map is handed over as a VisionMap whose image is the
occupancy grid drawn as a map image (the usual convention: light free, mid-grey unknown,
black occupied), and the OMPL planner, its roadmap and the move-cost estimate work on it
unchanged (one map interface, two sources).

Unknown space is not free: it is inflated by the base's radius like an obstacle, so no
path leaves the explored space or passes closer to it than the base's radius. The
inflation margin is the vision map's (base radius plus (1 + √½) cells: an obstacle may
lie anywhere in its cell, and the base anywhere in its own).
"""

from __future__ import annotations

import hashlib
import math

import numpy as np

from camera_model.image import CameraImage
from mapping.occupancy import FREE, OCCUPIED, UNKNOWN, OccupancyGrid
from planner.vision_map import VisionMap, inflated_map

# Grey levels of the map image (those of the ROS map_server's PGM images).
SHADES = {FREE: 254, UNKNOWN: 205, OCCUPIED: 0}


def map_image(grid: OccupancyGrid) -> CameraImage:
    """The grid drawn as a grayscale map image on its own floor grid (also what map.png shows)."""
    states = grid.states()
    pixels = np.full(states.shape, SHADES[UNKNOWN], dtype=np.uint8)
    pixels[states == FREE] = SHADES[FREE]
    pixels[states == OCCUPIED] = SHADES[OCCUPIED]
    g = grid.grid
    return CameraImage(pixels=pixels, inches_per_pixel=g.inches_per_pixel, origin_x_in=g.origin_x_in,
                       origin_y_in=g.origin_y_in)


def planning_map(grid: OccupancyGrid, base_radius_in: float) -> VisionMap:
    """The map the OMPL planner plans on: occupied and unknown cells inflated by
    ``base_radius_in``; ``free`` is where the base centre may stand."""
    if not (math.isfinite(base_radius_in) and base_radius_in >= 0):
        raise ValueError(f"base_radius_in must be finite and not negative, got {base_radius_in}")
    image = map_image(grid)
    blocked = image.pixels != SHADES[FREE]
    digest = hashlib.blake2b(digest_size=16)
    digest.update(repr(("scan map", image.shape, grid.inches_per_cell, image.origin_x_in, image.origin_y_in,
                        base_radius_in)).encode())
    digest.update(np.packbits(blocked).tobytes())
    return inflated_map(image, blocked, base_radius_in, digest.hexdigest())
