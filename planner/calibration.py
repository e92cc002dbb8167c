"""Camera calibration: from a raw overhead image to the floor, using a marker board.

A real ceiling camera is not mounted square and its lens bends straight lines, so the
image's nominal scale and origin place things inches off. ArUco markers printed on the
floor at known positions (a *board*, docs/camera.md) give both corrections from one
image: OpenCV's camera model (``cv2.calibrateCamera`` on the marker corners, with the
focal length and principal point held, solving the radial terms k1, k2 — one view of a
plane cannot separate focal length from height, and need not: the homography takes up
the scale) removes the lens distortion, then a homography maps undistorted pixels to
floor inches. Vision works on the *rectified* image: the raw image resampled onto a
floor grid of ``inches_per_pixel`` squares, where the documented pixel-to-floor mapping
(docs/conventions.md) holds exactly, so everything downstream is unchanged.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import cv2
import numpy as np

from camera_model.board import MarkerBoard
from camera_model.floor_grid import FloorGrid
from camera_model.image import CameraImage

MIN_MARKERS = 4  # 16 corners: a homography and two distortion terms with room to spare
RECTIFIED_INCHES_PER_PIXEL = 0.8  # the band image's grid: the planner's costs are tuned to it
CALIBRATION_FORMAT = 1
UNDISTORT_CRITERIA = (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 40, 1e-6)


@dataclass(frozen=True, eq=False)
class Calibration:
    """How one camera's raw images map onto the floor.

    ``camera_matrix`` and ``distortion`` (OpenCV's k1 k2 p1 p2 k3) undistort a raw
    image of ``image_size`` (width, height); ``homography`` takes undistorted pixels
    (col, row) to floor inches; the floor grid (``inches_per_pixel``, origin, size) is
    what :meth:`rectify` resamples onto. ``error_in`` is the RMS distance between the
    board's marker corners and where the calibration puts the detected ones.
    """

    camera_matrix: np.ndarray
    distortion: np.ndarray
    homography: np.ndarray
    image_size: tuple[int, int]
    inches_per_pixel: float
    origin_x_in: float
    origin_y_in: float
    floor_size: tuple[int, int]
    error_in: float
    markers_seen: int

    def to_floor(self, cols: np.ndarray, rows: np.ndarray) -> np.ndarray:
        """Floor (x, y) inches of raw-image pixel coordinates, as an Nx2 array."""
        pts = np.column_stack([np.asarray(cols, float), np.asarray(rows, float)]).reshape(-1, 1, 2)
        flat = _undistort(pts, self.camera_matrix, self.distortion)
        return cv2.perspectiveTransform(flat, self.homography).reshape(-1, 2)

    @cached_property
    def _maps(self) -> tuple[np.ndarray, np.ndarray]:
        """For each floor-grid pixel, where it lies in the raw image."""
        width, height = self.floor_size
        cols, rows = np.meshgrid(np.arange(width, dtype=np.float64), np.arange(height, dtype=np.float64))
        grid = FloorGrid(self.inches_per_pixel, self.origin_x_in, self.origin_y_in)
        world = grid.to_world(rows.ravel(), cols.ravel()).reshape(-1, 1, 2)
        flat = cv2.perspectiveTransform(world, np.linalg.inv(self.homography)).reshape(-1, 2)
        rays = np.column_stack([flat, np.ones(len(flat))]) @ np.linalg.inv(self.camera_matrix).T
        raw, _ = cv2.projectPoints(rays, np.zeros(3), np.zeros(3), self.camera_matrix, self.distortion)
        raw = raw.reshape(height, width, 2)
        return raw[..., 0].astype(np.float32), raw[..., 1].astype(np.float32)

    def rectify(self, pixels: np.ndarray) -> CameraImage:
        """The raw image resampled onto the floor grid (bilinear: a real image has no
        bands to keep apart); what the camera does not see is black."""
        pixels = np.asarray(pixels)
        if pixels.shape[::-1] != self.image_size:
            raise ValueError(f"camera image is {pixels.shape[1]}x{pixels.shape[0]} pixels, the calibration's "
                             f"{self.image_size[0]}x{self.image_size[1]}")
        map_x, map_y = self._maps
        flat = cv2.remap(np.ascontiguousarray(pixels, dtype=np.uint8), map_x, map_y, interpolation=cv2.INTER_LINEAR,
                         borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        return CameraImage(flat, self.inches_per_pixel, self.origin_x_in, self.origin_y_in)


def _detector(board: MarkerBoard) -> cv2.aruco.ArucoDetector:
    """OpenCV's detector for the board's dictionary, corners refined to sub-pixel."""
    params = cv2.aruco.DetectorParameters()
    params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_SUBPIX
    return cv2.aruco.ArucoDetector(cv2.aruco.getPredefinedDictionary(getattr(cv2.aruco, board.dictionary)), params)


def detect_markers(pixels: np.ndarray, board: MarkerBoard) -> dict[int, np.ndarray]:
    """The board's markers found in a raw image: id -> 4x2 (col, row) corners."""
    corners, ids, _ = _detector(board).detectMarkers(np.ascontiguousarray(pixels, dtype=np.uint8))
    known = {m.marker_id for m in board.markers}
    if ids is None:
        return {}
    return {int(i): c.reshape(4, 2).astype(np.float64) for c, i in zip(corners, ids.ravel()) if int(i) in known}


def calibrate(pixels: np.ndarray, board: MarkerBoard,
              inches_per_pixel: float = RECTIFIED_INCHES_PER_PIXEL) -> Calibration:
    """Lens and floor mapping from one raw image showing at least MIN_MARKERS markers."""
    pixels = np.asarray(pixels)
    found = detect_markers(pixels, board)
    if len(found) < MIN_MARKERS:
        raise ValueError(f"calibration: the image shows {len(found)} of the board's markers, at least "
                         f"{MIN_MARKERS} are needed (is the board on the floor and in view?)")
    image_pts = np.concatenate([found[i] for i in sorted(found)])
    floor_pts = np.array([corner for i in sorted(found) for corner in board.corners(i)], dtype=np.float64)
    height, width = pixels.shape[:2]
    guess = np.array([[float(width), 0, (width - 1) / 2], [0, float(width), (height - 1) / 2], [0, 0, 1]])
    flags = (cv2.CALIB_USE_INTRINSIC_GUESS | cv2.CALIB_FIX_FOCAL_LENGTH | cv2.CALIB_FIX_PRINCIPAL_POINT
             | cv2.CALIB_ZERO_TANGENT_DIST | cv2.CALIB_FIX_K3 | cv2.CALIB_FIX_ASPECT_RATIO)
    object_pts = np.column_stack([floor_pts, np.zeros(len(floor_pts))]).astype(np.float32)
    _, matrix, distortion, _, _ = cv2.calibrateCamera(
        [object_pts], [image_pts.astype(np.float32)], (width, height), guess, np.zeros(5), flags=flags)
    flat = _undistort(image_pts, matrix, distortion)
    homography, _ = cv2.findHomography(flat, floor_pts, 0)
    if homography is None:
        raise ValueError("calibration: the marker corners give no homography (markers all in a line?)")
    mapped = cv2.perspectiveTransform(flat, homography).reshape(-1, 2)
    error = float(np.sqrt(np.mean(np.sum((mapped - floor_pts) ** 2, axis=1))))
    ox, oy, size = _floor_grid(matrix, distortion, homography, width, height, inches_per_pixel)
    return Calibration(matrix, distortion.ravel(), homography, (width, height), inches_per_pixel, ox, oy, size,
                       error, len(found))


def _floor_grid(matrix: np.ndarray, distortion: np.ndarray, homography: np.ndarray, width: int, height: int,
                ipp: float) -> tuple[float, float, tuple[int, int]]:
    """The floor rectangle the raw image's border encloses, on whole inches."""
    steps = np.linspace(0, 1, 33)
    border = np.concatenate([np.column_stack([steps * (width - 1), np.zeros_like(steps)]),
                             np.column_stack([steps * (width - 1), np.full_like(steps, height - 1)]),
                             np.column_stack([np.zeros_like(steps), steps * (height - 1)]),
                             np.column_stack([np.full_like(steps, width - 1), steps * (height - 1)])])
    flat = _undistort(border, matrix, distortion)
    world = cv2.perspectiveTransform(flat, homography).reshape(-1, 2)
    x0, y1 = math.floor(world[:, 0].min()), math.ceil(world[:, 1].max())
    cols = math.ceil((world[:, 0].max() - x0) / ipp)
    rows = math.ceil((y1 - world[:, 1].min()) / ipp)
    return float(x0), float(y1), (cols, rows)


def save_calibration(calibration: Calibration, path: Path) -> None:
    """Write the calibration as JSON (docs/camera.md, "The calibration file")."""
    c = calibration
    data = {
        "format": CALIBRATION_FORMAT,
        "image_size": list(c.image_size),
        "camera_matrix": np.asarray(c.camera_matrix).tolist(),
        "distortion": np.asarray(c.distortion).ravel().tolist(),
        "homography": np.asarray(c.homography).tolist(),
        "floor": {"inches_per_pixel": c.inches_per_pixel, "origin_x_in": c.origin_x_in,
                  "origin_y_in": c.origin_y_in, "size": list(c.floor_size)},
        "error_in": c.error_in,
        "markers_seen": c.markers_seen,
    }
    Path(path).write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")


def load_calibration(path: Path) -> Calibration:
    """Read a calibration file; a bad one raises ValueError naming the file and field."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the calibration: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != CALIBRATION_FORMAT:
        raise ValueError(f"{path}: format: expected a calibration file of format {CALIBRATION_FORMAT}")
    floor = data.get("floor")
    if not isinstance(floor, dict):
        raise ValueError(f"{path}: floor: expected an object")
    ipp = _number(path, "floor.inches_per_pixel", floor.get("inches_per_pixel"))
    if ipp <= 0:
        raise ValueError(f"{path}: floor.inches_per_pixel: must be positive")
    matrix = _matrix(path, "camera_matrix", data.get("camera_matrix"), (3, 3))
    homography = _matrix(path, "homography", data.get("homography"), (3, 3))
    if abs(np.linalg.det(homography)) < 1e-12 or abs(np.linalg.det(matrix)) < 1e-12:
        raise ValueError(f"{path}: camera_matrix/homography: singular matrix")
    return Calibration(
        camera_matrix=matrix,
        distortion=_matrix(path, "distortion", data.get("distortion"), (5,)),
        homography=homography,
        image_size=_size(path, "image_size", data.get("image_size")),
        inches_per_pixel=ipp,
        origin_x_in=_number(path, "floor.origin_x_in", floor.get("origin_x_in")),
        origin_y_in=_number(path, "floor.origin_y_in", floor.get("origin_y_in")),
        floor_size=_size(path, "floor.size", floor.get("size")),
        error_in=_number(path, "error_in", data.get("error_in")),
        markers_seen=int(_number(path, "markers_seen", data.get("markers_seen"))),
    )


def _undistort(points: np.ndarray, matrix: np.ndarray, distortion: np.ndarray) -> np.ndarray:
    """Undistorted pixel coordinates (Nx1x2) of raw ones, iterated to 1e-6."""
    return cv2.undistortPoints(points.reshape(-1, 1, 2).astype(np.float64), matrix, distortion, None, None, matrix,
                               UNDISTORT_CRITERIA)


def _number(path: Path, name: str, value: object) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise ValueError(f"{path}: {name}: expected a finite number, got {value!r}")
    return float(value)


def _matrix(path: Path, name: str, value: object, shape: tuple[int, ...]) -> np.ndarray:
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        array = np.zeros(0)
    if array.shape != shape or not np.all(np.isfinite(array)):
        raise ValueError(f"{path}: {name}: expected {'x'.join(map(str, shape))} finite numbers")
    return array


def _size(path: Path, name: str, value: object) -> tuple[int, int]:
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) and 0 < v <= 20000 for v in value)):
        raise ValueError(f"{path}: {name}: expected [width, height] in whole pixels")
    return int(value[0]), int(value[1])
