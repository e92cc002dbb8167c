"""How good a built map and a localisation are, against the truth.

Map accuracy is the intersection over union of the occupied cells of the built grid and
of a truth grid on the same frame and resolution: 1 when they mark the same cells,
0 when they share none. Localisation error is the distance and heading difference of
each estimated pose from the true one, over time.
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from planner.geometry import Pose, angle_between


def occupied_iou(built: np.ndarray, truth: np.ndarray) -> float:
    """|built ∩ truth| / |built ∪ truth| of two boolean occupancy grids of one shape
    (1.0 when both are empty: they agree). ValueError when the shapes differ."""
    built, truth = np.asarray(built, dtype=bool), np.asarray(truth, dtype=bool)
    if built.shape != truth.shape:
        raise ValueError(f"built and truth grids differ in shape: {built.shape} and {truth.shape}")
    union = np.count_nonzero(built | truth)
    return 1.0 if union == 0 else np.count_nonzero(built & truth) / union


@dataclass(frozen=True)
class LocalisationError:
    """Per-pose errors over time: position (inches) and heading (degrees, unsigned)."""

    stamps_s: tuple[float, ...]
    position_in: tuple[float, ...]
    heading_deg: tuple[float, ...]

    @property
    def final_in(self) -> float:
        return self.position_in[-1]

    @property
    def mean_in(self) -> float:
        return statistics.fmean(self.position_in)

    @property
    def max_in(self) -> float:
        return max(self.position_in)

    @property
    def final_deg(self) -> float:
        return self.heading_deg[-1]

    @property
    def mean_deg(self) -> float:
        return statistics.fmean(self.heading_deg)


def localisation_error(estimated: Sequence[Pose], truth: Sequence[Pose],
                       stamps_s: Sequence[float]) -> LocalisationError:
    """The error of each estimated pose against the true pose at the same time.
    ValueError when the three sequences are empty or of different lengths."""
    if not (len(estimated) == len(truth) == len(stamps_s)) or not estimated:
        raise ValueError(f"estimated, truth and stamps_s must be non-empty and of one length, got "
                         f"{len(estimated)}, {len(truth)} and {len(stamps_s)}")
    position = tuple(math.hypot(e.x_in - t.x_in, e.y_in - t.y_in) for e, t in zip(estimated, truth))
    heading = tuple(angle_between(e.heading_deg, t.heading_deg) for e, t in zip(estimated, truth))
    return LocalisationError(tuple(float(s) for s in stamps_s), position, heading)
