"""Sensor and actuator imperfections, all drawn from the world's seeded generator.

Sonar values stay within a procedure's *expected error* unless an outlier is drawn,
because the learner merges values that agree within that error (docs/method.md §3): noise
inside the band is what the learner is built to tolerate, outliers and dropouts are
what reselection and backtracking are for.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, fields

import numpy as np


@dataclass(frozen=True)
class NoiseConfig:
    """How imperfect the simulated robot is.

    ``sonar``: Gaussian error with sigma = error/2, clipped to ±error.
    ``outlier_p``: chance a value is off by 2-5x the expected error (binary: flipped).
    ``dropout_p``: chance a value is missing (None).
    ``curved_depth_p``: chance that a round object lying end-on gives a Depth far too
    small (the paper's curved-surface sonar effect).
    ``odometry_frac``: sigma of the end-position error per inch driven.
    ``odometry_heading_deg``: sigma of the heading error after a move without centring.
    ``pixel_sigma``: camera pixel noise sigma (clipped to ±12 levels).
    ``fisheye``: render the overhead image through a fish-eye lens.
    """

    sonar: bool = True
    outlier_p: float = 0.02
    dropout_p: float = 0.01
    curved_depth_p: float = 0.3
    odometry_frac: float = 0.005
    odometry_heading_deg: float = 1.0
    pixel_sigma: float = 4.0
    fisheye: bool = False

    @classmethod
    def off(cls) -> NoiseConfig:
        """Exact values everywhere: for tests and for noise-free training probes."""
        return cls(sonar=False, outlier_p=0.0, dropout_p=0.0, curved_depth_p=0.0,
                   odometry_frac=0.0, odometry_heading_deg=0.0, pixel_sigma=0.0, fisheye=False)

    @classmethod
    def from_mapping(cls, data: Mapping[str, object], where: str) -> NoiseConfig:
        """Build from a world file's ``noise`` table; unknown or mistyped fields fail."""
        known = {f.name: f for f in fields(cls)}
        values: dict[str, object] = {}
        for key, value in data.items():
            if key not in known:
                raise ValueError(f"{where}: unknown field '{key}' (known: {', '.join(known)})")
            if known[key].type == "bool":
                if not isinstance(value, bool):
                    raise ValueError(f"{where}: field '{key}' must be true or false, got {value!r}")
            elif isinstance(value, bool) or not isinstance(value, (int, float)) or value < 0:
                raise ValueError(f"{where}: field '{key}' must be a number >= 0, got {value!r}")
            values[key] = value
        for key in ("outlier_p", "dropout_p", "curved_depth_p"):
            if float(values.get(key, 0.0)) > 1.0:
                raise ValueError(f"{where}: field '{key}' must be a probability <= 1")
        return cls(**values)  # type: ignore[arg-type]


def perturb(ideal: float, error: float, step: float, rng: np.random.Generator,
            noise: NoiseConfig) -> float | None:
    """A measured value for a feature whose exact value is ``ideal``.

    ``step`` is the procedure's quantum (1° or 5° for sweeps; 0 for values reported
    unquantised). Sweep noise is drawn in whole steps so the value stays a multiple of
    the step and within ±error of the exact quantised value.
    """
    if noise.dropout_p and rng.random() < noise.dropout_p:
        return None
    value = ideal
    if noise.outlier_p and rng.random() < noise.outlier_p:
        value += float(rng.choice((-1.0, 1.0))) * float(rng.uniform(2.0, 5.0)) * max(error, step)
    elif noise.sonar and error > 0:
        value += float(np.clip(rng.normal(0.0, error / 2.0), -error, error))
    if step > 0:
        value = step * math.floor(value / step + 0.5)
    return max(0.0, round(value, 3))


def perturb_flag(ideal: bool, rng: np.random.Generator, noise: NoiseConfig) -> float | None:
    """A 0/1 hole feature: dropouts give None, outliers flip it."""
    if noise.dropout_p and rng.random() < noise.dropout_p:
        return None
    flipped = bool(noise.outlier_p) and rng.random() < noise.outlier_p
    return float(ideal != flipped)
