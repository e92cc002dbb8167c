"""Sonar readings: exact feature values turned into measurements, all drawn from the
world's seeded generator.

Sonar values stay within a procedure's *expected error* unless an outlier is drawn,
because the learner merges values that agree within that error (docs/method.md §3): noise
inside the band is what the learner is built to tolerate; outliers, dropouts and the
echo effects of real ultrasonic sensors (specular misses, multipath, cross-talk) are
what reselection and backtracking are for.

An effect whose probability is zero draws nothing from the generator, so turning a new
effect off leaves every other reading of a seeded run unchanged.
"""

from __future__ import annotations

import math

import numpy as np

from hero_driver.sim.noise import NoiseConfig

OUTLIER_ERRORS = (2.0, 5.0)  # an outlier is off by this many expected errors
MULTIPATH_FACTOR = (1.5, 2.5)  # a second bounce reads this many times the true value...
MULTIPATH_MIN_ERRORS = 2.0  # ...and at least this many expected errors over it
CROSSTALK_FACTOR = (0.0, 0.25)  # an early foreign echo reads this fraction of the value
SPECULAR_KEPT = (0.0, 0.5)  # after a specular miss, the share of a size still echoed


def perturb(ideal: float, error: float, step: float, rng: np.random.Generator,
            noise: NoiseConfig) -> float | None:
    """A measured value for a feature whose exact value is ``ideal``.

    ``step`` is the procedure's quantum (1° or 5° for sweeps; 0 for values reported
    unquantised). Sweep noise is drawn in whole steps so the value stays a multiple of
    the step and within ±error of the exact quantised value. At most one gross error
    (outlier, multipath, cross-talk) hits a value; the in-band error only hits values
    that have none.
    """
    if noise.dropout_p and rng.random() < noise.dropout_p:
        return None
    value, band = ideal, max(error, step)
    if noise.outlier_p and rng.random() < noise.outlier_p:
        value += float(rng.choice((-1.0, 1.0))) * float(rng.uniform(*OUTLIER_ERRORS)) * band
    elif noise.multipath_p and rng.random() < noise.multipath_p:
        value = max(ideal * float(rng.uniform(*MULTIPATH_FACTOR)), ideal + MULTIPATH_MIN_ERRORS * band)
    elif noise.crosstalk_p and rng.random() < noise.crosstalk_p:
        value = ideal * float(rng.uniform(*CROSSTALK_FACTOR))
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


def specular_miss(incidence_deg: float | None, rng: np.random.Generator, noise: NoiseConfig) -> bool:
    """Whether a procedure loses the echo of a flat face met ``incidence_deg`` off its
    normal (None: a curved face, which always has a patch square to the beam).

    A smooth flat face reflects sound like a mirror: beyond about half the beam width
    the echo leaves at the mirror angle and never returns to the transducer, so the
    beams that meet the face time out on the far wall instead. One draw per procedure:
    the geometry is the same for all its beams.
    """
    if incidence_deg is None or not noise.specular_p or incidence_deg <= noise.specular_angle_deg:
        return False
    return bool(rng.random() < noise.specular_p)


def specular_value(ideal: float, rng: np.random.Generator) -> float:
    """What a size reads after a specular miss: only the face's near edge, where the
    beam meets it squarely enough, still echoes."""
    return ideal * float(rng.uniform(*SPECULAR_KEPT))
