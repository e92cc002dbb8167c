"""The scan-built map as the executive reads a look: a :class:`planner.vision.Scene`.

An overhead image's scene holds the object regions, the robot as seen, and two masks on
the image's pixel grid: ``furniture`` (walls and furniture) and ``objects``. The onboard
map gives the same on the occupancy grid's cells, so every behaviour that reads a scene,
and the planner that builds its map from one (``planner.vision_map.build_vision_map``:
both masks inflated by the base's radius), works on it unchanged:

- ``objects``: the cells of each candidate's region (:func:`candidate_region`);
- ``furniture``: every other cell that is occupied *or unknown* — unknown space is not
  free, so no plan leaves the explored floor or passes closer to it than the base's
  radius (as :func:`mapping.planning.planning_map`); the narrow unknown gaps between a
  far scan's diverging beams excepted (:func:`bridged`);
- ``robot``: the scan matcher's corrected pose;
- ``image``: the grid drawn as a map image (:func:`mapping.planning.map_image`).

A candidate becomes a region as the camera's would: its footprint polygon, centroid,
reference axis (None when round) and extents along and across it. The footprint is
the outline fitted to the returns near it (:func:`mapping.outline.outline`, the
training stage's own fit, so run-time positions are measured from the axis training
measured them from); when the returns cannot be fitted (too few yet, or something else
close by), the minimum-area rectangle of the candidate's thinned outline stands in.
A scan gives no appearance (area and elongation are the camera's pixels): those stay
None, and the learner rules nothing out by appearance.
"""

from __future__ import annotations

import copy
import dataclasses
import math
from collections.abc import Sequence

import cv2
import numpy as np

from mapping.candidates import Candidate
from mapping.occupancy import OccupancyGrid
from mapping.outline import nearest_on_outline, outline
from camera_model.image import CameraImage
from mapping.occupancy import DECIDED, FREE
from mapping.planning import SHADES, map_image
from mapping.scan import PlanarScan
from planner.geometry import Pose, counter_clockwise, wrap_360
from planner.vision import Region, Scene

CROP_MARGIN_IN = 24.0  # the scene reaches this far beyond the floor seen (unknown: blocked)
MIN_SIDE_IN = 1.0
# A region's "pixel count" is its footprint's area in the lab camera's pixels (0.8 in
# square), so the checks that compare counts (pushed or changed) read a scan's region
# at the resolution they were written for, not at the grid's coarser cells.
PIXEL_IN2 = 0.64
SEEN_AT_IN = 2.0
# refit: returns this far beyond a region's half-diagonal may be its object pushed (a
# failed grasp pushes up to about 4 in), at least this many of them, laid on its outline
# within this RMS gap; a shift smaller than the last is the outline's own noise.
REFIT_REACH_IN = 6.0
REFIT_MIN_RETURNS = 4
REFIT_RMS_IN = 1.0
REFIT_MIN_SHIFT_IN = 0.5
REFIT_ITERATIONS = 30  # a return this close to a region's footprint is the region seen again
BRIDGE_CELLS = 5  # unknown gaps up to this many cells across, free on both sides, are free (bridged)
BRIDGED_LOG_ODDS = -2.0 * DECIDED  # what a bridged cell holds: free, as a beam crossing it would say  # a region's extent is at least this (a leg seen edge-on is a line of returns)


def candidate_region(candidate: Candidate, views: Sequence[tuple[PlanarScan, Pose]],
                     range_sigma_in: float) -> Region:
    """The region of ``candidate`` (the module docstring says how), from ``views``, the
    scans at their corrected poses that may hold its returns."""
    centre = (candidate.x_in, candidate.y_in)
    try:
        fitted = outline(views, centre, range_sigma_in)
    except ValueError:
        fitted = None
    if fitted is not None and not np.isfinite(np.asarray(fitted.polygon, dtype=float)).all():
        fitted = None  # a degenerate fit: the candidate's own returns stand in
    if fitted is not None:
        polygon = np.asarray(fitted.polygon, dtype=float)
        centroid = np.asarray(fitted.centre, dtype=float)
        is_round = fitted.round
        axis = 0.0 if is_round else wrap_360(fitted.axis_deg)
    else:
        points = np.asarray(candidate.outline, dtype=np.float32).reshape(-1, 2)
        (cx, cy), (w, h), angle = cv2.minAreaRect(points)
        polygon = cv2.boxPoints(((cx, cy), (max(w, MIN_SIDE_IN), max(h, MIN_SIDE_IN)), angle)).astype(float)
        centroid = np.array([cx, cy], dtype=float)
        is_round = False
        axis = wrap_360(angle if w >= h else angle + 90.0)
    u = np.array([math.cos(math.radians(axis)), math.sin(math.radians(axis))])
    v = np.array([-u[1], u[0]])
    rel = polygon - centroid
    area = abs(float(cv2.contourArea(polygon.astype(np.float32))))
    return Region(
        polygon=tuple((float(x), float(y)) for x, y in counter_clockwise(polygon)),
        centroid=(float(centroid[0]), float(centroid[1])),
        pixel_count=max(1, round(area / PIXEL_IN2)),
        orientation_deg=None if is_round else axis,
        round=is_round,
        length_in=max(float(np.ptp(rel @ u)), MIN_SIDE_IN),
        width_in=max(float(np.ptp(rel @ v)), MIN_SIDE_IN),
    )


def seen_through(region: Region, scan: PlanarScan, pose: Pose) -> bool:
    """True when ``scan``, taken at ``pose``, looks through the place ``region`` lay:
    some beam crosses its footprint, none ends within :data:`SEEN_AT_IN` of it, and none
    ends short of it (an occluder leaves the place unseen). The object is not there now:
    picked up, or moved away. False when a return lies on it, when nothing crossed it,
    or when fewer than half the beams across it came back from beyond (a beam that
    returned nothing may be a dropout)."""
    returned = scan.returned
    h = math.radians(pose.heading_deg)
    bearings = h + scan.angles_rad
    polygon = region.polygon_array().astype(np.float32)
    centre = np.asarray(region.centroid)
    reach = 0.5 * math.hypot(region.length_in, region.width_in) + SEEN_AT_IN
    to_centre = centre - (pose.x_in, pose.y_in)
    distance = float(np.hypot(*to_centre))
    if distance <= reach:
        return False  # standing on it: nothing to tell
    off = np.abs(np.remainder(bearings - math.atan2(to_centre[1], to_centre[0]) + math.pi, 2 * math.pi) - math.pi)
    across = off <= math.asin(min(1.0, reach / distance))
    if not across.any():
        return False
    ranges = np.where(returned, scan.ranges_in, np.inf)[across]
    ends = np.column_stack([pose.x_in + np.cos(bearings[across]) * np.minimum(ranges, 1e6),
                            pose.y_in + np.sin(bearings[across]) * np.minimum(ranges, 1e6)])
    on = [cv2.pointPolygonTest(polygon, (float(x), float(y)), True) >= -SEEN_AT_IN for x, y in ends]
    if any(on) or (ranges < distance - reach).any():
        return False
    beyond = np.isfinite(ranges) & (ranges >= distance)
    return 2 * int(np.count_nonzero(beyond)) >= len(ranges)  # dropouts alone do not say it is gone


def refit(region: Region, returns: np.ndarray) -> Region:
    """``region`` moved to where ``returns`` (world inches: the latest scan's returns off
    the home's structure, near the region) say its object now stands.

    A kept region (the onboard perception keeps a candidate's once it has settled) would
    hide a push: a failed grasp shoves an object an inch or a few, and the map's memory
    of where it stood fades only over scans. So each look fits the region's outline to
    the returns near it by a translation alone (the nearest point of its outline to each
    return, then the mean gap, until it settles): an object the scan sees where its region is
    stays as it was; one pushed comes out shifted by the push, its size unchanged, which
    the checks read as pushed. Returns that no translation within :data:`REFIT_REACH_IN`
    lays on the outline (its RMS gap above :data:`REFIT_RMS_IN`) are not this footprint:
    the region is left as it was, for the checks to judge by what else they see."""
    polygon = region.polygon_array()
    centre = np.asarray(region.centroid)
    reach = 0.5 * math.hypot(region.length_in, region.width_in) + REFIT_REACH_IN
    near = returns[np.hypot(*(returns - centre).T) <= reach] if len(returns) else returns
    if len(near) < REFIT_MIN_RETURNS:
        return region
    shift = np.zeros(2)
    for _ in range(REFIT_ITERATIONS):
        step = (near - nearest_on_outline(near, polygon + shift)).mean(axis=0)
        shift += step
        if float(np.hypot(*step)) < 0.01:
            break
    rms = float(np.sqrt(np.mean(np.sum((near - nearest_on_outline(near, polygon + shift)) ** 2, axis=1))))
    if rms > REFIT_RMS_IN or float(np.hypot(*shift)) > REFIT_REACH_IN or float(np.hypot(*shift)) < REFIT_MIN_SHIFT_IN:
        return region
    dx, dy = float(shift[0]), float(shift[1])
    return dataclasses.replace(region, polygon=tuple((x + dx, y + dy) for x, y in region.polygon),
                               centroid=(region.centroid[0] + dx, region.centroid[1] + dy))


def map_scene(grid: OccupancyGrid, regions: Sequence[Region], robot: Pose | None,
              margin_in: float = CROP_MARGIN_IN, keep_out: Sequence[np.ndarray] = ()) -> Scene:
    """The scene of the map as it stands (the module docstring says how; ``grid``
    bridged already: :func:`bridged`), cropped to
    the floor seen so far and ``margin_in`` round it (and the robot): what lies beyond is
    unknown, hence blocked, and a planner sampling it would only waste its samples.
    ``keep_out``: polygons (Nx2, world inches) the base cannot enter though the scans see
    nothing there (a table's top, a place the bumper met): furniture of the scene."""
    image = _cropped(map_image(grid), grid, robot, margin_in)
    objects = _filled(image, [region.polygon_array() for region in regions])
    blocked = image.pixels != SHADES[FREE]
    return with_keep_out(Scene(image=image, regions=tuple(regions), robot=robot,
                               furniture=blocked & ~objects, objects=objects), keep_out)


def with_keep_out(scene: Scene, keep_out: Sequence[np.ndarray]) -> Scene:
    """``scene`` with the cells inside ``keep_out`` (polygons, world inches) furniture as
    well, where they are not an object's."""
    if not keep_out:
        return scene
    return dataclasses.replace(scene, furniture=scene.furniture | (_filled(scene.image, keep_out) & ~scene.objects))


def _filled(image: CameraImage, polygons: Sequence[np.ndarray]) -> np.ndarray:
    """The image's cells inside any of ``polygons`` (world inches), as a mask."""
    mask = np.zeros(image.shape, dtype=np.uint8)
    for polygon in polygons:
        rows, cols = image.grid.to_cell(polygon[:, 0], polygon[:, 1])
        corners = np.column_stack([cols, rows]) - 0.5  # pixel centres at whole numbers
        cv2.fillPoly(mask, [np.round(corners).astype(np.int32)], 1)
    return mask.astype(bool)


def bridged(grid: OccupancyGrid) -> OccupancyGrid:
    """A copy of ``grid`` with the unknown gaps between neighbouring beams taken as free.

    A scan's beams spread apart with range (a degree apart: 2 in at 115 in, 4 in at
    230 in), and some return nothing (a dropout), so floor a scan swept far off is free
    in stripes and speckles with unknown between: inflated like obstacles, they would
    wall in floor the robot has seen. An unknown gap narrower than
    :data:`BRIDGE_CELLS` with free floor on both sides is taken as free (morphological
    closing), unless it lies within that distance of an occupied cell: a small object
    hit by a beam or two is an occupied cell amid unknown ones, and the unknown round it
    is where the rest of it may be. The planner's map and the exploration's
    standing room are both read from the bridged grid."""
    free, occupied = grid.free, grid.occupied
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (BRIDGE_CELLS, BRIDGE_CELLS))
    closed = cv2.morphologyEx(free.astype(np.uint8), cv2.MORPH_CLOSE, kernel).astype(bool)
    near_hit = cv2.dilate(occupied.astype(np.uint8), kernel).astype(bool)
    out = copy.copy(grid)
    out.log_odds = grid.log_odds.copy()
    out.log_odds[closed & ~free & ~near_hit] = BRIDGED_LOG_ODDS
    return out


def _cropped(image: CameraImage, grid: OccupancyGrid, robot: Pose | None, margin_in: float) -> CameraImage:
    seen = ~grid.unknown
    if robot is not None:
        cell = grid.cell_of(robot.x_in, robot.y_in)
        if cell is not None:
            seen = seen.copy()
            seen[cell] = True
    rows, cols = np.nonzero(seen)
    if len(rows) == 0:
        return image
    m = math.ceil(margin_in / grid.inches_per_cell)
    r0, r1 = max(int(rows.min()) - m, 0), min(int(rows.max()) + m + 1, grid.shape[0])
    c0, c1 = max(int(cols.min()) - m, 0), min(int(cols.max()) + m + 1, grid.shape[1])
    s = image.inches_per_pixel
    return CameraImage(pixels=np.ascontiguousarray(image.pixels[r0:r1, c0:c1]), inches_per_pixel=s,
                       origin_x_in=image.origin_x_in + c0 * s, origin_y_in=image.origin_y_in - r0 * s)
