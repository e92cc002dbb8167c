"""The realistic camera preset: an overhead image like a real ceiling camera's.

Nothing here is a grey band the vision could rely on. The floor is a textured tile
(fixed per world, as a real floor is the same every day), lit unevenly (a gradient
across the room and vignetting), objects are light and shaded darker towards their
edges, people and carts crossing the floor are dark, all of them and the robot cast
soft shadows, the camera is slightly rotated and tilted, its lens has barrel
distortion and the sensor adds noise. The robot is
painted dark with a white disc ahead of its centre. The lab's marker board
(:mod:`hero_driver.sim.render_board`) is printed on the floor.

The image says only what a real camera could: its nominal scale and origin (what
the mapping would be with a perfect lens mounted square), no lens model. The
executive recovers the true mapping from the markers (``csl camera calibrate``).

A *scene change* (:data:`SCENE_CHANGES`) draws the same room after something changed
in it the way real rooms change between a calibration and a run: a lamp switched on,
a large shadow thrown across the floor, the floor re-laid with another texture, the
camera's exposure turned down. Calibrating on the plain room and then reading the
changed one is how the vision's scene-change check and its robustness are tried
(docs/camera.md, "When the room changes").
"""

from __future__ import annotations

import math
import zlib
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from camera_model.floor_grid import FloorGrid
from camera_model.image import CameraImage
from hero_driver.interface import Pose
from hero_driver.sim.catalogue import Footprint
from hero_driver.sim.physics import WALL_IN
from hero_driver.sim.render_board import board_for, print_board
from hero_driver.sim.worldfile import WorldSpec, footprint_polygon, rect_polygon

INCHES_PER_PIXEL = 0.5  # nominal: a real camera has more pixels than the band image
SUPERSAMPLE = 4

# Albedo (share of light reflected) of each material.
WALL_ALBEDO = 0.16
FURNITURE_ALBEDO = 0.22
FLOOR_ALBEDO = 0.42
FLOOR_TEXTURE = 0.07  # relative amplitude of the floor's mottling
GROUT_ALBEDO = 0.85  # tile joints, relative to the tile
TILE_IN = 12.0
OBJECT_ALBEDO = 0.80
EDGE_SHADING = 0.25  # an object's edge is this much darker than its top's middle
ROBOT_ALBEDO = 0.12
ROBOT_MARKER_ALBEDO = 0.92
# People and carts: dark clothes and a dark cart, below half the floor's albedo (what
# segmentation takes for a new obstacle, never an object), with no white disc (never the robot).
MOVER_ALBEDO = 0.14
PAPER_ALBEDO, INK_ALBEDO = 0.85, 0.06

# Light: brightest at high x, low y; vignetting darkens the corners.
LIGHT_MIN, LIGHT_SPAN = 0.6, 0.35
VIGNETTE = 0.18
SHADOW_OFFSET_IN = (1.2, -1.2)
SHADOW_DEPTH = 0.35
SHADOW_BLUR_IN = 1.0
GAIN = 1.1

# Mounting and lens: a slight rotation and tilt, barrel distortion, an off-centre axis.
MOUNT_ROTATION_DEG = 1.2
MOUNT_SCALE = 0.97
MOUNT_TILT = (1.5e-5, -1.0e-5)  # perspective terms per pixel
LENS_FOCAL_FRACTION = 0.9
LENS_DISTORTION = (-0.10, 0.02, 0.0, 0.0, 0.0)  # OpenCV k1 k2 p1 p2 k3
LENS_CENTRE_OFFSET_PX = (2.5, -1.5)
OPTICS_BLUR_PX = 0.5
READ_NOISE, SHOT_NOISE = 2.0, 0.04  # sigma^2 = READ^2 + SHOT * level

# Scene changes after calibration (docs/camera.md, "When the room changes").
SCENE_CHANGES = ("lamp", "shadow", "floor", "exposure")
# A floor lamp switched on: a pool of light, brightest at LAMP_AT_IN (in the lab,
# between the upright soda bottle and the magazine box), falling off as a Gaussian of
# LAMP_SPREAD_IN; the light there is (1 + LAMP_GAIN) times what it was.
LAMP_AT_IN, LAMP_SPREAD_IN, LAMP_GAIN = (0.5, 0.4), 40.0, 0.8  # room fractions, in, share
# Something outside the camera's view (a partition, a person by the window) throws a
# large soft-edged shadow over a quarter of the room (the tumbler and the 10 in box of
# the lab stand in it): the light there falls to SHADOW_LIGHT.
SHADOW_AREA = (0.6, 0.0, 1.0, 0.62)  # room fractions x0, y0, x1, y1
SHADOW_LIGHT = 0.6
SHADOW_EDGE_IN = 2.0
# The floor re-laid: tiles of another size with another mottle, of the same kind as
# the old (as textured, so a calibration on the new floor reads it as well).
NEW_TILE_IN, NEW_FLOOR_SEED = 16.0, 7
# The camera's exposure (or the room's overall light) turned down.
EXPOSURE = 0.7


@dataclass(frozen=True)
class Geometry:
    """The image size, its nominal origin and the floor-to-ideal-pixel homography."""

    width_px: int
    height_px: int
    origin_x_in: float
    origin_y_in: float
    world_to_pixel: np.ndarray  # 3x3, floor inches -> (col, row), pixel centres at integers

    @classmethod
    def for_room(cls, spec: WorldSpec) -> Geometry:
        ox, oy = -WALL_IN, spec.room_depth_in + WALL_IN
        w = math.ceil((spec.room_width_in + 2 * WALL_IN) / INCHES_PER_PIXEL)
        h = math.ceil((spec.room_depth_in + 2 * WALL_IN) / INCHES_PER_PIXEL)
        nominal = FloorGrid(INCHES_PER_PIXEL, ox, oy).world_to_pixel()
        cx, cy = (w - 1) / 2, (h - 1) / 2
        a = math.radians(MOUNT_ROTATION_DEG)
        about_centre = np.array([[1, 0, cx], [0, 1, cy], [0, 0, 1]]) @ np.array(
            [[MOUNT_SCALE * math.cos(a), -MOUNT_SCALE * math.sin(a), 0],
             [MOUNT_SCALE * math.sin(a), MOUNT_SCALE * math.cos(a), 0],
             [MOUNT_TILT[0], MOUNT_TILT[1], 1]]) @ np.array([[1, 0, -cx], [0, 1, -cy], [0, 0, 1]])
        return cls(w, h, ox, oy, about_centre @ nominal)

    def project(self, points: Sequence[tuple[float, float]]) -> np.ndarray:
        pts = np.asarray(points, dtype=np.float64).reshape(-1, 1, 2)
        return cv2.perspectiveTransform(pts, self.world_to_pixel).reshape(-1, 2)

    def world_grid(self) -> tuple[np.ndarray, np.ndarray]:
        """Floor (x, y) inches under every ideal pixel centre."""
        cols, rows = np.meshgrid(np.arange(self.width_px, dtype=np.float64),
                                 np.arange(self.height_px, dtype=np.float64))
        pts = np.stack([cols, rows], axis=-1).reshape(-1, 1, 2)
        world = cv2.perspectiveTransform(pts, np.linalg.inv(self.world_to_pixel)).reshape(self.height_px,
                                                                                          self.width_px, 2)
        return world[..., 0], world[..., 1]


def lens_model(width_px: int, height_px: int) -> tuple[np.ndarray, np.ndarray]:
    """The simulated lens (camera matrix, OpenCV distortion coefficients): what
    calibration has to recover; tests compare against it."""
    f = LENS_FOCAL_FRACTION * width_px
    k = np.array([[f, 0.0, (width_px - 1) / 2 + LENS_CENTRE_OFFSET_PX[0]],
                  [0.0, f, (height_px - 1) / 2 + LENS_CENTRE_OFFSET_PX[1]], [0.0, 0.0, 1.0]])
    return k, np.asarray(LENS_DISTORTION, dtype=np.float64)


def render(spec: WorldSpec, objects: Sequence[tuple[Footprint, float, float, float]], robot: Pose,
           base_radius_in: float, rng: np.random.Generator, clock_s: float,
           movers: Sequence[Sequence[tuple[float, float]]] = (), change: str | None = None) -> CameraImage:
    """Draw the room as a real overhead camera would see it (module docstring);
    ``movers`` are the outlines of the people and carts on the floor, drawn dark
    (MOVER_ALBEDO) beneath the objects; ``change`` one of SCENE_CHANGES, or None for
    the room as calibrated."""
    if change is not None and change not in SCENE_CHANGES:
        raise ValueError(f"scene change {change!r}: expected one of {', '.join(SCENE_CHANGES)}")
    geo = Geometry.for_room(spec)
    albedo = _floor_albedo(spec, geo, relaid=change == "floor")
    board = board_for(spec)
    if board is not None:
        print_board(board, albedo, geo.world_to_pixel, PAPER_ALBEDO, INK_ALBEDO)
    furniture = _coverage(geo, [rect_polygon(f.x_in, f.y_in, f.width_in, f.depth_in, f.yaw_deg)
                                for f in spec.furniture] + spec.wall_outlines())
    albedo = furniture * FURNITURE_ALBEDO + (1 - furniture) * albedo

    object_polys = [footprint_polygon(fp, x, y, yaw, segments=64) for fp, x, y, yaw in objects]
    robot_poly = _disc(robot.x_in, robot.y_in, base_radius_in)
    albedo *= 1.0 - SHADOW_DEPTH * _shadow(geo, [*movers, *object_polys, robot_poly])

    walking = _coverage(geo, list(movers))
    albedo = walking * MOVER_ALBEDO + (1 - walking) * albedo

    things = _coverage(geo, object_polys)
    albedo = things * OBJECT_ALBEDO * _shading(things) + (1 - things) * albedo
    body = _coverage(geo, [robot_poly])
    albedo = body * ROBOT_ALBEDO + (1 - body) * albedo
    h = math.radians(robot.heading_deg)
    ahead = 2.0 * base_radius_in / 3.0
    marker = _coverage(geo, [_disc(robot.x_in + ahead * math.cos(h), robot.y_in + ahead * math.sin(h),
                                   base_radius_in / 4.0)])
    albedo = marker * ROBOT_MARKER_ALBEDO + (1 - marker) * albedo

    level = 255.0 * GAIN * albedo * _light(spec, geo, change)
    level = cv2.GaussianBlur(level.astype(np.float32), (0, 0), OPTICS_BLUR_PX)
    map_x, map_y = _distortion_maps(geo.width_px, geo.height_px)
    level = cv2.remap(level, map_x, map_y, interpolation=cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                      borderValue=0.0)
    sigma = np.sqrt(READ_NOISE ** 2 + SHOT_NOISE * np.maximum(level, 0.0))
    level = level + rng.standard_normal(level.shape) * sigma
    pixels = np.clip(np.round(level), 0, 255).astype(np.uint8)
    return CameraImage(pixels=pixels, inches_per_pixel=INCHES_PER_PIXEL, origin_x_in=geo.origin_x_in,
                       origin_y_in=geo.origin_y_in, clock_s=clock_s,
                       meta={"world": spec.name, "camera": "realistic" if change is None else f"realistic-{change}"})


def _disc(x: float, y: float, r: float) -> list[tuple[float, float]]:
    return [(x + r * math.cos(2 * math.pi * k / 64), y + r * math.sin(2 * math.pi * k / 64)) for k in range(64)]


def _coverage(geo: Geometry, polygons: Sequence[Sequence[tuple[float, float]]]) -> np.ndarray:
    """The share of each pixel the polygons cover (0..1)."""
    shape = (geo.height_px, geo.width_px)
    if not polygons:
        return np.zeros(shape, np.float32)
    fine = np.zeros((shape[0] * SUPERSAMPLE, shape[1] * SUPERSAMPLE), np.uint8)
    shift = 4
    for polygon in polygons:
        px = (geo.project(polygon) + 0.5) * SUPERSAMPLE - 0.5
        cv2.fillPoly(fine, [np.round(px * (1 << shift)).astype(np.int32)], 255, lineType=cv2.LINE_8, shift=shift)
    return cv2.resize(fine, (shape[1], shape[0]), interpolation=cv2.INTER_AREA).astype(np.float32) / 255.0


def _floor_albedo(spec: WorldSpec, geo: Geometry, relaid: bool = False) -> np.ndarray:
    """Walls everywhere, the room's floor tiled and mottled, the same for a given world
    (``relaid``: the other floor of the ``floor`` scene change)."""
    x, y = geo.world_grid()
    rng = np.random.default_rng(zlib.crc32(spec.name.encode()) + (NEW_FLOOR_SEED if relaid else 0))
    tile_in = NEW_TILE_IN if relaid else TILE_IN
    coarse = rng.standard_normal((geo.height_px // 6 + 2, geo.width_px // 6 + 2)).astype(np.float32)
    mottle = cv2.resize(coarse, (geo.width_px, geo.height_px), interpolation=cv2.INTER_CUBIC)
    grain = cv2.GaussianBlur(rng.standard_normal((geo.height_px, geo.width_px)).astype(np.float32), (0, 0), 0.8)
    tile = FLOOR_ALBEDO * (1 + FLOOR_TEXTURE * np.clip(0.7 * mottle + 0.5 * grain, -2.5, 2.5))
    joint = (np.mod(x, tile_in) < 0.4) | (np.mod(y, tile_in) < 0.4)
    tile = np.where(joint, tile * GROUT_ALBEDO, tile)
    floor = _coverage(geo, [rect_polygon(spec.room_width_in / 2, spec.room_depth_in / 2,
                                         spec.room_width_in, spec.room_depth_in, 0.0)])
    return (floor * tile + (1 - floor) * WALL_ALBEDO).astype(np.float32)


def _light(spec: WorldSpec, geo: Geometry, change: str | None = None) -> np.ndarray:
    """Illumination: a gradient across the room times vignetting, times what a lamp,
    a large shadow or the exposure of a scene change adds."""
    x, y = geo.world_grid()
    u = np.clip(x / spec.room_width_in, 0, 1)
    v = np.clip(y / spec.room_depth_in, 0, 1)
    gradient = LIGHT_MIN + LIGHT_SPAN * (0.7 * u + 0.3 * (1 - v))
    cols, rows = np.meshgrid(np.arange(geo.width_px), np.arange(geo.height_px))
    rn2 = ((cols - geo.width_px / 2) ** 2 + (rows - geo.height_px / 2) ** 2) / (
        (geo.width_px / 2) ** 2 + (geo.height_px / 2) ** 2)
    light = gradient * (1 - VIGNETTE * rn2)
    if change == "lamp":
        lx, ly = LAMP_AT_IN[0] * spec.room_width_in, LAMP_AT_IN[1] * spec.room_depth_in
        light = light * (1 + LAMP_GAIN * np.exp(-((x - lx) ** 2 + (y - ly) ** 2) / (2 * LAMP_SPREAD_IN ** 2)))
    elif change == "shadow":
        x0, y0, x1, y1 = (f * d for f, d in zip(SHADOW_AREA, (spec.room_width_in, spec.room_depth_in) * 2))
        area = _coverage(geo, [rect_polygon((x0 + x1) / 2, (y0 + y1) / 2, x1 - x0, y1 - y0, 0.0)])
        area = cv2.GaussianBlur(area, (0, 0), SHADOW_EDGE_IN / INCHES_PER_PIXEL)
        light = light * (1 - (1 - SHADOW_LIGHT) * area)
    elif change == "exposure":
        light = light * EXPOSURE
    return light.astype(np.float32)


def _shadow(geo: Geometry, polygons: Sequence[Sequence[tuple[float, float]]]) -> np.ndarray:
    """Soft shadows: the footprints moved away from the light and blurred."""
    dx, dy = SHADOW_OFFSET_IN
    moved = [[(x + dx, y + dy) for x, y in p] for p in polygons]
    return cv2.GaussianBlur(_coverage(geo, moved), (0, 0), SHADOW_BLUR_IN / INCHES_PER_PIXEL)


def _shading(cover: np.ndarray) -> np.ndarray:
    """An object's top is brightest in its middle and darker by EDGE_SHADING at its
    edge, over about 2 in (a rounded or bevelled top seen from above)."""
    inside = (cover >= 0.5).astype(np.uint8)
    depth = cv2.distanceTransform(inside, cv2.DIST_L2, 3)
    ramp = np.clip(depth * INCHES_PER_PIXEL / 2.0, 0, 1)
    return (1 - EDGE_SHADING * (1 - ramp)).astype(np.float32)


@lru_cache(maxsize=4)
def _distortion_maps(width_px: int, height_px: int) -> tuple[np.ndarray, np.ndarray]:
    """For each pixel of the distorted image, where it comes from in the ideal one."""
    k, d = lens_model(width_px, height_px)
    cols, rows = np.meshgrid(np.arange(width_px, dtype=np.float64), np.arange(height_px, dtype=np.float64))
    pts = np.stack([cols.ravel(), rows.ravel()], axis=1).reshape(-1, 1, 2)
    ideal = cv2.undistortPoints(pts, k, d, None, None, k, (cv2.TERM_CRITERIA_COUNT | cv2.TERM_CRITERIA_EPS, 40, 1e-6)).reshape(height_px, width_px, 2)
    return ideal[..., 0].astype(np.float32), ideal[..., 1].astype(np.float32)
