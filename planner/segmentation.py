"""Segmenting a real camera's rectified image by comparing it with the empty floor.

A real image has no grey bands: the floor is textured and unevenly lit, objects are
shaded, things cast shadows. What stays true is that the floor at a given spot looks
the same every time, so each pixel is divided by the *empty floor* at that spot
(background subtraction as a ratio): texture and the lighting gradient cancel, an
object on the floor stands out as brighter, a shadow only darkens, the robot (painted
dark, a white disc ahead of its centre, docs/camera.md) as much darker with a bright
hole. Thresholds on the ratio (constants below) therefore hold across the whole room.

The empty floor is taken from one image, at calibration or the first one seen: what
is bright on it (objects) and the robot are painted out (``cv2.inpaint``), so any
image may serve. Static obstacles (walls, furniture, whatever the camera does not
see) are what is dark on it relative to a smooth fit of the floor's lighting.

Light that changed since calibration is divided out too, where it can be told from
objects: a global exposure change (the median ratio), and a lamp's pool of light or a
large shadow, which change the ratio over a wide area where objects are small (the
ratio's running median over BACKGROUND_WINDOW_PX, :func:`_light_change`). What cannot
be divided out (a new floor texture) is caught by :mod:`planner.scene_check`: a look
unlike its empty floor past a stated bound raises ``SceneChanged`` rather than report
phantoms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from camera_model.image import CameraImage
from planner import scene_check
from planner.calibration import Calibration, MarkerBoard, calibrate, load_calibration, save_calibration
from planner.scene_check import SceneMeasure

OBJECT_RATIO = 1.2  # brighter than the floor by this much: an object (5 noise sigmas)
ROBOT_RATIO = 0.5  # darker than this: the robot's paint (a shadow darkens to ~0.65 at most)
MARKER_RATIO = 1.5  # the robot's white disc, inside its dark body
OBSTACLE_RATIO = 0.6  # on the empty floor, darker than the lit floor by this much: wall, furniture
PRINT_RATIO = 1.5  # the white paper the board's markers are printed on
MIN_ROBOT_PIXELS = 40
ROBOT_SOLIDITY = 0.75  # a disc less its white disc (1/16 of it) and blurred edges
ROBOT_ROUNDNESS = 0.9  # 4 pi area / perimeter^2 of its hull: the robot 0.97-0.99, a cart's box 0.76-0.79
# The white disc's share of the body and its centre's distance from the body's, in
# radii: 1/16 and 2/3 drawn, 0.049-0.054 and 0.64-0.67 seen through blur and the
# threshold (lab, realistic camera); a person over a can showed 0.018 and 0.87.
MARKER_SHARE = (0.025, 0.17)
MARKER_OFFSET = (0.4, 0.85)
MIN_PRINT_PIXELS = 30
INPAINT_MARGIN_PX = 5  # paint out a rim too: blur and shadows reach ~4 in past an edge
MIN_BRIGHT_PIXELS = 3  # fewer is a speck of noise or texture (the 2 in box shows ~6)
PRINT_INK_SHARE = 0.1  # a printed marker is at least this much ink; a light object has none
# The empty floor is smoothed to about halve its own sensor noise, edge-preserving
# (bilateral): a plain blur would darken a strip of floor between dark walls and
# furniture, which then reads as brighter than the floor, an object.
REFERENCE_SMOOTH_PX = 1.0
REFERENCE_SMOOTH_LEVELS = 10.0  # about three noise sigmas: edges are kept
LIGHT_FIT_ROUNDS = 3
# The light that changed since calibration (a lamp's pool, a large shadow) is the
# ratio's running median over this window (25 in square): the largest test object
# (the 10 in box) covers a sixth of it, far from the half that would pull a median, and
# it is narrow enough to follow a lamp's pool; a median keeps a shadow's edge sharp
# where a mean would smear it into a bright rim (phantoms) outside and a dark one inside.
BACKGROUND_WINDOW_PX = 31
# The change of light divided out is held to this range: darker than a shadow or
# brighter than a lamp is not light but something on the floor (a cart parked).
BACKGROUND_RANGE = (0.5, 2.5)
BACKGROUND_STEP = 0.01  # the median is taken on the ratio in steps of this (8-bit)
# Where the light changes fast (a shadow's soft edge, above all where it meets a wall)
# the median lags the ratio by several noise sigmas; the brightest light within this
# many pixels is taken instead, so the lit side of an edge never reads as an object.
BACKGROUND_REACH_PX = 2

_CROSS = cv2.getStructuringElement(cv2.MORPH_RECT, (3, 3))


@dataclass(frozen=True, eq=False)
class EmptyFloor:
    """The floor with nothing on it, on the rectified grid: ``level`` (float32 grey
    levels), ``obstacles`` (walls, furniture and unseen parts) and ``printed`` (the
    board's markers, where no object can be told from the print), bool masks."""

    level: np.ndarray
    obstacles: np.ndarray
    printed: np.ndarray


@dataclass(frozen=True, eq=False)
class Camera:
    """A calibrated camera and its empty floor: what vision needs for real images."""

    calibration: Calibration
    empty_floor: EmptyFloor


def calibrated_camera(pixels: np.ndarray, board: MarkerBoard) -> Camera:
    """A camera calibrated on one raw image of the board, its empty floor from the same
    image (what ``csl camera calibrate`` saves, or what an episode can make from its
    first image when no calibration file is given)."""
    calibration = calibrate(pixels, board)
    return Camera(calibration, empty_floor(calibration.rectify(pixels)))


def empty_floor_path(calibration_path: Path) -> Path:
    """Where the empty floor image of a calibration file is kept: beside it."""
    return Path(calibration_path).with_suffix(".floor.png")


def save_camera(calibration: Calibration, empty_floor_image: CameraImage, path: Path) -> None:
    """Write the calibration file and, beside it, the rectified image the empty floor is
    made from (a PNG, so the floor can be looked at and the file read anywhere)."""
    path = Path(path)
    save_calibration(calibration, path)
    floor_path = empty_floor_path(path)
    if not cv2.imwrite(str(floor_path), np.ascontiguousarray(empty_floor_image.pixels, dtype=np.uint8)):
        raise ValueError(f"{floor_path}: cannot write the empty floor image")


def load_camera(path: Path) -> Camera:
    """A calibration file and its empty floor image; one-line errors for bad ones."""
    calibration = load_calibration(path)
    floor_path = empty_floor_path(path)
    pixels = cv2.imread(str(floor_path), cv2.IMREAD_GRAYSCALE) if floor_path.exists() else None
    if pixels is None:
        raise ValueError(f"{floor_path}: missing or not an image (write it with csl camera calibrate)")
    if pixels.shape[::-1] != calibration.floor_size:
        raise ValueError(f"{floor_path}: is {pixels.shape[1]}x{pixels.shape[0]}, the calibration's floor grid "
                         f"{calibration.floor_size[0]}x{calibration.floor_size[1]}")
    image = CameraImage(pixels, calibration.inches_per_pixel, calibration.origin_x_in, calibration.origin_y_in)
    return Camera(calibration, empty_floor(image))


@dataclass(frozen=True, eq=False)
class Masks:
    """One image cut into what vision tells apart (bool masks on the rectified grid)."""

    robot_body: np.ndarray  # filled disc, marker included
    robot_marker: np.ndarray
    obstacles: np.ndarray
    objects: np.ndarray
    brightness: np.ndarray  # float: the image over the empty floor (1 = bare floor)
    scene: SceneMeasure  # how far the look is from its empty floor (planner.scene_check)


def empty_floor(image: CameraImage) -> EmptyFloor:
    """The empty floor from one rectified image, objects and robot painted out."""
    level = np.asarray(image.pixels, dtype=np.float32)
    light = _floor_light(level)
    ratio = (level + 1.0) / (light + 1.0)
    printed = _printed_marks(ratio)
    dark = ratio < OBSTACLE_RATIO
    body, _ = _robot(ratio, ratio)
    bright = _without_specks((ratio > OBJECT_RATIO) & ~printed)
    painted_out = cv2.dilate(((body > 0) | bright).astype(np.uint8), _CROSS, iterations=INPAINT_MARGIN_PX)
    # Filled from the floor around, never from a wall: a wall's dark pixels drawn into
    # the floor there would make the bare floor read as an object on every image.
    source = np.where(dark & ~printed, light, level)
    filled = cv2.inpaint(np.clip(source, 0, 255).astype(np.uint8), painted_out, 3, cv2.INPAINT_TELEA)
    filled = np.where(painted_out > 0, filled, level)
    obstacles = dark & ~printed & (painted_out == 0)
    obstacles = cv2.morphologyEx(obstacles.astype(np.uint8), cv2.MORPH_OPEN, _CROSS) > 0
    return EmptyFloor(level=_smooth(filled), obstacles=obstacles, printed=printed)


def segment(image: CameraImage, floor: EmptyFloor, check: bool = True) -> Masks:
    """Robot, obstacles and objects of one rectified image against the empty floor;
    with ``check``, a look past the bounds of :mod:`planner.scene_check` raises
    ``SceneChanged`` (one line: what differs, and to recalibrate)."""
    level = np.asarray(image.pixels, dtype=np.float32)
    if level.shape != floor.level.shape:
        raise ValueError(f"image is {level.shape[1]}x{level.shape[0]} on the floor grid, its empty floor "
                         f"{floor.level.shape[1]}x{floor.level.shape[0]}")
    ratio = (level + 1.0) / (floor.level + 1.0)
    seen = ~floor.obstacles
    exposure = float(np.median(ratio[seen])) if seen.any() else 1.0
    ratio /= max(exposure, 1e-3)  # a camera's auto exposure scales every pixel alike
    light = _light_change(ratio)
    # Bright things against the light where they stand (the brightest light within
    # BACKGROUND_REACH_PX); dark things only against more light (a lamp), never less: a
    # cart parked in a wide patch is no shadow to divide out.
    bright, dark = ratio / _reach(light), ratio / np.maximum(light, 1.0)
    body, marker = _robot(dark, bright)
    robot_zone = cv2.dilate(body, _CROSS, iterations=2) > 0
    objects = (bright > OBJECT_RATIO) & ~robot_zone & seen & ~floor.printed
    new_dark = cv2.morphologyEx(((dark < ROBOT_RATIO) & ~robot_zone).astype(np.uint8), cv2.MORPH_OPEN, _CROSS)
    scene = scene_check.measure(ratio / light, seen & ~floor.printed & ~robot_zone, objects, image.inches_per_pixel)
    if check:
        scene_check.check(scene)
    return Masks(robot_body=body > 0, robot_marker=marker > 0, obstacles=floor.obstacles | (new_dark > 0),
                 objects=objects, brightness=bright, scene=scene)


def _light_change(ratio: np.ndarray) -> np.ndarray:
    """How much the light changed since calibration at each pixel: the ratio's running
    median over BACKGROUND_WINDOW_PX, held to BACKGROUND_RANGE.

    The robot and what is dark (people, carts) are left out of each window's median by
    standing in for them alternately the lowest and the highest value: as many below as
    above, they move no median, so floor beside a parked cart stays floor."""
    code = np.clip(np.round(ratio / BACKGROUND_STEP), 1, 254).astype(np.uint8)
    rows, cols = np.indices(ratio.shape)
    code = np.where(ratio < ROBOT_RATIO, np.where((rows + cols) % 2 == 0, 0, 255), code).astype(np.uint8)
    median = cv2.medianBlur(code, BACKGROUND_WINDOW_PX).astype(np.float32) * BACKGROUND_STEP
    return np.clip(median, *BACKGROUND_RANGE)


def _reach(light: np.ndarray) -> np.ndarray:
    """The brightest ``light`` within BACKGROUND_REACH_PX of each pixel."""
    return cv2.dilate(light, cv2.getStructuringElement(cv2.MORPH_RECT, (2 * BACKGROUND_REACH_PX + 1,) * 2))


def _without_specks(mask: np.ndarray) -> np.ndarray:
    """``mask`` less its regions of fewer than MIN_BRIGHT_PIXELS pixels."""
    count, labels, stats, _ = cv2.connectedComponentsWithStats(mask.astype(np.uint8), connectivity=8)
    keep = stats[:, cv2.CC_STAT_AREA] >= MIN_BRIGHT_PIXELS
    keep[0] = False
    return keep[labels]


def _smooth(pixels: np.ndarray) -> np.ndarray:
    return cv2.bilateralFilter(np.asarray(pixels, dtype=np.float32), 5, REFERENCE_SMOOTH_LEVELS, REFERENCE_SMOOTH_PX)


def _floor_light(level: np.ndarray) -> np.ndarray:
    """The lighting of the bare floor: a quadratic surface in (x, y) fitted to the
    pixels that look like floor (within 25 % of the fit), refitted a few times so
    walls, furniture, objects and paper drop out."""
    rows, cols = np.indices(level.shape, dtype=np.float64)
    u, v = cols / level.shape[1] - 0.5, rows / level.shape[0] - 0.5
    basis = np.stack([np.ones_like(u), u, v, u * u, u * v, v * v], axis=-1).reshape(-1, 6)
    values = level.reshape(-1).astype(np.float64)
    use = values > np.percentile(values, 20)  # walls and the unseen border first out
    fit = np.full(values.shape, np.median(values[use]))
    for _ in range(LIGHT_FIT_ROUNDS):
        pick = np.flatnonzero(use)[:: max(1, int(use.sum()) // 20000)]
        coef, *_ = np.linalg.lstsq(basis[pick], values[pick], rcond=None)
        fit = basis @ coef
        use = np.abs(values / np.maximum(fit, 1.0) - 1.0) < 0.25
    return fit.reshape(level.shape).astype(np.float32)


def _printed_marks(ratio: np.ndarray) -> np.ndarray:
    """The board's markers: each white paper square with its ink (the convex hull of
    a large very bright region with ink inside)."""
    paper = (ratio > PRINT_RATIO).astype(np.uint8)
    ink = ratio < OBSTACLE_RATIO
    contours, _ = cv2.findContours(paper, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    marks = np.zeros(ratio.shape, np.uint8)
    for contour in contours:
        if cv2.contourArea(contour) < MIN_PRINT_PIXELS:
            continue
        hull = np.zeros(ratio.shape, np.uint8)
        cv2.fillPoly(hull, [cv2.convexHull(contour)], 1)
        if np.count_nonzero(ink & (hull > 0)) >= PRINT_INK_SHARE * np.count_nonzero(hull):
            marks |= hull
    return cv2.dilate(marks, _CROSS) > 0


def _robot(ratio: np.ndarray, bright_ratio: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The robot's body and its white disc (0/255 masks; empty when absent): dark in
    ``ratio``, the disc bright in ``bright_ratio`` (the same but for a change of light).

    A candidate is a dark region that is a solid disc (the dark share of its convex
    hull at least ROBOT_SOLIDITY, the hull taking in the white disc wherever blur opens
    it to the edge, and the hull round: ROBOT_ROUNDNESS) with a bright region inside.
    A person or a cart standing over a light object is one too, so the robot is the
    candidate whose bright region is most like its white disc (docs/camera.md): a
    sixteenth of the body, its centre 2/3 of the radius ahead of the body's; one too
    unlike it (MARKER_SHARE, MARKER_OFFSET) is no robot at all."""
    dark = cv2.morphologyEx((ratio < ROBOT_RATIO).astype(np.uint8), cv2.MORPH_CLOSE, _CROSS)
    # Outer boundaries of every dark region, those inside the walls' ring included.
    contours, hierarchy = cv2.findContours(dark, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_SIMPLE)
    bright = bright_ratio > MARKER_RATIO
    best = (math.inf, np.zeros(ratio.shape, np.uint8), np.zeros(ratio.shape, np.uint8))
    for contour, links in zip(contours, hierarchy[0] if hierarchy is not None else []):
        if links[3] != -1 or cv2.contourArea(contour) < MIN_ROBOT_PIXELS:
            continue
        hull = cv2.convexHull(contour)
        if 4.0 * math.pi * cv2.contourArea(hull) < ROBOT_ROUNDNESS * cv2.arcLength(hull, True) ** 2:
            continue  # a cart's box
        body = np.zeros(ratio.shape, np.uint8)
        cv2.fillPoly(body, [hull], 255)
        inside = body > 0
        area = int(np.count_nonzero(inside))
        marker = inside & bright
        if np.count_nonzero(dark[inside]) < ROBOT_SOLIDITY * area or np.count_nonzero(marker) < 2:
            continue
        unlike = _unlike_the_marker(inside, marker)
        if unlike < best[0]:
            best = (unlike, body, marker.astype(np.uint8) * 255)
    return best[1], best[2]


def _unlike_the_marker(body: np.ndarray, marker: np.ndarray) -> float:
    """How far a bright region inside a dark disc is from the robot's white disc
    (0 = just like it, ``inf`` = outside MARKER_SHARE or MARKER_OFFSET): the log of
    its share of the body over a sixteenth, plus its centre's distance from the body's
    in radii off 2/3."""
    area = np.count_nonzero(body)
    share = np.count_nonzero(marker) / area
    rows, cols = np.nonzero(body)
    marker_rows, marker_cols = np.nonzero(marker)
    offset = math.hypot(marker_rows.mean() - rows.mean(), marker_cols.mean() - cols.mean()) / math.sqrt(area / math.pi)
    if not (MARKER_SHARE[0] <= share <= MARKER_SHARE[1] and MARKER_OFFSET[0] <= offset <= MARKER_OFFSET[1]):
        return math.inf
    return abs(math.log(share * 16.0)) + abs(offset - 2.0 / 3.0)
