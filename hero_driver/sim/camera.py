"""The overhead camera: a top-down grayscale image of the room with the fixed
intensity bands of docs/conventions.md (:mod:`camera_model.bands`), optionally seen
through a fish-eye lens, with pixel noise and with each object's orientation misjudged
by a few degrees. This is the ``simple`` preset; ``realistic`` (:mod:`hero_driver.sim.render_realistic`) draws
what a real ceiling camera would see instead (docs/camera.md), and ``realistic-CHANGE``
the same room after a scene change (a lamp, a shadow, a new floor, lower exposure:
``render_realistic.SCENE_CHANGES``), to be read through a calibration made on the
plain ``realistic`` room (:func:`before_change`).

A pixel takes a layer's intensity when the layer covers at least half of it (each
layer is drawn SUPERSAMPLE times finer and area-averaged), so a region's pixel count
tracks its true area: the executive compares pixel counts to tell a pushed object
from a knocked-over one, and plain polygon filling overcounts small objects twofold.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from camera_model.bands import BASE, FLOOR, MARKER, OBJECT, PIXEL_NOISE_MAX, WALL
from camera_model.floor_grid import FloorGrid
from camera_model.image import CameraImage
from hero_driver.interface import Pose
from hero_driver.sim import render_realistic
from hero_driver.sim.catalogue import Footprint
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.physics import WALL_IN
from hero_driver.sim.worldfile import WorldSpec, footprint_polygon, rect_polygon

INCHES_PER_PIXEL = 0.8
SHIFT = 4  # fillPoly fractional bits
SUPERSAMPLE = 5
FISHEYE_D = (0.05, 0.01, 0.0, 0.0)  # mild barrel on top of the equidistant projection
FISHEYE_FOCAL_FRACTION = 0.8  # focal length as a fraction of the image width
PRESETS = ("simple", "realistic", *(f"realistic-{change}" for change in render_realistic.SCENE_CHANGES))


def before_change(preset: str) -> str:
    """The preset of the room as it was calibrated: ``realistic`` for a scene change
    (``realistic-lamp``: the room before the lamp went on), else ``preset`` itself."""
    return "realistic" if preset.startswith("realistic-") else preset


@dataclass(frozen=True)
class Frame:
    """How world inches map to pixel coordinates for one room."""

    origin_x_in: float
    origin_y_in: float
    width_px: int
    height_px: int

    @classmethod
    def for_room(cls, spec: WorldSpec) -> Frame:
        return cls(-WALL_IN, spec.room_depth_in + WALL_IN,
                   math.ceil((spec.room_width_in + 2 * WALL_IN) / INCHES_PER_PIXEL),
                   math.ceil((spec.room_depth_in + 2 * WALL_IN) / INCHES_PER_PIXEL))

    def to_pixels(self, points: Sequence[tuple[float, float]], scale: int) -> np.ndarray:
        """Fixed-point (col, row) on a ``scale`` times finer grid, pixel centres at
        integers, for cv2 drawing with SHIFT."""
        pts = np.asarray(points, dtype=np.float64)
        rows, cols = FloorGrid(INCHES_PER_PIXEL, self.origin_x_in, self.origin_y_in).finer(scale).to_pixel(
            pts[:, 0], pts[:, 1])
        return np.round(np.stack([cols, rows], axis=1) * (1 << SHIFT)).astype(np.int32)


class YawErrors:
    """Each object's orientation error in the overhead image, drawn once per object
    and pose: the error comes from how the object looks from the ceiling (its height
    in perspective, its shading), which does not change while it rests where it is."""

    def __init__(self) -> None:
        self._drawn: dict[int, tuple[tuple[float, float, float], float]] = {}

    def error(self, index: int, pose: tuple[float, float, float], noise: NoiseConfig,
              rng: np.random.Generator) -> float:
        """The error in degrees for object ``index`` at ``pose`` (x, y, yaw): the one
        drawn for this pose before, else a fresh N(0, camera_yaw_deg) draw (none at all
        when the sigma is zero, so the random stream is unchanged)."""
        if noise.camera_yaw_deg <= 0:
            return 0.0
        seen = self._drawn.get(index)
        if seen is None or seen[0] != pose:
            seen = (pose, float(rng.normal(0.0, noise.camera_yaw_deg)))
            self._drawn[index] = seen
        return seen[1]


def _paint(img: np.ndarray, frame: Frame, polygons: Sequence[Sequence[tuple[float, float]]], value: int) -> None:
    """Set ``value`` where the polygons cover at least half a pixel. Each polygon is
    filled on its own: one ``fillPoly`` call over several fills by the even-odd rule, so
    where two overlap (a person walking past a cart) the overlap would come out a hole."""
    if not polygons:
        return
    fine = np.zeros((frame.height_px * SUPERSAMPLE, frame.width_px * SUPERSAMPLE), dtype=np.uint8)
    for polygon in polygons:
        cv2.fillPoly(fine, [frame.to_pixels(polygon, SUPERSAMPLE)], 255, lineType=cv2.LINE_8, shift=SHIFT)
    coverage = cv2.resize(fine, (frame.width_px, frame.height_px), interpolation=cv2.INTER_AREA)
    img[coverage >= 128] = value


def _disc(x: float, y: float, r: float) -> list[tuple[float, float]]:
    return [(x + r * math.cos(2 * math.pi * k / 48), y + r * math.sin(2 * math.pi * k / 48)) for k in range(48)]


def fisheye_model(width_px: int, height_px: int) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    """The lens: camera matrix centred on the image and the four fisheye coefficients."""
    f = FISHEYE_FOCAL_FRACTION * width_px
    k = np.array([[f, 0.0, (width_px - 1) / 2], [0.0, f, (height_px - 1) / 2], [0.0, 0.0, 1.0]])
    return k, FISHEYE_D


@lru_cache(maxsize=8)
def _distortion_maps(width_px: int, height_px: int) -> tuple[np.ndarray, np.ndarray]:
    """For each distorted pixel, where it comes from in the ideal image, so that
    ``cv2.fisheye.undistortImage(img, K, D, Knew=K)`` gives the ideal image back."""
    k, d = fisheye_model(width_px, height_px)
    cols, rows = np.meshgrid(np.arange(width_px, dtype=np.float64), np.arange(height_px, dtype=np.float64))
    pts = np.stack([cols.ravel(), rows.ravel()], axis=1).reshape(-1, 1, 2)
    src = cv2.fisheye.undistortPoints(pts, k, np.asarray(d, dtype=np.float64), P=k).reshape(height_px, width_px, 2)
    return src[..., 0].astype(np.float32), src[..., 1].astype(np.float32)


def render(spec: WorldSpec, objects: Sequence[tuple[Footprint, float, float, float]], robot: Pose,
           base_radius_in: float, noise: NoiseConfig, rng: np.random.Generator,
           clock_s: float, preset: str = "simple", movers: Sequence[Sequence[tuple[float, float]]] = ()) -> CameraImage:
    """Draw the room, furniture, the movers (their outlines: people and carts), the
    objects on the floor as (footprint, x, y, yaw) and the robot, then apply the lens
    and pixel noise; ``preset`` names the look.

    A mover is drawn in the walls' band, as furniture is: vision maps it as an
    obstacle and never takes it for an object to grasp. It is drawn beneath the
    objects: a person stepping over an object hides little of it from above, and
    the executive must not read a passer-by as the object taken away."""
    if preset in PRESETS and preset != "simple":
        change = preset.removeprefix("realistic").removeprefix("-") or None
        return render_realistic.render(spec, objects, robot, base_radius_in, rng, clock_s, movers, change)
    if preset != "simple":
        raise ValueError(f"camera preset {preset!r}: expected one of {', '.join(PRESETS)}")
    frame = Frame.for_room(spec)
    img = np.full((frame.height_px, frame.width_px), WALL, dtype=np.uint8)
    _paint(img, frame, [rect_polygon(spec.room_width_in / 2, spec.room_depth_in / 2,
                                     spec.room_width_in, spec.room_depth_in, 0.0)], FLOOR)
    _paint(img, frame, [rect_polygon(f.x_in, f.y_in, f.width_in, f.depth_in, f.yaw_deg) for f in spec.furniture]
           + spec.wall_outlines(), WALL)
    _paint(img, frame, list(movers), WALL)
    _paint(img, frame, [footprint_polygon(fp, x, y, yaw, segments=64) for fp, x, y, yaw in objects], OBJECT)
    _paint(img, frame, [_disc(robot.x_in, robot.y_in, base_radius_in)], BASE)
    h = math.radians(robot.heading_deg)
    ahead = 2.0 * base_radius_in / 3.0
    _paint(img, frame, [_disc(robot.x_in + ahead * math.cos(h), robot.y_in + ahead * math.sin(h),
                              base_radius_in / 4.0)], MARKER)
    camera_matrix, coefficients = None, None
    if noise.fisheye:
        map_x, map_y = _distortion_maps(frame.width_px, frame.height_px)
        img = cv2.remap(img, map_x, map_y, interpolation=cv2.INTER_NEAREST,
                        borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        camera_matrix, coefficients = fisheye_model(frame.width_px, frame.height_px)
    if noise.pixel_sigma > 0:
        jitter = np.clip(np.round(rng.normal(0.0, noise.pixel_sigma, img.shape)), -PIXEL_NOISE_MAX, PIXEL_NOISE_MAX)
        img = np.clip(img.astype(np.int16) + jitter.astype(np.int16), 0, 255).astype(np.uint8)
    return CameraImage(pixels=img, inches_per_pixel=INCHES_PER_PIXEL, origin_x_in=frame.origin_x_in,
                       origin_y_in=frame.origin_y_in, camera_matrix=camera_matrix, fisheye=coefficients,
                       clock_s=clock_s, meta={"world": spec.name})
