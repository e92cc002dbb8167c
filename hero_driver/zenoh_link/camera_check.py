"""Does a driver's overhead image show things where they are?

A camera reply can decode perfectly and still ruin every episode: rows counted from
the bottom put each object at its mirror-image place, objects drawn at another grey
level are no objects to the vision, and objects drawn off their place send the robot
to empty floor. The conformance suite knows the position of two kinds of thing: the
robot itself, which must lie around the published pose with its heading marker ahead
of it; and the objects a ``reset`` to a known world placed, each of which must be seen
around its place, at about its size.

A band image (docs/driver-protocol.md) is read here by its grey levels
(:mod:`camera_model.bands`): the base (140-194) with the marker (235-255) and nothing
else in the robot's levels, the objects in 195-234. A real camera's image has no
bands; it is read through the executive's own vision and the camera's calibration
(:func:`calibrated_reader`, docs/camera.md), the way an episode will read it, and the
same tolerances apply to what that vision sees.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from camera_model.bands import MARKER_BAND, OBJECT_BAND, ROBOT_BAND, WALL_BAND, in_band
from camera_model.fisheye import undistortion_maps
from camera_model.floor_grid import FloorGrid
from camera_model.image import CameraImage
from hero_driver.interface import Pose

CENTRE_TOLERANCE_IN = 4.0  # base centroid vs published position (odometry, pixelisation)
HEADING_TOLERANCE_DEG = 25.0  # marker bearing vs published heading (a small marker, few pixels)
SEARCH_IN = 12.0  # how far from the published position a robot blob may start
STRAY_PIXELS = 4  # robot-level pixels away from the robot tolerated (noise survivors)
OBJECT_TOLERANCE_IN = 3.0  # footprint centroid vs where reset placed the object
OBJECT_AREA_RATIO = 2.0  # drawn area within a factor of the footprint's (side-effect checks count pixels)
_OPEN = cv2.getStructuringElement(cv2.MORPH_RECT, (3, 3))


class MappingError(ValueError):
    """The image does not show the robot as the protocol requires; one line."""


def undistorted(image: CameraImage) -> np.ndarray:
    """The pixels with the fish-eye lens removed (nearest-neighbour, so no grey level is
    invented along edges), or as they are when the image carries no lens."""
    if image.fisheye is None or image.camera_matrix is None:
        return image.pixels
    rows, cols = image.pixels.shape
    map_x, map_y = undistortion_maps(np.asarray(image.camera_matrix, dtype=np.float64), image.fisheye, rows, cols)
    return cv2.remap(image.pixels, map_x, map_y, interpolation=cv2.INTER_NEAREST,
                     borderMode=cv2.BORDER_CONSTANT, borderValue=0)


def _band(pixels: np.ndarray, band: tuple[int, int]) -> np.ndarray:
    return in_band(pixels, band).astype(np.uint8)


def _grid(image: CameraImage) -> FloorGrid:
    return FloorGrid(image.inches_per_pixel, image.origin_x_in, image.origin_y_in)


def _world(image: CameraImage, rows: np.ndarray, cols: np.ndarray) -> tuple[float, float]:
    """The world position of the mean of pixel centres (docs/driver-protocol.md)."""
    x, y = _grid(image).to_world(float(np.mean(rows)), float(np.mean(cols)))[0]
    return float(x), float(y)


@dataclass(frozen=True)
class _DrawnRobot:
    """The robot as a band image draws it: its pose (base centroid, marker bearing)
    and how many pixels in its levels lie off its blob."""

    pose: Pose
    stray_pixels: int


def _find_robot(image: CameraImage, pose: Pose) -> _DrawnRobot:
    """The robot-level blob nearest ``pose``, read; MappingError when there is none
    within SEARCH_IN or it carries no heading marker."""
    pixels = undistorted(image)
    robot = cv2.morphologyEx(_band(pixels, ROBOT_BAND) | _band(pixels, MARKER_BAND), cv2.MORPH_OPEN, _OPEN)
    count, labels = cv2.connectedComponents(robot, connectivity=8)
    s = image.inches_per_pixel
    row, col = _grid(image).to_pixel(pose.x_in, pose.y_in)
    best, best_in = 0, math.inf
    for label in range(1, count):
        rows, cols = np.nonzero(labels == label)
        gap_in = s * float(np.min(np.hypot(rows - row, cols - col)))
        if gap_in < best_in:
            best, best_in = label, gap_in
    if best == 0 or best_in > SEARCH_IN:
        mirrored = pixels.shape[0] - 1 - row
        hint = (" (it is at the row-mirrored place: rows must count down from the high-y edge)"
                if _blob_near(labels, count, mirrored, col, SEARCH_IN / s) else "")
        raise MappingError(f"no robot (levels {ROBOT_BAND[0]}-{ROBOT_BAND[1]}) drawn within {SEARCH_IN:g} in "
                           f"of the published position ({pose.x_in:.1f}, {pose.y_in:.1f}){hint}")
    rows, cols = np.nonzero(labels == best)
    x, y = _world(image, rows, cols)
    marker = (labels == best) & (_band(pixels, MARKER_BAND) > 0)
    if not marker.any():
        raise MappingError(f"no heading marker (levels {MARKER_BAND[0]}-{MARKER_BAND[1]}) on the robot's base")
    mx, my = _world(image, *np.nonzero(marker))
    bearing = math.degrees(math.atan2(my - y, mx - x))
    return _DrawnRobot(Pose(x, y, bearing), int(robot.sum()) - len(rows))


def robot_drawn(image: CameraImage, pose: Pose) -> Pose:
    """Where a band image draws the robot found near ``pose``: its base's centroid and
    the bearing of its heading marker from there (degrees CCW from +x); MappingError
    when no robot with a marker is drawn near ``pose``. For checks that compare two
    images (did the robot turn as it said?)."""
    return _find_robot(image, pose).pose


def check_robot_drawn(image: CameraImage, pose: Pose) -> str:
    """A one-line account of where the robot was found; MappingError when the base is
    not at ``pose``, the marker not ahead of it, or other things share its levels."""
    drawn = _find_robot(image, pose)
    x, y, bearing = drawn.pose.x_in, drawn.pose.y_in, drawn.pose.heading_deg
    off_in = math.hypot(x - pose.x_in, y - pose.y_in)
    if off_in > CENTRE_TOLERANCE_IN:
        raise MappingError(f"the robot's base is drawn at ({x:.1f}, {y:.1f}), {off_in:.1f} in from the published "
                           f"position ({pose.x_in:.1f}, {pose.y_in:.1f}); at most {CENTRE_TOLERANCE_IN:g} in")
    turn = (bearing - pose.heading_deg + 180.0) % 360.0 - 180.0
    if abs(turn) > HEADING_TOLERANCE_DEG:
        raise MappingError(f"the heading marker points to {bearing:.0f} deg, the published heading is "
                           f"{pose.heading_deg:.0f} deg (rows counted the wrong way flip it)")
    if drawn.stray_pixels > STRAY_PIXELS:
        raise MappingError(f"{drawn.stray_pixels} pixels away from the robot are drawn in its levels "
                           f"{ROBOT_BAND[0]}-{ROBOT_BAND[1]}: objects belong at "
                           f"{OBJECT_BAND[0]}-{OBJECT_BAND[1]}, furniture at {WALL_BAND[0]}-{WALL_BAND[1]}")
    return (f"robot drawn at ({x:.1f}, {y:.1f}) heading {bearing:.0f} deg, {off_in:.1f} in from the published pose")


def _blob_near(labels: np.ndarray, count: int, row: float, col: float, radius_px: float) -> bool:
    for label in range(1, count):
        rows, cols = np.nonzero(labels == label)
        if float(np.min(np.hypot(rows - row, cols - col))) <= radius_px:
            return True
    return False


@dataclass(frozen=True)
class PlacedObject:
    """An object a world file puts on the floor: its centre and footprint area."""

    name: str
    x_in: float
    y_in: float
    area_in2: float


def check_objects_drawn(image: CameraImage, objects: Sequence[PlacedObject]) -> str:
    """A one-line account of how far the drawn objects lie from their places;
    MappingError naming the first object that is missing, off its place by more than
    OBJECT_TOLERANCE_IN, or drawn at another size.

    Each object is matched to the object-level blob nearest its centre (no opening:
    an upright bottle is a handful of pixels, and no other level reaches this band
    through the protocol's pixel noise)."""
    pixels = undistorted(image)
    count, labels = cv2.connectedComponents(_band(pixels, OBJECT_BAND), connectivity=8)
    blobs = [np.nonzero(labels == label) for label in range(1, count)]
    s = image.inches_per_pixel
    worst = 0.0
    for placed in objects:
        row, col = _grid(image).to_pixel(placed.x_in, placed.y_in)
        gaps = [s * float(np.min(np.hypot(rows - row, cols - col))) for rows, cols in blobs]
        if not gaps or min(gaps) > SEARCH_IN:
            raise MappingError(f"{placed.name}: nothing drawn in the object levels {OBJECT_BAND[0]}-{OBJECT_BAND[1]} "
                               f"within {SEARCH_IN:g} in of ({placed.x_in:g}, {placed.y_in:g}), where reset "
                               f"placed it{_mirrored_hint(pixels, blobs, row, col, s)}")
        rows, cols = blobs[int(np.argmin(gaps))]
        x, y = _world(image, rows, cols)
        off_in = math.hypot(x - placed.x_in, y - placed.y_in)
        if off_in > OBJECT_TOLERANCE_IN:
            raise MappingError(f"{placed.name}: drawn at ({x:.1f}, {y:.1f}), {off_in:.1f} in from "
                               f"({placed.x_in:g}, {placed.y_in:g}) where reset placed it; at most "
                               f"{OBJECT_TOLERANCE_IN:g} in{_mirrored_hint(pixels, blobs, row, col, s)}")
        area_in2 = len(rows) * s * s
        if not placed.area_in2 / OBJECT_AREA_RATIO <= area_in2 <= placed.area_in2 * OBJECT_AREA_RATIO:
            raise MappingError(f"{placed.name}: drawn over {area_in2:.1f} sq in, its footprint is "
                               f"{placed.area_in2:.1f} sq in (within a factor {OBJECT_AREA_RATIO:g} expected)")
        worst = max(worst, off_in)
    return f"{len(objects)} objects drawn where reset placed them, the farthest {worst:.1f} in off"


def _mirrored_hint(pixels: np.ndarray, blobs: list[tuple[np.ndarray, np.ndarray]], row: float, col: float,
                   s: float) -> str:
    """For an object's error message: a hint when a blob lies at its row-mirrored place."""
    mirrored = pixels.shape[0] - 1 - row
    return (" (one is at the row-mirrored place: rows must count down from the high-y edge)"
            if any(s * float(np.min(np.hypot(rows - mirrored, cols - col))) <= OBJECT_TOLERANCE_IN
                   for rows, cols in blobs) else "")


@dataclass(frozen=True)
class SeenObject:
    """An object as a vision saw it: its centre and its footprint's area."""

    x_in: float
    y_in: float
    area_in2: float


@dataclass(frozen=True)
class Sight:
    """What a vision made of one image: the robot's pose (None: no robot seen) and
    the objects."""

    robot: Pose | None
    objects: tuple[SeenObject, ...]


Vision = Callable[[CameraImage], Sight]


def calibrated_reader(path: Path) -> Vision:
    """The executive's own vision (``planner.vision.look``) through the calibration
    file at ``path`` and the empty floor beside it, as ``csl run --camera-calibration``
    reads images; ValueError (one line naming the file and field) for a bad file.

    The planner is imported here, and only here, because a real camera's image means
    only what that vision makes of it: a check with its own reading could pass images
    an episode then misreads."""
    from planner.scene_check import SceneChanged
    from planner.segmentation import load_camera
    from planner.vision import look

    camera = load_camera(path)
    width, height = camera.calibration.image_size

    def read(image: CameraImage) -> Sight:
        rows, cols = image.pixels.shape[:2]
        if (cols, rows) != (width, height):
            raise MappingError(f"the calibration {path} is for {width}x{height} images, the driver's camera gives "
                               f"{cols}x{rows} (a calibration of another camera?)")
        try:
            scene = look(image, camera)
        except SceneChanged as exc:  # a camera moved or a room changed since calibration: a failed check
            raise MappingError(f"the calibrated vision: {exc}") from None
        robot = None if scene.robot is None else Pose(scene.robot.x_in, scene.robot.y_in, scene.robot.heading_deg)
        # look() measures every region from pixels, so each has its area
        return Sight(robot, tuple(SeenObject(r.centroid[0], r.centroid[1], float(r.area_in2 or 0.0))
                                  for r in scene.regions))

    return read


def check_robot_seen(sight: Sight, pose: Pose) -> str:
    """:func:`check_robot_drawn` for what a vision saw: the robot at ``pose`` within
    CENTRE_TOLERANCE_IN, heading within HEADING_TOLERANCE_DEG; MappingError otherwise."""
    if sight.robot is None:
        raise MappingError("the calibrated vision finds no robot (a dark base with a white disc ahead of its "
                           "centre, docs/camera.md)")
    seen = sight.robot
    off_in = math.hypot(seen.x_in - pose.x_in, seen.y_in - pose.y_in)
    if off_in > CENTRE_TOLERANCE_IN:
        raise MappingError(f"the calibrated vision sees the robot at ({seen.x_in:.1f}, {seen.y_in:.1f}), {off_in:.1f} "
                           f"in from the published position ({pose.x_in:.1f}, {pose.y_in:.1f}); at most "
                           f"{CENTRE_TOLERANCE_IN:g} in")
    turn = (seen.heading_deg - pose.heading_deg + 180.0) % 360.0 - 180.0
    if abs(turn) > HEADING_TOLERANCE_DEG:
        raise MappingError(f"the calibrated vision sees the robot heading {seen.heading_deg:.0f} deg, the published "
                           f"heading is {pose.heading_deg:.0f} deg")
    return (f"robot seen through the calibration at ({seen.x_in:.1f}, {seen.y_in:.1f}) heading "
            f"{seen.heading_deg:.0f} deg, {off_in:.1f} in from the published pose")


def check_objects_seen(sight: Sight, objects: Sequence[PlacedObject]) -> str:
    """:func:`check_objects_drawn` for what a vision saw: each placed object matched to
    the seen object nearest its centre, within OBJECT_TOLERANCE_IN and at its size
    within a factor OBJECT_AREA_RATIO; MappingError naming the first that is not."""
    worst = 0.0
    for placed in objects:
        gaps = [math.hypot(seen.x_in - placed.x_in, seen.y_in - placed.y_in) for seen in sight.objects]
        if not gaps or min(gaps) > SEARCH_IN:
            raise MappingError(f"{placed.name}: the calibrated vision sees no object within {SEARCH_IN:g} in of "
                               f"({placed.x_in:g}, {placed.y_in:g}), where reset placed it")
        seen = sight.objects[int(np.argmin(gaps))]
        off_in = min(gaps)
        if off_in > OBJECT_TOLERANCE_IN:
            raise MappingError(f"{placed.name}: seen at ({seen.x_in:.1f}, {seen.y_in:.1f}), {off_in:.1f} in from "
                               f"({placed.x_in:g}, {placed.y_in:g}) where reset placed it; at most "
                               f"{OBJECT_TOLERANCE_IN:g} in")
        if not placed.area_in2 / OBJECT_AREA_RATIO <= seen.area_in2 <= placed.area_in2 * OBJECT_AREA_RATIO:
            raise MappingError(f"{placed.name}: seen over {seen.area_in2:.1f} sq in, its footprint is "
                               f"{placed.area_in2:.1f} sq in (within a factor {OBJECT_AREA_RATIO:g} expected)")
        worst = max(worst, off_in)
    return (f"{len(objects)} objects seen through the calibration where reset placed them, the farthest "
            f"{worst:.1f} in off")
