"""Overhead vision: object regions, furniture and the robot's own pose from one image.

Real camera images (a calibrated :class:`~planner.segmentation.Camera` given) are cut
up by :mod:`planner.segmentation`; the rest of this docstring is about band images.
The camera cannot identify objects; it tells things apart by the intensity bands of
docs/conventions.md (:mod:`camera_model.bands`: floor 30, walls/furniture 110, robot
170, heading marker 250, objects 220, noise within ±12). Band limits sit halfway
between neighbouring levels, so noise never moves a pixel into the wrong band. Where two levels meet, blurring (and
fish-eye undistortion) leaves thin rims of in-between intensities: a rim of "furniture"
around every object and a rim of "object" around the heading marker. Furniture and the
robot body are therefore opened (they are thick, rims are not), and object pixels near
the robot are ignored; objects themselves are never eroded because the smallest test
object (2 in) is only 2-3 pixels across.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import cv2
import numpy as np

from camera_model.bands import MARKER_BAND, OBJECT_BAND, ROBOT_BAND, WALL_BAND
from camera_model.image import CameraImage
from planner.geometry import Pose, counter_clockwise, wrap_360
from planner.image import undistorted
from planner.segmentation import Camera, segment


MIN_OBJECT_PIXELS = 2  # one stray pixel is not an object
MIN_ROBOT_PIXELS = 40  # the HERO's base covers ~400 pixels at 0.8 in/pixel
OUTLINE_UPSAMPLE = 4  # sub-pixel outline tracing
ROBOT_RIM_PX = 2  # blurred rim around the robot that must not count as anything else

# A footprint is round when its second moments are nearly isotropic and, for regions
# big enough to tell, it fills its circumscribed circle (a square fills 64 %). Below
# ROUND_CHECK_MIN_PIXELS pixelisation makes discs and squares look alike (an upright
# soda can is ~17 pixels), and such a small near-isotropic blob shows no usable axis
# anyway; the 5 x 4 in upright box sits on the edge and is sometimes called round.
ROUND_AXIS_RATIO = 0.78
ROUND_FILL_RATIO = 0.75
ROUND_CHECK_MIN_PIXELS = 100

# Touching objects (docs/planner.md "Clutter"): a blob is cut at a pinch only when two
# outline defects are this deep (pixels; a rasterised convex footprint's are under 1),
# each piece keeps at least this many pixels, and the cut between the defects is no
# longer than this share of the smaller piece's width (a pinch, not a notch).
SPLIT_DEPTH_PX = 1.25
MIN_SPLIT_PIXELS = 3
SPLIT_NECK_RATIO = 1.0
# An outline of at least CLUSTER_CHECK_MIN_PIXELS filling less of its convex hull than
# CLUSTER_SOLIDITY is a cluster of objects. A lone catalogue object fills 0.88 or more
# on clean band images, but the fish-eye camera of the `paper` noise preset roughens
# outlines: over 960 lone objects of 40 test floors, down to 0.748 at 30 pixels or more,
# and smaller ones (a 2 in box, 4-10 pixels) as low as 0.64. Two objects merged at under
# an inch apart mostly fill 0.68-0.91, so one image tells only the clearest; objects
# that were seen apart and came to touch are told by the image before
# (planner/merging.py, docs/planner.md "Clutter").
CLUSTER_SOLIDITY = 0.72
CLUSTER_CHECK_MIN_PIXELS = 20

_CROSS = cv2.getStructuringElement(cv2.MORPH_RECT, (3, 3))


@dataclass(frozen=True)
class Region:
    """One object as the overhead camera sees it, in world inches.

    ``orientation_deg`` is the major axis pointing into the half with more pixels (None
    for a round footprint, whose reference axis is world +x by convention);
    ``length_in`` and ``width_in`` are the footprint's extents along and across the
    reference axis. ``pixel_count`` is what the side-effect check after a failed grasp
    compares (pushed: about the same; changed: clearly different); on a real image it
    is the covered area in pixels, to a fraction of one. ``area_in2`` (pixels
    times pixel area) and ``elongation`` (major over minor axis of the pixels' second
    moments) are the footprint's rotation-invariant measures, the object's appearance
    (docs/library-format.md); None on a region not measured from pixels.
    ``cluster``: the outline is too far from convex for one footprint (every catalogue
    footprint is convex) and could not be cut at a pinch (:func:`split_touching`): two
    or more objects touching that vision cannot tell apart (docs/planner.md "Clutter").
    """

    polygon: tuple[tuple[float, float], ...]
    centroid: tuple[float, float]
    pixel_count: int
    orientation_deg: float | None
    round: bool
    length_in: float
    width_in: float
    area_in2: float | None = None
    elongation: float | None = None
    cluster: bool = False

    @property
    def reference_axis_deg(self) -> float:
        """The axis positions are measured from: the orientation, or 0 when round."""
        return 0.0 if self.orientation_deg is None else self.orientation_deg

    def polygon_array(self) -> np.ndarray:
        """The polygon as an Nx2 float array (counter-clockwise in the world frame)."""
        return np.asarray(self.polygon, dtype=float)


@dataclass(frozen=True, eq=False)
class Scene:
    """Everything one overhead image tells: regions, the robot's pose, obstacle masks.

    The masks are on the undistorted image's pixel grid: ``furniture`` holds walls and
    furniture, ``objects`` the object regions' pixels; neither contains the robot.
    """

    image: CameraImage
    regions: tuple[Region, ...]
    robot: Pose | None
    furniture: np.ndarray
    objects: np.ndarray


def look(image: CameraImage, camera: Camera | None = None) -> Scene:
    """Segment an overhead image: by the grey bands (undistorting it first when it is
    fish-eye), or, given a calibrated ``camera``, rectified onto the floor and compared
    with its empty floor (:mod:`planner.segmentation`, docs/camera.md)."""
    image.check()
    if camera is not None:
        flat = camera.calibration.rectify(image.pixels)
        masks = segment(flat, camera.empty_floor)
        body, marker = masks.robot_body, masks.robot_marker
        furniture, objects, brightness = masks.obstacles, masks.objects, masks.brightness
    else:
        flat = undistorted(image)
        pixels = np.ascontiguousarray(flat.pixels, dtype=np.uint8)
        body_mask = _robot_body(pixels)
        not_robot = cv2.dilate(body_mask, _CROSS, iterations=ROBOT_RIM_PX) == 0
        body = body_mask > 0
        marker = (_band(pixels, MARKER_BAND) > 0) & body
        furniture = (cv2.morphologyEx(_band(pixels, WALL_BAND), cv2.MORPH_OPEN, _CROSS) > 0) & not_robot
        objects = (_band(pixels, OBJECT_BAND) > 0) & not_robot
        brightness = None

    regions, region_pixels = _regions(flat, objects, brightness)
    return Scene(
        image=flat,
        regions=regions,
        robot=_robot_pose(flat, body, marker),
        furniture=furniture,
        objects=region_pixels,
    )


def _band(pixels: np.ndarray, band: tuple[int, int]) -> np.ndarray:
    return cv2.inRange(pixels, np.array([band[0]], np.uint8), np.array([band[1]], np.uint8))


def _robot_body(pixels: np.ndarray) -> np.ndarray:
    """The robot's filled disc (marker included) as a 0/255 mask; empty when absent."""
    # Closing bridges the blurred rim between marker and body; opening then drops the
    # thin robot-band rims that blurring leaves around objects.
    body = cv2.bitwise_or(_band(pixels, ROBOT_BAND), _band(pixels, MARKER_BAND))
    body = cv2.morphologyEx(body, cv2.MORPH_CLOSE, _CROSS)
    body = cv2.morphologyEx(body, cv2.MORPH_OPEN, _CROSS)
    contours, _ = cv2.findContours(body, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    filled = np.zeros_like(body)
    if contours:
        largest = max(contours, key=cv2.contourArea)
        if cv2.contourArea(largest) >= MIN_ROBOT_PIXELS:
            cv2.drawContours(filled, [largest], -1, 255, thickness=cv2.FILLED)
    return filled


def _robot_pose(image: CameraImage, body: np.ndarray, marker: np.ndarray) -> Pose | None:
    """Base centre from the body's centroid, heading towards the marker's centroid."""
    body_m = cv2.moments(body.astype(np.uint8), binaryImage=True)
    marker_m = cv2.moments(marker.astype(np.uint8), binaryImage=True)
    if body_m["m00"] == 0 or marker_m["m00"] == 0:
        return None
    (cx, cy), (mx, my) = (
        image.to_world(body_m["m01"] / body_m["m00"], body_m["m10"] / body_m["m00"])[0],
        image.to_world(marker_m["m01"] / marker_m["m00"], marker_m["m10"] / marker_m["m00"])[0],
    )
    heading = wrap_360(math.degrees(math.atan2(my - cy, mx - cx)))
    return Pose(float(cx), float(cy), heading)


def _regions(image: CameraImage, objects: np.ndarray,
             brightness: np.ndarray | None = None) -> tuple[tuple[Region, ...], np.ndarray]:
    """Object regions and the mask of the pixels that belong to a kept region; given a
    real image's ``brightness``, pixel counts are its sub-pixel object areas
    (:func:`_covered_pixels`).

    A blob is 4-connected: pixels meeting only at a corner are apart. The fish-eye
    camera's undistortion resamples to the nearest pixel and so can repeat a pixel
    that bridges a one-pixel gap diagonally, joining two objects cluttered 1 in apart far
    more often with 8-connected blobs than with 4-connected ones, while a lone object
    falls apart with neither (BENCHMARKS.md, "Clutter")."""
    on = np.asarray(objects, dtype=bool)
    count, labels, stats, _ = cv2.connectedComponentsWithStats(on.astype(np.uint8), connectivity=4)
    kept = np.zeros(on.shape, dtype=bool)
    regions = []
    for label in range(1, count):
        col, row, width, height = (int(v) for v in stats[label, :4])
        blob = (labels[row:row + height, col:col + width] == label).astype(np.uint8)
        for roi in split_touching(blob):
            region = _kept_region(image, roi, row, col, on, brightness, kept)
            if region is not None:
                regions.append(region)
    regions.sort(key=lambda r: (r.centroid[0], r.centroid[1]))
    return tuple(regions), kept


def _kept_region(image: CameraImage, roi: np.ndarray, row: int, col: int, on: np.ndarray,
                 brightness: np.ndarray | None, kept: np.ndarray) -> Region | None:
    """One object's region from its 0/1 pixel mask within the blob's box at (row, col),
    marked in ``kept``; None when it is too small to be an object."""
    height, width = roi.shape
    count = int(roi.sum())
    if count < MIN_OBJECT_PIXELS:
        return None
    kept[row:row + height, col:col + width] |= roi.astype(bool)
    region = _describe(image, roi, row, col)
    if brightness is not None:
        covered = _covered_pixels(brightness, on, roi, row, col)
        region = dataclasses.replace(region, pixel_count=covered, area_in2=covered * image.inches_per_pixel ** 2)
    return region


def split_touching(blob: np.ndarray) -> list[np.ndarray]:
    """A blob of object pixels (0/1 mask) as one mask per object: objects touching or
    closer than a pixel (docs/planner.md "Clutter") show as one blob pinched where they
    meet, and it is cut there.

    Every catalogue footprint is convex, so a blob whose outline has two convexity
    defects at least :data:`SPLIT_DEPTH_PX` deep is two footprints meeting: the cut
    joins the two deepest defects' far points, and it is kept only when it leaves two
    pieces of at least :data:`MIN_SPLIT_PIXELS` each and is no longer than
    :data:`SPLIT_NECK_RATIO` of the smaller piece's width (a pinch, not a notch). The
    cut's own pixels go to the nearer piece; each piece is split again (a trio).
    """
    contours, _ = cv2.findContours(blob, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    if len(contours) != 1 or len(contours[0]) < 5:
        return [blob]
    contour = contours[0]
    hull = cv2.convexHull(contour, returnPoints=False)
    try:
        defects = cv2.convexityDefects(contour, hull)
    except cv2.error:  # a self-touching outline OpenCV cannot take: leave it whole
        return [blob]
    if defects is None:
        return [blob]
    deep = sorted((d for d in defects.reshape(-1, 4) if d[3] / 256.0 >= SPLIT_DEPTH_PX), key=lambda d: -d[3])[:2]
    if len(deep) < 2:
        return [blob]
    a, b = (tuple(int(v) for v in contour[d[2], 0]) for d in deep)
    cut = blob.copy()
    cv2.line(cut, a, b, 0, thickness=1)
    count, labels = cv2.connectedComponents(cut, connectivity=4)
    sizes = [int((labels == k).sum()) for k in range(1, count)]
    if count != 3 or min(sizes) < MIN_SPLIT_PIXELS:
        return [blob]
    neck = math.hypot(a[0] - b[0], a[1] - b[1]) - 1.0  # between the far points, themselves outline pixels
    if neck > SPLIT_NECK_RATIO * min(_width_px(labels == k) for k in (1, 2)):
        return [blob]
    # the cut's pixels to the nearer piece
    _, nearest = cv2.distanceTransformWithLabels((labels == 0).astype(np.uint8), cv2.DIST_L2, 3,
                                                 labelType=cv2.DIST_LABEL_PIXEL)
    zero_rows, zero_cols = np.nonzero(labels != 0)
    owner = np.zeros(int(nearest.max()) + 1, np.int32)
    owner[nearest[zero_rows, zero_cols]] = labels[zero_rows, zero_cols]
    full = np.where((labels == 0) & (blob > 0), owner[nearest], labels)
    return [piece for k in (1, 2) for piece in split_touching((full == k).astype(np.uint8) & blob)]


def _width_px(mask: np.ndarray) -> float:
    """A piece's smaller extent, in pixels (its minimum-area rectangle's short side)."""
    points = np.column_stack(np.nonzero(mask)[::-1]).astype(np.float32)
    (_, _), (w, h), _ = cv2.minAreaRect(points)
    return min(w, h) + 1.0  # centre to centre, plus the pixels' own halves


def _covered_pixels(brightness: np.ndarray, objects: np.ndarray, roi: np.ndarray, row0: int, col0: int) -> int:
    """How many pixels' worth of the image the object covers, to a fraction of a pixel.

    On a real image a pixel is lighter over the floor in proportion to how much of it
    the object covers, so each pixel of the region and of the one-pixel rim around it
    (what the threshold left out) counts ``(b - 1) / (peak - 1)``, clipped to 0..1, with
    ``b`` its brightness over the empty floor and ``peak`` the region's (90th
    percentile). A count of whole pixels over the threshold jumps by a pixel or two as
    a small object moves across the grid (a 2 in box covers ~6 pixels, so by a third):
    the side-effect check would call a pushed object "changed". The object's shading
    is its own wherever it stands, so the count follows the object, not the grid; the
    shading also makes it read low (edges darker than the peak: ~0.83 of the true
    area on the realistic preset, BENCHMARKS.md), the same for the object everywhere.
    """
    rows, cols = brightness.shape
    r0, c0 = max(row0 - 1, 0), max(col0 - 1, 0)
    r1, c1 = min(row0 + roi.shape[0] + 1, rows), min(col0 + roi.shape[1] + 1, cols)
    region = np.zeros((r1 - r0, c1 - c0), bool)
    region[row0 - r0:row0 - r0 + roi.shape[0], col0 - c0:col0 - c0 + roi.shape[1]] = roi > 0
    rim = (cv2.dilate(region.astype(np.uint8), _CROSS) > 0) & ~objects[r0:r1, c0:c1]
    window = brightness[r0:r1, c0:c1]
    peak = float(np.percentile(window[region], 90))
    share = np.clip((window - 1.0) / max(peak - 1.0, 1e-3), 0.0, 1.0)
    return max(int(round(float(share[region].sum() + share[rim].sum()))), 1)


def _describe(image: CameraImage, roi: np.ndarray, row0: int, col0: int) -> Region:
    """Centroid, axis, polygon and sizes of one region (``roi`` is its 0/1 pixel mask)."""
    ipp = image.inches_per_pixel
    moments = cv2.moments(roi, binaryImage=True)
    count = int(moments["m00"])
    c_mean, r_mean = moments["m10"] / count, moments["m01"] / count
    # Second moments of the pixel squares (a unit square adds 1/12 to each variance).
    mu_cc = moments["mu20"] / count + 1 / 12
    mu_rr = moments["mu02"] / count + 1 / 12
    mu_rc = moments["mu11"] / count
    spread = math.hypot(mu_cc - mu_rr, 2 * mu_rc)
    major, minor = (mu_cc + mu_rr + spread) / 2, (mu_cc + mu_rr - spread) / 2
    axis_ratio = math.sqrt(max(minor, 0.0) / major)

    polygon_px = _outline(roi)  # (col, row) within the roi
    world_polygon = image.to_world(polygon_px[:, 1] + row0, polygon_px[:, 0] + col0)
    centroid = image.to_world(r_mean + row0, c_mean + col0)[0]

    is_round = axis_ratio >= ROUND_AXIS_RATIO and (
        count < ROUND_CHECK_MIN_PIXELS or _fill_ratio(world_polygon, centroid) >= ROUND_FILL_RATIO
    )
    if is_round:
        orientation = None
        axis_deg = 0.0
    else:
        if axis_ratio >= ROUND_AXIS_RATIO:
            # Nearly isotropic but cornered (a square box): moments give no stable
            # axis, the minimum-area rectangle's sides do.
            axis_deg = _rectangle_axis_deg(world_polygon)
        else:
            # Image rows grow downwards, so the world angle flips the row term.
            axis_deg = math.degrees(math.atan2(-2 * mu_rc, mu_cc - mu_rr)) / 2
        rows, cols = np.nonzero(roi)
        dr, dc = rows - r_mean, cols - c_mean
        along = dc * math.cos(math.radians(axis_deg)) - dr * math.sin(math.radians(axis_deg))
        if np.count_nonzero(along < -1e-9) > np.count_nonzero(along > 1e-9):
            axis_deg += 180.0
        orientation = wrap_360(axis_deg)
        axis_deg = orientation

    u = np.array([math.cos(math.radians(axis_deg)), math.sin(math.radians(axis_deg))])
    v = np.array([-u[1], u[0]])
    rel = world_polygon - centroid
    length = float(np.ptp(rel @ u))
    width = float(np.ptp(rel @ v))
    return Region(
        polygon=tuple((float(x), float(y)) for x, y in counter_clockwise(world_polygon)),
        centroid=(float(centroid[0]), float(centroid[1])),
        pixel_count=count,
        orientation_deg=orientation,
        round=is_round,
        length_in=max(length, ipp),
        width_in=max(width, ipp),
        area_in2=count * ipp * ipp,
        elongation=1.0 / axis_ratio,  # the +1/12 pixel-square term keeps minor > 0
        cluster=count >= CLUSTER_CHECK_MIN_PIXELS and _solidity(world_polygon) < CLUSTER_SOLIDITY,
    )


def _solidity(polygon: np.ndarray) -> float:
    """The outline's area over its convex hull's (1 for a convex outline)."""
    points = polygon.astype(np.float32)
    hull = abs(float(cv2.contourArea(cv2.convexHull(points))))
    return abs(float(cv2.contourArea(points))) / hull if hull > 0 else 1.0


def _outline(roi: np.ndarray) -> np.ndarray:
    """The footprint's outline in (col, row) pixel units of the region's mask.

    A camera pixel shows an object when the object covers at least half of it, so the
    true outline runs, on average, halfway between object pixel centres and their
    non-object neighbours: the mask's 50 % iso-line. It is traced on a bilinearly
    upsampled copy of the mask (marching-squares fashion) and simplified; this also
    gives thin regions (a line or a dot of pixels) a proper area.
    """
    scale = OUTLINE_UPSAMPLE
    padded = np.pad(roi.astype(np.uint8) * 255, 1)
    fine = cv2.resize(padded, None, fx=scale, fy=scale, interpolation=cv2.INTER_LINEAR)
    contours, _ = cv2.findContours((fine >= 128).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    points = np.concatenate(contours) if len(contours) > 1 else contours[0]
    if len(contours) > 1:
        points = cv2.convexHull(points)
    simplified = cv2.approxPolyDP(points, 0.75 * scale, closed=True).reshape(-1, 2).astype(float)
    # Fine pixel i's centre is at coarse (i + 0.5) / scale - 0.5; the pad adds one.
    return (simplified + 0.5) / scale - 1.5


def _fill_ratio(polygon: np.ndarray, centroid: np.ndarray) -> float:
    """How much of its circumscribed circle (about the centroid) a polygon fills."""
    radius = float(np.max(np.linalg.norm(polygon - centroid, axis=1)))
    return abs(float(cv2.contourArea(polygon.astype(np.float32)))) / (math.pi * radius * radius)


def _rectangle_axis_deg(polygon: np.ndarray) -> float:
    """Direction of the minimum-area rectangle's longer side (world degrees)."""
    box = cv2.boxPoints(cv2.minAreaRect(polygon.astype(np.float32)))
    sides = [box[1] - box[0], box[2] - box[1]]
    side = max(sides, key=lambda s: float(np.hypot(*s)))
    return math.degrees(math.atan2(float(side[1]), float(side[0])))
