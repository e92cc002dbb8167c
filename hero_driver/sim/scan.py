"""The onboard range scan: what a planar range sensor on the robot would read, by ray
casting through the pymunk space (the ``scan`` feature, docs/simulator.md "Scans").

Two models, chosen by the robot profile's ``[scanner]`` table
(:class:`robot_profile.ScannerSpec`): a 2-D lidar, one thin ray per beam, and the
HERO's wrist sonar swept in place, whose wide beam answers with the nearest echo
anywhere in its cone (sampled by thin rays :data:`SUB_RAY_DEG` apart). Every beam
starts at the base centre of the robot's *true* pose, as a real sensor on a drifting
base does; the caller stamps the scan with the pose the encoders report.

A ray stops at walls, furniture, objects on the floor at least as tall as the scan
plane and moving obstacles (people and carts, which the rest of the simulator's
queries look past: a range sensor sees legs); never at the robot itself, which is not
in the space. Glass furniture (a world file's ``glass``) lets a lidar's light through
and echoes a sonar's sound.

Noise (:class:`~hero_driver.sim.noise.NoiseConfig`'s ``scan_*`` fields) is drawn from
the generator the caller hands in, which is the scan's own stream, so scanning never
moves any other draw of a seeded run. An effect whose rate is 0 draws nothing.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pymunk

from hero_driver.interface import Pose
from hero_driver.sim.noise import NoiseConfig
from hero_driver.sim.physics import Physics
from robot_profile import SCANNER_DEFAULTS, RobotProfile, ScannerSpec

SUB_RAY_DEG = 1.0  # a wide beam is sampled by thin rays this far apart across its cone
SCAN_STREAM = 0x5CA9  # mixed with the world's seed: the scan's random stream is its own


@dataclass(frozen=True)
class Echo:
    """Where one thin ray first met something that echoes: how far from the origin and
    how far off the surface's normal it arrived (degrees; 0 square on)."""

    range_in: float
    incidence_deg: float


@dataclass(frozen=True)
class Ranges:
    """One scan as the sensor reads it (robot frame): beam angles and ranges (``inf``:
    no echo within ``range_in``)."""

    angles_deg: tuple[float, ...]
    ranges_in: tuple[float, ...]


def scanner_of(profile: RobotProfile) -> ScannerSpec:
    """The profile's scanner; a profile without a ``[scanner]`` table gets the lidar with
    its model's values (the simulator serves scans whatever robot it simulates)."""
    if profile.scanner is not None:
        return profile.scanner
    return ScannerSpec(model="lidar", **SCANNER_DEFAULTS["lidar"])  # type: ignore[arg-type]


def scan_rng(seed: int) -> np.random.Generator:
    """The scan's own random stream for a world seeded with ``seed``."""
    return np.random.default_rng([SCAN_STREAM, seed])


def beam_angles(spec: ScannerSpec) -> tuple[float, ...]:
    """Beam directions in the robot frame: evenly spread, increasing, in [-180, 180)."""
    return tuple(-180.0 + k * spec.step_deg for k in range(spec.beams))


def cast(physics: Physics, origin: tuple[float, float], bearing_deg: float, reach_in: float,
         spec: ScannerSpec) -> Echo | None:
    """The first echo a thin ray from ``origin`` along the world bearing meets within
    ``reach_in``: glass passed when the scanner sees through it, objects lower than the
    scan plane passed under; None when nothing echoes."""
    u = (math.cos(math.radians(bearing_deg)), math.sin(math.radians(bearing_deg)))
    end = (origin[0] + reach_in * u[0], origin[1] + reach_in * u[1])
    hits: list[pymunk.SegmentQueryInfo] = list(physics.space.segment_query(origin, end, 0.0, pymunk.ShapeFilter()))
    hits += [hit for hit in (m.shape.segment_query(origin, end, 0.0) for m in physics.movers.all)
             if hit is not None and hit.shape is not None]
    for hit in sorted(hits, key=lambda h: h.alpha):
        if spec.through_glass and hit.shape in physics.glass:
            continue
        owner = physics.owner(hit.shape)
        if owner is not None and owner.entry.height_in < spec.height_in:
            continue
        cos = -(hit.normal.x * u[0] + hit.normal.y * u[1])
        return Echo(float(hit.alpha) * reach_in, math.degrees(math.acos(max(-1.0, min(1.0, cos)))))
    return None


def _cone(spec: ScannerSpec) -> Sequence[float]:
    """Offsets of the thin rays that sample one beam (one ray for a thin beam)."""
    if spec.beam_deg <= 0:
        return (0.0,)
    rays = max(2, math.floor(spec.beam_deg / SUB_RAY_DEG) + 1)
    return tuple(np.linspace(-spec.beam_deg / 2, spec.beam_deg / 2, rays))


def beam_range(physics: Physics, origin: tuple[float, float], bearing_deg: float, spec: ScannerSpec,
               noise: NoiseConfig, rng: np.random.Generator) -> float:
    """One beam's reading: the nearest echo in its cone, after the scan noise.

    A specular miss (``scan_specular_p``, one draw per beam met beyond ``specular_deg``
    somewhere in it) loses the echoes that came in at a grazing angle; then the nearest
    echo left is the reading, ``inf`` when none is left, or when it is nearer than the
    scanner measures. A dropout (``scan_dropout_p``) loses the beam; a reading gets a
    Gaussian error of sigma ``scan_range_frac`` x range, kept within the range limits."""
    low, high = spec.range_in
    echoes = [e for e in (cast(physics, origin, bearing_deg + off, high, spec) for off in _cone(spec)) if e is not None]
    grazing = any(e.incidence_deg > spec.specular_deg for e in echoes)
    if grazing and noise.scan_specular_p > 0 and rng.random() < noise.scan_specular_p:
        echoes = [e for e in echoes if e.incidence_deg <= spec.specular_deg]
    if not echoes:
        return math.inf
    nearest = min(e.range_in for e in echoes)
    if nearest < low:
        return math.inf
    if noise.scan_dropout_p > 0 and rng.random() < noise.scan_dropout_p:
        return math.inf
    if noise.scan_range_frac > 0:
        nearest += float(rng.normal(0.0, noise.scan_range_frac * nearest))
    return min(high, max(low, nearest))


def take(physics: Physics, true_pose: Pose, spec: ScannerSpec, noise: NoiseConfig,
         rng: np.random.Generator) -> Ranges:
    """A scan from the base centre of ``true_pose``: each beam's reading, in the robot
    frame (angles counter-clockwise from its true heading)."""
    origin = (true_pose.x_in, true_pose.y_in)
    angles = beam_angles(spec)
    ranges = tuple(beam_range(physics, origin, true_pose.heading_deg + a, spec, noise, rng) for a in angles)
    return Ranges(angles, ranges)
